#version 460
// Pass `reactions` (forces out, once per frame after the last step, with per-frame metrics):
// the forces the supports exerted on the bodies in the frame's last step, from what
// `integrate` left in ReactionInputs, summed per workgroup into ReactionPartials (the host
// adds the workgroups' sums in f64): the pins' (what holds each pinned node against every
// other force on it; variant `elastic`: the finite elements' elastic force at the step's
// end, minus the energy's gradient over the node's tets, taken from it as cpu-ref does),
// the floor's (its normal forces, in the pins' w), each collider's (the force of the
// nodes it pushes) and each clamp's (its nodes' share of the pins'). The twin of cpu-ref's
// `reactions_of` (src/backend/cpu/reference/reactions.rs).
// @variant plain:
// @variant elastic: ELASTIC
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"

// The colliders and the clamps (specialisation constants 1 and 2).
layout(constant_id = 1) const uint COLLIDERS = 0u;
layout(constant_id = 2) const uint CLAMPS = 0u;

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_REACTION_INPUTS) readonly restrict buffer ReactionInputs { vec4 inputs[]; };
layout(std430, set = 0, binding = B_REACTION_PARTIALS) writeonly restrict buffer ReactionPartials { vec4 partials[]; };
layout(std430, set = 0, binding = B_NODE_CLAMPS) readonly restrict buffer NodeClamps { uint node_clamps[]; };

#ifdef ELASTIC
#define NODE_TETS
#include "physics/elastic.glsl"
#include "physics/stiffness.glsl"
#include "common/elastic_tets.glsl"
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };

// The elastic force on node i at the positions: minus its tets' energy gradient there.
vec3 elastic_force(uint i) {
    vec3 grad = vec3(0.0);
    vec3 h0 = vec3(0.0);
    vec3 h1 = vec3(0.0);
    for (uint item = node_tet_offsets[i]; item < node_tet_offsets[i + 1u]; ++item) {
        uint t = node_tet_items[item] >> 2u;
        uvec4 tet = tets[t];
        vec4 r0 = elastic_tets[4u * t];
        vec4 r1 = elastic_tets[4u * t + 1u];
        vec4 r2 = elastic_tets[4u * t + 2u];
        vec4 r3 = elastic_tets[4u * t + 3u];
        elastic_corner(positions[tet.x].xyz, positions[tet.y].xyz, positions[tet.z].xyz,
                       positions[tet.w].xyz, r0.xyz, r1.xyz, r2.xyz, r0.w, r1.w, r2.w, r3.x,
                       node_tet_items[item] & 3u, grad, h0, h1);
    }
    return -grad;
}
#endif

WORKGROUP_SUM_PAIR(reaction_sum, vec4)

// Sums `a` and `b` over the workgroup into partials `slot` and `slot + 1` (the latter only
// while below `end`).
void store_pair(vec4 a, vec4 b, uint slot, uint end) {
    reaction_sum(a, b);
    uint row = gl_WorkGroupID.x * (1u + COLLIDERS + CLAMPS);
    if (gl_LocalInvocationID.x == 0u) {
        partials[row + slot] = a;
        if (slot + 1u < end) {
            partials[row + slot + 1u] = b;
        }
    }
    barrier();
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    vec4 holding = vec4(0.0); // the pin's force, w: the floor's normal force
    vec3 pushed = vec3(0.0);
    int pusher = -1;
    int clamp = -1;
    if (i < pc.node_count) {
        vec4 r0 = inputs[2u * i];
        vec4 r1 = inputs[2u * i + 1u];
        if (positions[i].w <= 0.0) {
            holding.xyz = -r0.xyz;
#ifdef ELASTIC
            holding.xyz -= elastic_force(i);
#endif
            clamp = CLAMPS > 0u ? int(node_clamps[i]) - 1 : -1;
        }
        holding.w = r0.w;
        pushed = r1.xyz;
        pusher = int(r1.w + 0.5) - 1;
    }
    // The pins' and the floor's, then each collider's and each clamp's, two at a time.
    uint end = 1u + COLLIDERS + CLAMPS;
    for (uint slot = 0u; slot < end; slot += 2u) {
        vec4 pair[2];
        for (uint k = 0u; k < 2u; ++k) {
            uint s = slot + k;
            pair[k] = vec4(0.0);
            if (s == 0u) {
                pair[k] = holding;
            } else if (s <= COLLIDERS) {
                pair[k] = int(s) - 1 == pusher ? vec4(pushed, 0.0) : vec4(0.0);
            } else if (s < end) {
                pair[k] = int(s - 1u - COLLIDERS) == clamp ? vec4(holding.xyz, 0.0) : vec4(0.0);
            }
        }
        store_pair(pair[0], pair[1], slot, end);
    }
}
