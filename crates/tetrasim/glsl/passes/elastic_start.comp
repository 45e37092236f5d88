#version 460
// Pass `elastic_start` (finite elements, per node, at each linearisation; docs/GPU.md,
// "Finite elements on the GPU"), after `elastic_contacts`: where node i ends the step at
// the forces so far, AT = x + dt (v + dt w F), its elastic force so far PHI = F - m g - the floor's normal force
// (F.w) - the colliders' force, Y = AT - w dt^2 PHI (where inertia and gravity alone take
// it), DX = 0, and the direction a contact holds it along,
// NORMAL: the floor's +Y where the floor pushes it or it ends within HELD_GAP of it in
// strain (its reach in ELASTIC_PLANE_NODE), else a collider's push's (NORMAL.w: 1 where the
// floor or a collider pushes it, which `elastic_rows` makes `touching`). The twin of the
// start of a linearisation in cpu-ref's `conjugate_gradients` (end_position,
// StepForces::elastic, collider::held_normal). Variant `colliders`: the colliders' force so
// far (ColliderContacts) is not elastic, pushes the node and holds it along its direction,
// and where none pushes it, the first collider the node ends within HELD_GAP of in strain
// (beyond the collider's contact thickness) holds it along its normal.
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/implicit.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

#ifdef COLLIDERS_ON
// The colliders and the grabbed nodes (specialisation constants 2 and 3).
layout(constant_id = 2) const uint COLLIDERS = 0u;
layout(constant_id = 3) const uint GRABBED = 0u;
#include "physics/contact.glsl"
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) readonly restrict buffer ColliderContacts { vec4 collider_contacts[]; };

// The outward normal of the first collider whose surface x lies within `gap` of (its
// contact thickness included) at the step's end, or zero (collider::resting_on).
vec3 resting_on(vec3 x, float gap) {
    for (uint k = 0u; k < COLLIDERS; ++k) {
        vec3 away = x - poses[pc.collider_first + k].end_position.xyz;
        float reach = colliders[k].reach;
        if (dot(away, away) > reach * reach) {
            continue;
        }
        vec3 normal;
        if (collider_distance(k, x, normal) - colliders[k].thickness <= gap) {
            return normal;
        }
    }
    return vec3(0.0);
}
#endif

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) restrict buffer ElasticNodesBuffer { vec4 nodes[]; };

void main() {
    if (!elastic_linearises()) {
        return;
    }
    uint i = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
    if (i >= n) {
        return;
    }
    vec4 x = positions[i];
    vec4 v = velocities[i];
    vec4 f = forces[i];
#ifdef COLLIDERS_ON
    vec3 contact = collider_contacts[i].xyz;
#else
    vec3 contact = vec3(0.0);
#endif
    vec3 phi = f.xyz - pc.gravity * v.w - vec3(0.0, f.w, 0.0) - contact;
    float w = x.w;
    vec3 at = x.xyz + (v.xyz + f.xyz * (w * pc.dt)) * pc.dt;
    bool floor_pushes = pc.floor_on != 0u && f.w > 0.0;
    float reach = nodes[ELASTIC_PLANE_NODE * n + i].x;
    bool on_floor = pc.floor_on != 0u && (floor_pushes || at.y * reach <= HELD_GAP);
    nodes[ELASTIC_PLANE_AT * n + i] = vec4(at, 0.0);
    nodes[ELASTIC_PLANE_Y * n + i] = vec4(at - phi * (w * pc.dt * pc.dt), 0.0);
    nodes[ELASTIC_PLANE_DX * n + i] = vec4(0.0);
    nodes[ELASTIC_PLANE_PHI * n + i] = vec4(phi, 0.0);
    bool touching = floor_pushes || contact != vec3(0.0);
    vec3 collider = contact;
#ifdef COLLIDERS_ON
    if (contact == vec3(0.0) && reach > 0.0) {
        collider = resting_on(at, HELD_GAP / reach);
    }
#endif
    nodes[ELASTIC_PLANE_NORMAL * n + i] = vec4(held_direction(on_floor, collider), touching ? 1.0 : 0.0);
}
