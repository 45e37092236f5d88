#version 460
// Pass `anderson_mix`: the second half of Anderson acceleration (src/physics/anderson.rs),
// after anderson_sum, from iteration 1 on. Every workgroup adds the CHUNKS rows of
// AndersonSums in the same fixed order (strided per invocation, then the workgroup sum of
// common/workgroup_sum.glsl, eight terms at a time where global_volume sums two), so all of
// them solve the same weights gamma (invocation 0,
// anderson_weights); then each node's next input x = g - sum_j gamma_j dg_j is kept and
// becomes its forces, whose floor and colliders' contacts are solved again
// (passes/node_contacts.glsl); the compliant multipliers are mixed with the
// same weights (a grid-stride loop). Mirrors src/backend/cpu/parallel/anderson.rs.
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "physics/anderson.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor (specialisation constant 1, as in constraint_apply).
layout(constant_id = 1) const uint FLOOR = 1u;
// The workgroups of anderson_sum, its rows of AndersonSums (specialisation constant 2).
layout(constant_id = 2) const uint CHUNKS = 1u;
// The kinematic colliders (specialisation constant 3).
layout(constant_id = 3) const uint COLLIDERS = 0u;
// The nodes grabs hold (specialisation constant 4): the rows of one step's GrabTargets.
layout(constant_id = 4) const uint GRABBED = 0u;
#include "physics/contact.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_ANDERSON_HISTORY) restrict buffer AndersonHistory { vec4 history[]; };
layout(std430, set = 0, binding = B_ANDERSON_SUMS) readonly restrict buffer AndersonSums { float sums[]; };
layout(std430, set = 0, binding = B_SPRING_MULTIPLIERS) restrict buffer SpringMultipliers { float spring_multipliers[]; };
layout(std430, set = 0, binding = B_VOLUME_MULTIPLIERS) restrict buffer VolumeMultipliers { float volume_multipliers[]; };
layout(std430, set = 0, binding = B_ANDERSON_MULTIPLIERS) readonly restrict buffer AndersonMultipliers { float lambda_history[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) restrict buffer ColliderContacts { vec4 contacts[]; };
#endif
#include "passes/node_contacts.glsl"

WORKGROUP_SUM_PAIR(workgroup_sum8, vec4)

shared float s_gamma[ANDERSON_MAX_MEMORY];

void main() {
    if (pc.iteration == 0u) {
        return;
    }
    uint k = anderson_columns(pc.iteration);
    uint l = gl_LocalInvocationID.x;
    if (k > 0u) {
        uint count = gram_terms(k);
        float partial[ANDERSON_MAX_TERMS];
        for (uint t = 0u; t < count; ++t) {
            partial[t] = 0.0;
        }
        for (uint chunk = l; chunk < CHUNKS; chunk += gl_WorkGroupSize.x) {
            for (uint t = 0u; t < count; ++t) {
                partial[t] += sums[chunk * ANDERSON_MAX_TERMS + t];
            }
        }
        float total[ANDERSON_MAX_TERMS];
        for (uint t = 0u; t < count; t += 8u) {
            vec4 a;
            vec4 b;
            for (uint j = 0u; j < 4u; ++j) {
                a[j] = t + j < count ? partial[t + j] : 0.0;
                b[j] = t + 4u + j < count ? partial[t + 4u + j] : 0.0;
            }
            workgroup_sum8(a, b);
            for (uint j = 0u; j < 4u; ++j) {
                if (t + j < count) {
                    total[t + j] = a[j];
                }
                if (t + 4u + j < count) {
                    total[t + 4u + j] = b[j];
                }
            }
        }
        if (l == 0u) {
            float gamma[ANDERSON_MAX_MEMORY];
            anderson_weights(total, k, gamma);
            for (uint j = 0u; j < ANDERSON_MAX_MEMORY; ++j) {
                s_gamma[j] = gamma[j];
            }
        }
        barrier();
    }
    uint total = MIX_SPRINGS + MIX_TETS;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint c = gl_GlobalInvocationID.x; c < total && k > 0u; c += stride) {
        float mixed = c < MIX_SPRINGS ? spring_multipliers[c] : volume_multipliers[c - MIX_SPRINGS];
        for (uint j = 0u; j < k; ++j) {
            mixed -= s_gamma[j] * lambda_history[(1u + j) * total + c];
        }
        if (c < MIX_SPRINGS) {
            spring_multipliers[c] = mixed;
        } else {
            volume_multipliers[c - MIX_SPRINGS] = mixed;
        }
    }
    uint i = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
    if (i >= n) {
        return;
    }
    vec3 next = history[2u * n + i].xyz;
    for (uint j = 0u; j < k; ++j) {
        next -= s_gamma[j] * history[(3u + MEMORY + j) * n + i].xyz;
    }
    history[i] = vec4(next, 0.0);
    vec4 force = forces[i];
    force.xyz = next;
    forces[i] = node_contacts(i, force);
}
