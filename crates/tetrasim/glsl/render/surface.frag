#version 460
// Surface shading (`shade` in common.glsl). Colour: flat, or the diverging map of the
// per-node scalar.
#include "render/common.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in float v_scalar;
layout(location = 0) out vec4 out_colour;

// Flat colour (sRGB 0.86, 0.62, 0.42): a warm clay (FLAT_RGB in src/render/style.rs).
const vec3 FLAT = vec3(0.86, 0.62, 0.42);

void main() {
    vec3 n = normalize(v_normal);
    if (!gl_FrontFacing) {
        n = -n;
    }
    vec3 albedo = pc.mode == MODE_FLAT ? srgb_to_linear(FLAT) : scalar_colour(v_scalar);
    out_colour = vec4(shade(albedo, n, v_world), 1.0);
}
