#version 460
// Pass `elastic_coarse_nodes` (finite elements' coarse level, when it is built; docs/GPU.md,
// "Finite elements on the GPU"): per free node of an aggregate (in the aggregates' member
// order), its own block m/dt^2 I + h h^T (h: its contact's stiffening) against its
// aggregate's modes there, the 6 x 6 block into CoarseScratch after the tets' items. The twin
// of ElasticNodes::coarse_columns' nodes (CoarseSpace::add_node).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

layout(constant_id = 2) const uint AGGREGATES = 1u;

#include "common/coarse.glsl"

layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) readonly restrict buffer ElasticNodesBuffer { vec4 nodes[]; };
layout(std430, set = 0, binding = B_COARSE_INDEX) readonly restrict buffer CoarseIndex { uint index[]; };
layout(std430, set = 0, binding = B_COARSE_SCRATCH) writeonly restrict buffer CoarseScratch { float scratch[]; };

void main() {
    if (!coarse_rebuilds()) {
        return;
    }
    uint k = gl_GlobalInvocationID.x;
    if (k >= aggregates[AGGREGATES]) {
        return;
    }
    uint n = pc.node_count;
    uint i = aggregate_member(k);
    uint a = aggregate_of(i);
    float inertia = velocities[i].w / (pc.dt * pc.dt);
    vec3 h = nodes[ELASTIC_PLANE_HELD * n + i].xyz;
    vec3 rho = coarse_rho(a, nodes[ELASTIC_PLANE_AT * n + i].xyz);
    uint row = index[pc.tet_count] + k;
    for (uint c = 0u; c < 6u; ++c) {
        vec3 mode = coarse_mode(c, rho);
        vec3 applied = mode * inertia + h * dot(h, mode);
        for (uint l = 0u; l < 6u; ++l) {
            scratch[36u * row + 6u * l + c] = dot(coarse_mode(l, rho), applied);
        }
    }
}
