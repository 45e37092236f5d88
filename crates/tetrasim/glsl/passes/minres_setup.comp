#version 460
// Pass `minres_setup`: MINRES's first pass (common/minres.glsl), one invocation per node:
// its mobility in the solve (Mobility::held_by in src/physics/minres.rs), plane 1 of
// MinresNodeVectors: the direction a contact holds it along (the floor's +Y when the floor
// pushes it, F.w > 0; else a collider's push, in the `colliders` variant) and its inverse
// mass (0 when a grab holds it).
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"
#include "physics/implicit.glsl"

// The nodes grabs hold (specialisation constant 3; 0: GrabNodes is not read).
layout(constant_id = 3) const uint GRABBED = 0u;

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) readonly restrict buffer ColliderContacts { vec4 contacts[]; };
layout(std430, set = 0, binding = B_GRAB_NODES) readonly restrict buffer GrabNodes { uint grab_nodes[]; };
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    float inv_mass = positions[i].w;
#ifdef COLLIDERS_ON
    vec3 push = contacts[i].xyz;
    if (GRABBED > 0u && grab_nodes[i] != 0xffffffffu) {
        inv_mass = 0.0;
    }
#else
    vec3 push = vec3(0.0);
#endif
    node_vectors[pc.node_count + i] = vec4(held_direction(forces[i].w > 0.0, push), inv_mass);
}
