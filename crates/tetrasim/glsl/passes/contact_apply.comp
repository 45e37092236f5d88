#version 460
// Pass `contact_apply`: ends a sweep of the body contacts (the rest of contact_iteration in
// src/backend/cpu/reference.rs). Per node with contacts this step, F += omega * weight *
// sum, the weight the combine mode's apply weight for its contact degree and sum the
// contacts' forces contact_solve added up (cleared here); then every node's floor contact
// is solved again against the new F, then, in variant `colliders`, its kinematic colliders'
// (as constraint_apply does).
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/implicit.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor (specialisation constant 1, set by the engine plan).
layout(constant_id = 1) const uint FLOOR = 1u;
// The kinematic colliders (specialisation constant 2, set by the engine plan).
layout(constant_id = 2) const uint COLLIDERS = 0u;
// The nodes grabs hold (specialisation constant 3): the rows of one step's GrabTargets.
layout(constant_id = 3) const uint GRABBED = 0u;
#include "physics/contact.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_CONTACT_SUMS) restrict buffer ContactSums { vec4 sums[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) restrict buffer ColliderContacts { vec4 contacts[]; };
#endif
#include "passes/node_contacts.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    vec4 f = forces[i];
    vec4 summed = sums[i];
    uint d = floatBitsToUint(summed.w);
    if (d > 0u) {
        vec3 sum = summed.xyz;
        sums[i].xyz = vec3(0.0);
        f.xyz += sum * (combine_apply_weight(pc.combine, float(d)) * pc.omega);
    }
    forces[i] = node_contacts(i, f);
}
