#version 460
// Pass `elastic_contacts` (finite elements, per node, at a step's first iteration;
// docs/GPU.md, "Finite elements on the GPU"): the node's floor and, in the `colliders`
// variant, its kinematic colliders solved against the step's forces so far
// (passes/node_contacts.glsl), as cpu-ref's `contact_solve` does before it linearises. A
// later linearisation follows `constraint_apply`, which has just solved them.
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/implicit.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor; the colliders and the grabbed nodes (specialisation
// constants 1 to 3, as in `constraint_apply`).
layout(constant_id = 1) const uint FLOOR = 1u;
layout(constant_id = 2) const uint COLLIDERS = 0u;
layout(constant_id = 3) const uint GRABBED = 0u;
#include "physics/contact.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) restrict buffer ColliderContacts { vec4 contacts[]; };
#endif
#include "passes/node_contacts.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    forces[i] = node_contacts(i, forces[i]);
}
