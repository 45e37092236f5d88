#version 460
// Floor: a light grey with grid lines every pc.floor_centre.w metres (anti-aliased with
// screen-space derivatives), fading into the background towards the quad's edge.
#include "render/common.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 0) out vec4 out_colour;

// sRGB colours; FLOOR_RGB, GRID_RGB and BACKGROUND_RGB in src/render/style.rs.
const vec3 FLOOR = vec3(0.80, 0.79, 0.76);
const vec3 GRID = vec3(0.68, 0.68, 0.66);
const vec3 BACKGROUND = vec3(0.95, 0.96, 0.97);

void main() {
    vec2 g = v_world.xz / pc.floor_centre.w;
    vec2 width = fwidth(g);
    vec2 dist = abs(fract(g - 0.5) - 0.5) / max(width, vec2(1e-6));
    float line = 1.0 - clamp(min(dist.x, dist.y), 0.0, 1.0);
    // Fewer visible lines where they would alias (far away or at grazing angles).
    line *= 1.0 - smoothstep(0.15, 0.4, max(width.x, width.y));
    vec3 c = mix(srgb_to_linear(FLOOR), srgb_to_linear(GRID), line);
    float r = length(v_world.xz - pc.floor_centre.xz) / pc.light.w;
    c = mix(c, srgb_to_linear(BACKGROUND), smoothstep(0.6, 1.0, r));
    out_colour = vec4(c, 1.0);
}
