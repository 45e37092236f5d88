#version 460
// The colliders: one neutral steel grey, lit like the object (`shade` in common.glsl).
#include "render/common.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 0) out vec4 out_colour;

// sRGB 0.47, 0.52, 0.58: a cool steel grey, apart from the object's colours (COLLIDER_RGB in
// src/render/style.rs).
const vec3 STEEL = vec3(0.47, 0.52, 0.58);

void main() {
    vec3 n = normalize(v_normal);
    // Tessellated normals point out of the solid; a plane is also seen from below.
    if (dot(n, pc.eye.xyz - v_world) < 0.0) {
        n = -n;
    }
    out_colour = vec4(shade(srgb_to_linear(STEEL), n, v_world), 1.0);
}
