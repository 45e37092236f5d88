// Shared by every render shader: descriptor bindings (set 0), the push-constant block, the
// light and the colour map. The host side is src/render/layout.rs (`binding::*`,
// `RenderPush`); a test there checks these numbers and offsets in the compiled SPIR-V.
#ifndef RENDER_COMMON_GLSL
#define RENDER_COMMON_GLSL

// Per node, vec4: xyz = position [m] (the simulation's own buffer, read in place).
#define R_POSITIONS 0
// Per node, vec4: xyz = unit normal, w = the colour-mode scalar (written by attrs.comp).
#define R_ATTRS 1
// The nodes that lie on the surface (attrs.comp runs once per entry).
#define R_SURFACE_NODES 2
// Node -> surface triangles CSR (N + 1 offsets, then triangle indices).
#define R_FACE_OFFSETS 3
#define R_FACE_ITEMS 4
// Surface triangles, 3 node indices each (also bound as the index buffer).
#define R_TRIANGLES 5
// Node -> tets CSR.
#define R_TET_OFFSETS 6
#define R_TET_ITEMS 7
// Per tet: uvec4 node indices; per tet: rest volume [m^3].
#define R_TETS 8
#define R_REST_VOLUMES 9
// Node -> springs CSR; per spring: uvec4 (a, b, rest length bits, unused).
#define R_SPRING_OFFSETS 10
#define R_SPRING_ITEMS 11
#define R_SPRINGS 12
// Collider triangles in their local frames, 2 vec4 per vertex: position (w = the collider's
// index) and unit normal (uploaded once); per collider, its local -> world mat4 at the
// picture's time (rewritten before each picture).
#define R_COLLIDER_VERTICES 13
#define R_COLLIDER_POSES 14

// Colour modes (`ColourMode` in src/render/mod.rs).
#define MODE_FLAT 0u
#define MODE_VOLUME 1u
#define MODE_STRAIN 2u

// 128 bytes, the guaranteed push-constant size.
layout(push_constant, std430) uniform RenderPush {
    mat4 view_proj;     // world [m] -> clip
    vec4 eye;           // xyz: camera position [m]; w: contact-shading height [m]
    vec4 light;         // xyz: unit direction towards the light; w: floor half extent [m]
    vec4 floor_centre;  // xz: centre of the floor quad [m]; y: shadow darkness in [0, 1];
                        // w: grid spacing [m]
    uvec2 legend;       // legend bar rectangle as fractions of the image (x right, y down),
                        // unorm16 pairs: (x0, y0), (x1, y1)
    float range;        // colour map: the scalar's half range around its neutral value
    uint mode;          // MODE_*
} pc;

// The legend bar's corners in normalised device coordinates: x0, y0 (top), x1, y1.
vec4 legend_ndc() {
    return 2.0 * vec4(unpackUnorm2x16(pc.legend.x), unpackUnorm2x16(pc.legend.y)) - 1.0;
}

vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

// Diverging map (blue - light grey - red, after Moreland's cool-warm) of t in [-1, 1],
// as linear RGB. Blue: less than neutral (volume lost, spring compressed); red: more.
vec3 diverging(float t) {
    t = clamp(t, -1.0, 1.0);
    vec3 cold = srgb_to_linear(vec3(0.23, 0.30, 0.75));
    vec3 mid = srgb_to_linear(vec3(0.87, 0.87, 0.87));
    vec3 warm = srgb_to_linear(vec3(0.71, 0.02, 0.15));
    return t < 0.0 ? mix(mid, cold, -t) : mix(mid, warm, t);
}

// The colour of a scalar of the current mode: V/V0 is neutral at 1, strain at 0.
vec3 scalar_colour(float s) {
    float neutral = pc.mode == MODE_VOLUME ? 1.0 : 0.0;
    return diverging((s - neutral) / max(pc.range, 1e-6));
}

// Lit shading of every solid the render draws (the object's surface, the colliders):
// hemisphere ambient + Lambert + a little Blinn-Phong specular, darkened near the floor (a
// cheap contact / ambient-occlusion cue). `albedo` is linear RGB; `n` a unit normal facing
// the viewer.
vec3 shade(vec3 albedo, vec3 n, vec3 world) {
    vec3 to_eye = normalize(pc.eye.xyz - world);
    vec3 l = pc.light.xyz;
    float diffuse = max(dot(n, l), 0.0);
    vec3 sky = vec3(0.42, 0.45, 0.52);
    vec3 ground = vec3(0.18, 0.17, 0.16);
    vec3 ambient = mix(ground, sky, 0.5 + 0.5 * n.y);
    float spec = pow(max(dot(n, normalize(l + to_eye)), 0.0), 48.0) * step(0.0, dot(n, l));
    float contact = mix(0.45, 1.0, smoothstep(0.0, pc.eye.w, world.y));
    return albedo * (ambient + 0.85 * diffuse) * contact + 0.18 * spec;
}

#endif
