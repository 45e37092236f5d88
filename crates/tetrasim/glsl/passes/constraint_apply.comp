#version 460
// Pass `constraint_apply`: ends the sweep of one constraint group. Per node,
// F += omega * weight * sum, where weight is the combine mode's apply weight (1, or
// 1 / d_k for the first edition's averaging; physics.md) and sum the node's constraint
// forces of the group: variant `sums` (atomic Jacobi) reads and clears the per-node sums
// the atomics built; variant `gather` sums the node's contribution slots of group
// pc.group in a fixed order (no atomics, bit-identical reruns); variant `chebyshev` is
// `sums` with the Chebyshev semi-iteration (physics.md; chebyshev_weights in
// src/params.rs), `gather_chebyshev` the same on the gather path (no atomics): F = w (Fhat - F_before) + F_before with the iteration's weight
// w = pc.chebyshev_weight and F_before, the force two iterations back (floor force in w),
// kept per node. Then the node's floor
// contact is solved again against the new F (the floor is a one-sided constraint solved in
// the same iterations; its force is kept in F.w), then, in the `_colliders` variants, the
// kinematic colliders' contacts (physics/contact.glsl; their force kept in ColliderContacts).
// On the gather path LANES invocations share a node (common/lanes.glsl): each sums every
// LANES-th of its slots, and the first finishes the node. A node of a single-group sweep
// sums 14 or more slots (4 lanes), of one of the default's groups about 2 (1 lane).
// @variant sums: SUMS
// @variant gather: GATHER
// @variant chebyshev: SUMS CHEBYSHEV
// @variant gather_chebyshev: GATHER CHEBYSHEV
// @variant sums_colliders: SUMS COLLIDERS_ON
// @variant gather_colliders: GATHER COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/implicit.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor; 0 compiles the contact solve away (specialisation constant 1,
// set by the engine plan).
layout(constant_id = 1) const uint FLOOR = 1u;
// The kinematic colliders (specialisation constant 2, set by the engine plan).
layout(constant_id = 2) const uint COLLIDERS = 0u;
// The nodes grabs hold (specialisation constant 3): the rows of one step's GrabTargets.
layout(constant_id = 3) const uint GRABBED = 0u;
#include "physics/contact.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };
#ifdef GATHER
layout(std430, set = 0, binding = B_CONTRIBUTIONS) readonly restrict buffer Contributions { vec4 contributions[]; };
layout(std430, set = 0, binding = B_NODE_SLOT_OFFSETS) readonly restrict buffer NodeSlotOffsets { uint node_slot_offsets[]; };
layout(std430, set = 0, binding = B_NODE_SLOT_ITEMS) readonly restrict buffer NodeSlotItems { uint node_slot_items[]; };
#else
layout(std430, set = 0, binding = B_CONSTRAINT_SUM) restrict buffer Sum { vec4 sums[]; };
#endif
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) restrict buffer ColliderContacts { vec4 contacts[]; };
#endif
#ifdef CHEBYSHEV
layout(std430, set = 0, binding = B_CHEBYSHEV_BEFORE) restrict buffer ChebyshevBefore { vec4 before[]; };
#endif
#include "passes/node_contacts.glsl"

#ifdef GATHER
#include "common/lanes.glsl"
#endif

void main() {
#ifdef GATHER
    uint i = lane_node();
    uint lane = lane_index();
    uint row = group_node(i);
    vec3 sum = vec3(0.0);
    if (i < pc.node_count) {
        uint end = node_slot_offsets[row + 1u];
        for (uint e = node_slot_offsets[row] + lane; e < end; e += LANES) {
            sum += contributions[node_slot_items[e]].xyz;
        }
    }
    sum = lanes_total(sum);
    if (i >= pc.node_count || lane != 0u) {
        return;
    }
#else
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    uint row = group_node(i);
    vec3 sum = sums[i].xyz;
    sums[i] = vec4(0.0);
#endif
    float weight = pc.omega * combine_apply_weight(pc.combine, degrees[row]);
    vec4 f = forces[i];
#ifdef CHEBYSHEV
    vec4 f0 = f;
#endif
    f.xyz += weight * sum;
#ifdef CHEBYSHEV
    if (pc.chebyshev_weight != 1.0) {
        vec4 b = before[i];
        f = (f - b) * pc.chebyshev_weight + b;
    }
    before[i] = f0;
#endif
    forces[i] = node_contacts(i, f);
}
