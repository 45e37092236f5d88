#version 460
// Pass `contact_measure`: the frame's contact measures (the run record's `collider_nodes`,
// `body_contacts`, `deepest_m`; ContactSample in src/backend/mod.rs, as cpu-ref's volume()
// takes them), once per frame after the last step, into the status's contact words, which
// the frame copies to the host with the divergence status (the frame zeroes them first).
// One invocation per node:
//   variant `colliders`: a node whose w flag integrate left in ColliderContacts (a collider
//   pushed it in the step's last solve) counts 1; its depth inside each collider in reach
//   at the colliders' poses at the frame's end (the last step's end poses: the push
//   constants of the frame's last step) is -phi (contact::deepest);
//   variant `bodies`: surface node s (< the records' count) with a contact whose multiplier
//   pushes after the last step (lambda < 0) counts 1; its depth behind the triangle is
//   -n . (x_p - sum_k b_k x_k).
// Counts go in with atomicAdd, the deepest positive depth with atomicMax on its bits (for
// non-negative floats their order is the numbers'); only nodes in contact or inside touch
// the status.
// @variant colliders: COLLIDERS_ON
// @variant bodies: BODIES_ON
// @variant colliders_bodies: COLLIDERS_ON BODIES_ON
#include "common/version.glsl"
#include "common/bindings.glsl"

// The kinematic colliders (specialisation constant 1, set by the engine plan).
layout(constant_id = 1) const uint COLLIDERS = 0u;
// contact.glsl's grab attachment is not solved here.
const uint GRABBED = 0u;
#include "physics/contact.glsl"
#include "physics/body_record.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) readonly restrict buffer ColliderContacts { vec4 collider_contacts[]; };
#endif
#ifdef BODIES_ON
layout(std430, set = 0, binding = B_CONTACTS) readonly restrict buffer Contacts { BodyContactRecord records[]; };
#endif
layout(std430, set = 0, binding = B_STATUS) restrict buffer Status {
    uint divergence[4]; // check.comp's words
    uint collider_nodes;
    uint body_contacts;
    uint deepest;       // [m], f32 bits
    uint pad;
} status;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    vec3 x = positions[i].xyz;
    float deepest = 0.0;
#ifdef COLLIDERS_ON
    if (collider_contacts[i].w > 0.0) {
        atomicAdd(status.collider_nodes, 1u);
    }
    for (uint k = 0u; k < COLLIDERS; ++k) {
        // ColliderAt::may_touch_at_start against the pose at the frame's end.
        vec3 away = x - poses[pc.collider_first + k].end_position.xyz;
        float reach = colliders[k].reach;
        if (dot(away, away) <= reach * reach) {
            vec3 normal;
            deepest = max(deepest, -collider_distance(k, x, normal));
        }
    }
#endif
#ifdef BODIES_ON
    if (i < records.length()) {
        BodyContactRecord rec = records[i];
        if (rec.nodes.x != NO_CONTACT && rec.bary_lambda.w < 0.0) {
            atomicAdd(status.body_contacts, 1u);
            float depth = -contact_separation(rec, positions[rec.nodes.x].xyz,
                positions[rec.nodes.y].xyz, positions[rec.nodes.z].xyz, positions[rec.nodes.w].xyz);
            deepest = max(deepest, depth);
        }
    }
#endif
    if (deepest > 0.0) {
        atomicMax(status.deepest, floatBitsToUint(deepest));
    }
}
