#version 460
// Pass `global_volume`: the second half of one iteration of the global volume constraints
// (physics.md, "One global volume constraint"), after global_volume_sum. Every workgroup
// adds its object's chunk partials (common/global_chunk.glsl: C_g + V0, A, B and the
// contacts' held terms) in the
// same fixed order (strided per invocation, then common/workgroup_sum.glsl), so all of them
// compute the same multiplier (bit-identical reruns),
// then each surface node of its chunk gets F -= lambda grad_k and its floor contact is
// solved again, then (variant `colliders`) its kinematic colliders' contacts. Mirrors
// global_apply in src/backend/cpu/parallel/iterations.rs.
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/global_chunk.glsl"
#include "common/workgroup_sum.glsl"
#include "physics/implicit.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor (specialisation constant 1, as in constraint_apply).
layout(constant_id = 1) const uint FLOOR = 1u;
// The kinematic colliders (specialisation constant 3; 2 is CHUNKS).
layout(constant_id = 3) const uint COLLIDERS = 0u;
// The nodes grabs hold (specialisation constant 4): the rows of one step's GrabTargets.
layout(constant_id = 4) const uint GRABBED = 0u;
#include "physics/contact.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_GLOBAL_OBJECTS) readonly restrict buffer GlobalObjects { GlobalObject objects[]; };
layout(std430, set = 0, binding = B_SURFACE_NODES) readonly restrict buffer SurfaceNodes { uint surface_nodes[]; };
layout(std430, set = 0, binding = B_SURFACE_GRADIENTS) readonly restrict buffer SurfaceGradients { vec4 surface_gradients[]; };
layout(std430, set = 0, binding = B_GLOBAL_STATE) readonly restrict buffer GlobalState { vec4 global_state[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) restrict buffer ColliderContacts { vec4 contacts[]; };
#endif
#include "passes/node_contacts.glsl"

WORKGROUP_SUM_PAIR(workgroup_sum2, float)

void main() {
    uint index = global_object_index();
    GlobalObject object = objects[index];
    // The chunk partials in parallel, then the workgroup sum: a fixed order, so every
    // workgroup of the object gets the same sums (a loop of CHUNKS dependent loads per
    // workgroup took 14 us per iteration on the horse on an H200).
    vec4 partial = vec4(0.0);
    for (uint chunk = gl_LocalInvocationID.x; chunk < CHUNKS; chunk += gl_WorkGroupSize.x) {
        partial += global_state[index * CHUNKS + chunk];
    }
    workgroup_sum2(partial.x, partial.y);
    workgroup_sum2(partial.z, partial.w);
    vec4 sums = partial;
    // sums.w: the floor's held terms (floor_held).
    float lambda = global_multiplier(solve_hard(pc.phase, sums.x - object.rest_volume), sums.y, sums.z, sums.w, pc.dt, pc.epsilon);
    uint k = global_chunk_item();
    if (k >= object.node_count) {
        return;
    }
    uint node = surface_nodes[object.node_first + k];
    vec4 f = forces[node];
    f.xyz -= lambda * surface_gradients[object.node_first + k].xyz;
    forces[node] = node_contacts(node, f);
}
