#version 460
// Pass `elastic_restrict` (finite elements' preconditioner, every conjugate-gradient
// iteration; docs/GPU.md, "Finite elements on the GPU"): one workgroup per aggregate, its
// six entries of P^T r into CoarseVector: over its members not touching a contact, the
// residual (the translations') and rho x r, rho = (x - centre) / size (the rotations': the
// rotation e_l x rho against r is (rho x r)_l), x where the node ends the step so far. The
// twin of CoarseSpace::restrict summed as cpu-ref's `precondition` sums it.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

layout(constant_id = 2) const uint AGGREGATES = 1u;

#include "common/coarse.glsl"

layout(std430, set = 0, binding = B_ELASTIC_NODES) readonly restrict buffer ElasticNodesBuffer { vec4 nodes[]; };
layout(std430, set = 0, binding = B_COARSE_VECTOR) writeonly restrict buffer CoarseVector { float vector[]; };

WORKGROUP_SUM_PAIR(restrict_sum, vec4)

void main() {
    if (!elastic_preconditions()) {
        return;
    }
    uint a = gl_WorkGroupID.x;
    uint n = pc.node_count;
    vec4 centre = modes[a];
    vec4 push = vec4(0.0);
    vec4 turn = vec4(0.0);
    for (uint k = aggregate_first(a) + gl_LocalInvocationID.x; k < aggregate_end(a); k += gl_WorkGroupSize.x) {
        uint i = aggregate_member(k);
        if (nodes[ELASTIC_PLANE_HELD * n + i].w > 0.0) {
            continue;
        }
        vec3 r = nodes[ELASTIC_PLANE_R * n + i].xyz;
        vec3 rho = (nodes[ELASTIC_PLANE_AT * n + i].xyz - centre.xyz) / centre.w;
        push += vec4(r, 0.0);
        turn += vec4(cross(rho, r), 0.0);
    }
    restrict_sum(push, turn);
    if (gl_LocalInvocationID.x == 0u) {
        vector[6u * a] = push.x;
        vector[6u * a + 1u] = push.y;
        vector[6u * a + 2u] = push.z;
        vector[6u * a + 3u] = turn.x;
        vector[6u * a + 4u] = turn.y;
        vector[6u * a + 5u] = turn.z;
    }
}
