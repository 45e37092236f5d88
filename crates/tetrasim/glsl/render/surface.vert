#version 460
// The object's surface: vertices pulled from the simulation's position buffer by the index
// buffer's node indices; normal and colour scalar from attrs.comp.
#include "render/common.glsl"

layout(std430, set = 0, binding = R_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = R_ATTRS) readonly restrict buffer Attrs { vec4 attrs[]; };

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out float v_scalar;

void main() {
    vec3 world = positions[gl_VertexIndex].xyz;
    vec4 a = attrs[gl_VertexIndex];
    v_world = world;
    v_normal = a.xyz;
    v_scalar = a.w;
    gl_Position = pc.view_proj * vec4(world, 1.0);
}
