#version 460
// Pass `anderson_sum`: the first half of Anderson acceleration (src/physics/anderson.rs),
// after each iteration's other stages. Per node: its forces g = F (the floor's and
// colliders' included), the residual f = g - x, the history column of the iteration
// df = f - f_last, dg = g - g_last, and f, g kept (AndersonHistory, planes of a vec4 per
// node: x, f, g, then MEMORY columns of df, then of dg); in iteration 0 only x = g. Then
// every workgroup (a chunk of nodes) sums the products of the normal equations,
// df_i . df_j and df_i . f, eight at a time in shared memory in a fixed order into its row of
// AndersonSums. The compliant multipliers (SpringMultipliers, VolumeMultipliers) keep
// their last values and history column likewise, in AndersonMultipliers (a grid-stride
// loop). Mirrors src/backend/cpu/parallel/anderson.rs.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "physics/anderson.glsl"

WORKGROUP_SUM_PAIR(workgroup_sum8, vec4)

layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_ANDERSON_HISTORY) restrict buffer AndersonHistory { vec4 history[]; };
layout(std430, set = 0, binding = B_ANDERSON_SUMS) writeonly restrict buffer AndersonSums { float sums[]; };
layout(std430, set = 0, binding = B_SPRING_MULTIPLIERS) readonly restrict buffer SpringMultipliers { float spring_multipliers[]; };
layout(std430, set = 0, binding = B_VOLUME_MULTIPLIERS) readonly restrict buffer VolumeMultipliers { float volume_multipliers[]; };
layout(std430, set = 0, binding = B_ANDERSON_MULTIPLIERS) restrict buffer AndersonMultipliers { float lambda_history[]; };

// The multipliers' last values and this iteration's history column.
void keep_multipliers(int slot) {
    uint total = MIX_SPRINGS + MIX_TETS;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint c = gl_GlobalInvocationID.x; c < total; c += stride) {
        float now = c < MIX_SPRINGS ? spring_multipliers[c] : volume_multipliers[c - MIX_SPRINGS];
        if (slot >= 0) {
            lambda_history[(1u + uint(slot)) * total + c] = now - lambda_history[c];
        }
        lambda_history[c] = now;
    }
}

void main() {
    keep_multipliers(anderson_slot(pc.iteration));
    uint i = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
    bool live = i < n;
    vec3 g = vec3(0.0);
    if (live) {
        g = forces[i].xyz;
    }
    if (pc.iteration == 0u) {
        if (live) {
            history[i] = vec4(g, 0.0);
        }
        return;
    }
    int slot = anderson_slot(pc.iteration);
    uint k = anderson_columns(pc.iteration);
    vec3 f = vec3(0.0);
    if (live) {
        f = g - history[i].xyz;
        if (slot >= 0) {
            uint s = uint(slot);
            history[(3u + s) * n + i] = vec4(f - history[n + i].xyz, 0.0);
            history[(3u + MEMORY + s) * n + i] = vec4(g - history[2u * n + i].xyz, 0.0);
        }
        history[n + i] = vec4(f, 0.0);
        history[2u * n + i] = vec4(g, 0.0);
    }
    if (k == 0u) {
        return;
    }
    vec3 df[ANDERSON_MAX_MEMORY];
    for (uint c = 0u; c < k; ++c) {
        df[c] = live ? history[(3u + c) * n + i].xyz : vec3(0.0);
    }
    float terms[ANDERSON_MAX_TERMS];
    for (uint a = 0u; a < k; ++a) {
        for (uint b = a; b < k; ++b) {
            terms[gram_index(a, b, k)] = dot(df[a], df[b]);
        }
        terms[k * (k + 1u) / 2u + a] = dot(df[a], f);
    }
    uint count = gram_terms(k);
    uint row = gl_WorkGroupID.x * ANDERSON_MAX_TERMS;
    for (uint t = 0u; t < count; t += 8u) {
        vec4 a;
        vec4 b;
        for (uint j = 0u; j < 4u; ++j) {
            a[j] = t + j < count ? terms[t + j] : 0.0;
            b[j] = t + 4u + j < count ? terms[t + 4u + j] : 0.0;
        }
        workgroup_sum8(a, b);
        if (gl_LocalInvocationID.x == 0u) {
            for (uint j = 0u; j < 4u; ++j) {
                if (t + j < count) {
                    sums[row + t + j] = a[j];
                }
                if (t + 4u + j < count) {
                    sums[row + t + 4u + j] = b[j];
                }
            }
        }
    }
}
