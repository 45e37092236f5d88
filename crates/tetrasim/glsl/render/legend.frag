#version 460
// The colour bar: the diverging map from -range (bottom) to +range (top) around the neutral
// value, with a dark frame and a tick at the neutral value.
#include "render/common.glsl"

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_colour;

void main() {
    vec2 px = fwidth(v_uv);
    vec2 edge = min(v_uv, 1.0 - v_uv) / px;
    bool frame = min(edge.x, edge.y) < 1.5;
    bool tick = abs(v_uv.y - 0.5) / px.y < 0.75;
    vec3 c = frame || tick ? vec3(0.02) : diverging(2.0 * v_uv.y - 1.0);
    out_colour = vec4(c, 1.0);
}
