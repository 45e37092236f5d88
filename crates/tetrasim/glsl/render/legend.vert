#version 460
// The colour bar of the legend: a quad over the legend rectangle, v_uv in [0, 1]^2, v = 0 at the
// bottom (the low end of the map). The labels are drawn on the CPU (src/render/legend.rs).
#include "render/common.glsl"

layout(location = 0) out vec2 v_uv;

void main() {
    const vec2 corners[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
    vec2 uv = corners[gl_VertexIndex];
    v_uv = uv;
    // NDC y grows downwards in Vulkan: y0 is the bar's top.
    vec4 r = legend_ndc();
    gl_Position = vec4(mix(r.x, r.z, uv.x), mix(r.w, r.y, uv.y), 0.0, 1.0);
}
