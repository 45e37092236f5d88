#version 460
// Pass `elastic` (finite elements, per node, every conjugate-gradient iteration; docs/GPU.md,
// "Finite elements on the GPU"): a conjugate-gradient step of ALPHA along P (unless the solve is done): the
// displacement DX grows by alpha p, the residual R loses alpha q, and the node's force
// increment for the iteration goes to SUM and to its contribution slot, which
// `constraint_apply#gather` adds to its force (its inertia's and its contact's, the latter cut
// to what the contacts push it with now: `held_increment`). A checked step that kept the
// linearisation (no RELINEARISE from `elastic_backtrack`) sets it where a free node
// no contact holds ends inside the floor. `elastic_prolong` preconditions the new residual.
// The twin of the update in cpu-ref's `conjugate_gradients`
// (src/backend/cpu/reference/elastic.rs). Variant `colliders`: also where it ends within a
// collider's contact thickness (collider::enters_unheld).
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

#ifdef COLLIDERS_ON
// The colliders and the grabbed nodes (specialisation constants 2 and 3).
layout(constant_id = 2) const uint COLLIDERS = 0u;
layout(constant_id = 3) const uint GRABBED = 0u;
#include "physics/contact.glsl"
#endif

// Whether a node ending at x is inside the floor or, with colliders, within one's contact
// thickness (collider::enters_unheld's places).
bool inside_a_contact(vec3 x) {
    if (pc.floor_on != 0u && x.y < 0.0) {
        return true;
    }
#ifdef COLLIDERS_ON
    for (uint k = 0u; k < COLLIDERS; ++k) {
        vec3 away = x - poses[pc.collider_first + k].end_position.xyz;
        float reach = colliders[k].reach;
        vec3 normal;
        if (dot(away, away) <= reach * reach && collider_distance(k, x, normal) < colliders[k].thickness) {
            return true;
        }
    }
#endif
    return false;
}

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) restrict buffer ElasticNodesBuffer { vec4 nodes[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) readonly restrict buffer ColliderContacts { vec4 collider_contacts[]; };
#endif
layout(std430, set = 0, binding = B_CONTRIBUTIONS) writeonly restrict buffer Contributions { vec4 contributions[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
    if (i >= n) {
        return;
    }
    vec3 sum = vec3(0.0);
    if (state_u[ELASTIC_STATE_DONE] == 0u) {
        float alpha = state[ELASTIC_STATE_ALPHA];
        vec3 p = nodes[ELASTIC_PLANE_P * n + i].xyz;
        vec3 h = nodes[ELASTIC_PLANE_HELD * n + i].xyz;
        vec3 d = p * alpha;
        vec3 dx = nodes[ELASTIC_PLANE_DX * n + i].xyz + d;
        nodes[ELASTIC_PLANE_DX * n + i] = vec4(dx, 0.0);
        // A checked step kept the linearisation: a free node no contact holds that ends
        // inside a contact starts a new Newton step (collider::enters_unheld).
        bool kept = state_u[ELASTIC_STATE_CHECK] != 0u && state_u[ELASTIC_STATE_RELINEARISE] == 0u;
        vec3 end = nodes[ELASTIC_PLANE_AT * n + i].xyz + dx;
        if (kept && positions[i].w > 0.0 && h == vec3(0.0) && inside_a_contact(end)) {
            atomicOr(state_u[ELASTIC_STATE_RELINEARISE], 1u);
        }
        // What the contacts push it with now: the floor's force (F.w) and the colliders'.
        vec3 pushed = vec3(0.0, forces[i].w, 0.0);
#ifdef COLLIDERS_ON
        pushed += collider_contacts[i].xyz;
#endif
        sum = held_increment(node_increment(velocities[i].w, pc.dt, h, p, alpha), h, d, pushed);
        vec3 r = nodes[ELASTIC_PLANE_R * n + i].xyz - nodes[ELASTIC_PLANE_Q * n + i].xyz * alpha;
        nodes[ELASTIC_PLANE_R * n + i] = vec4(r, 0.0);
    }
    nodes[ELASTIC_PLANE_SUM * n + i] = vec4(sum, 0.0);
    contributions[pc.slot_first + i] = vec4(sum, 0.0);
}
