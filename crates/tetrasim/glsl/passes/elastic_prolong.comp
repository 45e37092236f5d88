#version 460
// Pass `elastic_prolong` (finite elements' preconditioner, per node; docs/GPU.md, "Finite
// elements on the GPU"): the preconditioned residual Z = the inverse diagonal block times R
// plus, for a node of an aggregate not touching a contact, the coarse correction P u
// (`elastic_coarse_solve`'s u, CoarseVector's second half: its aggregate's translation plus
// its turn x (x - centre) / size), and its share of r . z as the workgroup's partial, at a linearisation or while
// the solve goes on (`elastic_preconditions`). The twin of cpu-ref's `precondition`
// (src/schedule/family/elastic.rs, ElasticNodes::precondition). Without aggregates
// (AGGREGATES 0) the block-Jacobi term alone.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

layout(constant_id = 2) const uint AGGREGATES = 1u;

#include "common/coarse.glsl"

layout(std430, set = 0, binding = B_ELASTIC_NODES) restrict buffer ElasticNodesBuffer { vec4 nodes[]; };
layout(std430, set = 0, binding = B_COARSE_VECTOR) readonly restrict buffer CoarseVector { float vector[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
    float share = 0.0;
    if (i < n && elastic_preconditions()) {
        vec3 r = nodes[ELASTIC_PLANE_R * n + i].xyz;
        vec4 a = nodes[ELASTIC_PLANE_INVERSE_A * n + i];
        vec4 b = nodes[ELASTIC_PLANE_INVERSE_B * n + i];
        vec3 z = sym3_apply(Sym3(a.xyz, vec3(a.w, b.x, b.y)), r);
        uint g = AGGREGATES > 0u ? aggregate_of(i) : NO_AGGREGATE;
        if (g != NO_AGGREGATE && nodes[ELASTIC_PLANE_HELD * n + i].w == 0.0) {
            vec4 centre = modes[g];
            // `elastic_coarse_solve`'s u, after the restricted residual.
            uint u = 6u * AGGREGATES + 6u * g;
            vec3 push = vec3(vector[u], vector[u + 1u], vector[u + 2u]);
            vec3 turn = vec3(vector[u + 3u], vector[u + 4u], vector[u + 5u]);
            z += push + cross(turn, nodes[ELASTIC_PLANE_AT * n + i].xyz - centre.xyz) / centre.w;
        }
        nodes[ELASTIC_PLANE_Z * n + i] = vec4(z, 0.0);
        share = dot(r, z);
    }
    store_partial(share);
}
