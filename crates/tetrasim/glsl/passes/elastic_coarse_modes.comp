#version 460
// Pass `elastic_coarse_modes` (finite elements' coarse level, when it is built; docs/GPU.md,
// "Finite elements on the GPU"): one workgroup per aggregate, its modes where its nodes end
// the step so far (ElasticNodes' AT plane): the centre of its members and its size, their
// root-mean-square distance to it (1 for a point), into CoarseModes. The twin of
// CoarseSpace::new (src/physics/coarse.rs).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

layout(constant_id = 2) const uint AGGREGATES = 1u;

#include "common/coarse.glsl"

layout(std430, set = 0, binding = B_ELASTIC_NODES) readonly restrict buffer ElasticNodesBuffer { vec4 nodes[]; };

WORKGROUP_SUM_PAIR(modes_sum, vec4)

void main() {
    if (!coarse_rebuilds()) {
        return;
    }
    uint a = gl_WorkGroupID.x;
    uint first = aggregate_first(a);
    uint end = aggregate_end(a);
    float count = float(max(end - first, 1u));
    vec4 sum = vec4(0.0);
    vec4 unused = vec4(0.0);
    for (uint k = first + gl_LocalInvocationID.x; k < end; k += gl_WorkGroupSize.x) {
        sum += vec4(nodes[ELASTIC_PLANE_AT * pc.node_count + aggregate_member(k)].xyz, 0.0);
    }
    modes_sum(sum, unused);
    barrier();
    vec3 centre = sum.xyz / count;
    vec4 spread = vec4(0.0);
    for (uint k = first + gl_LocalInvocationID.x; k < end; k += gl_WorkGroupSize.x) {
        vec3 d = nodes[ELASTIC_PLANE_AT * pc.node_count + aggregate_member(k)].xyz - centre;
        spread.x += dot(d, d);
    }
    modes_sum(spread, unused);
    if (gl_LocalInvocationID.x == 0u) {
        float mean = spread.x / count;
        modes[a] = vec4(centre, mean > 0.0 ? sqrt(mean) : 1.0);
    }
}
