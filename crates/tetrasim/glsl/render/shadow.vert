#version 460
// The object's hard shadow: its surface projected along the light onto just above the floor
// (planar projection). Drawn blended with a stencil test so overlapping triangles darken once.
#include "render/common.glsl"

layout(std430, set = 0, binding = R_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };

void main() {
    vec3 p = positions[gl_VertexIndex].xyz;
    vec3 l = pc.light.xyz;
    vec3 onto = p - l * (max(p.y, 0.0) / max(l.y, 1e-3));
    onto.y = 1e-4 * pc.light.w;
    gl_Position = pc.view_proj * vec4(onto, 1.0);
}
