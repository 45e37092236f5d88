#version 460
// The floor y = 0: one quad of half extent pc.light.w around pc.floor_centre, from
// gl_VertexIndex alone (no vertex buffer).
#include "render/common.glsl"

layout(location = 0) out vec3 v_world;

void main() {
    const vec2 corners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    vec2 c = corners[gl_VertexIndex] * pc.light.w;
    vec3 world = vec3(pc.floor_centre.x + c.x, 0.0, pc.floor_centre.z + c.y);
    v_world = world;
    gl_Position = pc.view_proj * vec4(world, 1.0);
}
