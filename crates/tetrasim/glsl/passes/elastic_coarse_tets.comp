#version 460
// Pass `elastic_coarse_tets` (finite elements' coarse level, when it is built; docs/GPU.md,
// "Finite elements on the GPU"): per tet, its items of the coarse assembly
// (backend::vulkan::CoarseIndex): for each aggregate among its corners, the tet's stiffness
// times that aggregate's six modes at its corners in it (each corner's row scaled by
// 1 + beta/dt as the fine product scales it), and for each corner of an aggregate b the 6 x 6
// block of b's modes there against those products, into CoarseScratch. The twin of
// ElasticNodes::coarse_columns' tets (CoarseSpace::add_tet).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"
#define NODE_TETS
#include "common/elastic_tets.glsl"

layout(constant_id = 2) const uint AGGREGATES = 1u;

#include "common/coarse.glsl"

layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_ELASTIC_LINEAR) readonly restrict buffer ElasticLinearBuffer { vec4 linear[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) readonly restrict buffer ElasticNodesBuffer { vec4 nodes[]; };
layout(std430, set = 0, binding = B_COARSE_INDEX) readonly restrict buffer CoarseIndex { uint index[]; };
layout(std430, set = 0, binding = B_COARSE_SCRATCH) writeonly restrict buffer CoarseScratch { float scratch[]; };

void main() {
    if (!coarse_rebuilds()) {
        return;
    }
    uint t = gl_GlobalInvocationID.x;
    if (t >= pc.tet_count) {
        return;
    }
    uvec4 tet = tets[t];
    uint corner[4] = uint[4](tet.x, tet.y, tet.z, tet.w);
    ElasticTet e = elastic_tet_at(t);
    ElasticLinear lin = elastic_linear_of(linear[6u * t], linear[6u * t + 1u], linear[6u * t + 2u],
                                          linear[6u * t + 3u], linear[6u * t + 4u], linear[6u * t + 5u]);
    vec3 x[4];
    uint agg[4];
    float scale[4];
    for (uint j = 0u; j < 4u; ++j) {
        x[j] = nodes[ELASTIC_PLANE_AT * pc.node_count + corner[j]].xyz;
        agg[j] = aggregate_of(corner[j]);
        scale[j] = 1.0 + node_damping(corner[j]) / pc.dt;
    }
    uint items = pc.tet_count + 1u;
    vec3 applied[6][4];
    uint current = NO_AGGREGATE;
    for (uint item = index[t]; item < index[t + 1u]; ++item) {
        uint a = index[items + item] >> 2u;
        uint j = index[items + item] & 3u;
        if (a != current) {
            // The tet's stiffness times aggregate a's modes at its corners in a.
            current = a;
            for (uint k = 0u; k < 6u; ++k) {
                vec3 d[4];
                for (uint c = 0u; c < 4u; ++c) {
                    d[c] = agg[c] == a ? coarse_mode(k, coarse_rho(a, x[c])) : vec3(0.0);
                }
                vec3 q[4];
                elastic_product_strain(e, lin, d[0], d[1], d[2], d[3], q[0], q[1], q[2], q[3]);
                for (uint c = 0u; c < 4u; ++c) {
                    applied[k][c] = q[c] * scale[c];
                }
            }
        }
        vec3 rho = coarse_rho(agg[j], x[j]);
        for (uint l = 0u; l < 6u; ++l) {
            vec3 mode = coarse_mode(l, rho);
            for (uint k = 0u; k < 6u; ++k) {
                scratch[36u * item + 6u * l + k] = dot(mode, applied[k][j]);
            }
        }
    }
}
