#version 460
// Surface shading: hemisphere ambient + Lambert + a little Blinn-Phong specular, darkened near
// the floor (a cheap contact / ambient-occlusion cue). Colour: flat, or the diverging map of
// the per-node scalar.
#include "render/common.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in float v_scalar;
layout(location = 0) out vec4 out_colour;

// Flat colour (sRGB 0.86, 0.62, 0.42): a warm clay (FLAT_RGB in src/render/style.rs).
const vec3 FLAT = vec3(0.86, 0.62, 0.42);

void main() {
    vec3 n = normalize(v_normal);
    vec3 to_eye = normalize(pc.eye.xyz - v_world);
    if (!gl_FrontFacing) {
        n = -n;
    }
    vec3 albedo = pc.mode == MODE_FLAT ? srgb_to_linear(FLAT) : scalar_colour(v_scalar);
    vec3 l = pc.light.xyz;
    float diffuse = max(dot(n, l), 0.0);
    vec3 sky = vec3(0.42, 0.45, 0.52);
    vec3 ground = vec3(0.18, 0.17, 0.16);
    vec3 ambient = mix(ground, sky, 0.5 + 0.5 * n.y);
    float spec = pow(max(dot(n, normalize(l + to_eye)), 0.0), 48.0) * step(0.0, dot(n, l));
    float contact = mix(0.45, 1.0, smoothstep(0.0, pc.eye.w, v_world.y));
    vec3 c = albedo * (ambient + 0.85 * diffuse) * contact + 0.18 * spec;
    out_colour = vec4(c, 1.0);
}
