#version 460
// Pass `minres_forces`: MINRES's last pass (common/minres.glsl), LANES invocations per node
// (common/lanes.glsl): the force the increments take off the node, its share of J^T x less
// its part along the direction a contact holds (Minres::node_force: that part is the
// contact's to decide), then the node's floor and, in the `colliders` variant, its
// colliders solved again.
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"
#include "common/lanes.glsl"
#include "physics/implicit.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor (specialisation constant 1, as in constraint_apply).
layout(constant_id = 1) const uint FLOOR = 1u;
// The kinematic colliders (specialisation constant 2).
layout(constant_id = 2) const uint COLLIDERS = 0u;
// The nodes grabs hold (specialisation constant 3): the rows of one step's GrabTargets.
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
    uint i = lane_node();
    vec3 force = i < pc.node_count ? transpose_sum(i, P_X, lane_index(), LANES) : vec3(0.0);
    force = lanes_total(force);
    if (i >= pc.node_count || lane_index() != 0u) {
        return;
    }
    vec3 held = node_vectors[pc.node_count + i].xyz;
    vec4 f = forces[i];
    f.xyz -= force - held * dot(held, force);
    forces[i] = node_contacts(i, f);
}
