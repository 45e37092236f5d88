#version 460
// Pass `elastic_coarse_gather` (finite elements' coarse level, when it is built; docs/GPU.md,
// "Finite elements on the GPU"): one workgroup per block (column aggregate a, row aggregate
// b) of the coarse matrix: its items' 6 x 6 blocks (backend::vulkan::CoarseIndex) added in a
// fixed order (strided, then the workgroup sum), into the matrix's columns 6a..6a+6, rows
// 6b..6b+6 (column-major, as `elastic_coarse_factor` reads it); a block of no item is zero.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"
#include "common/workgroup_sum.glsl"

layout(constant_id = 2) const uint AGGREGATES = 1u;

layout(std430, set = 0, binding = B_COARSE_INDEX) readonly restrict buffer CoarseIndex { uint index[]; };
layout(std430, set = 0, binding = B_COARSE_SCRATCH) readonly restrict buffer CoarseScratch { float scratch[]; };
layout(std430, set = 0, binding = B_COARSE_MATRIX) writeonly restrict buffer CoarseMatrix { float coarse[]; };

WORKGROUP_SUM_PAIR(gather_sum, float)

void main() {
    if (!coarse_rebuilds()) {
        return;
    }
    uint block = gl_WorkGroupID.x;
    uint a = block / AGGREGATES;
    uint b = block % AGGREGATES;
    uint n = 6u * AGGREGATES;
    // The blocks' offsets follow the tets' offsets and items.
    uint blocks = pc.tet_count + 1u + index[pc.tet_count];
    uint items = blocks + AGGREGATES * AGGREGATES + 1u;
    float sum[36];
    for (uint e = 0u; e < 36u; ++e) {
        sum[e] = 0.0;
    }
    for (uint item = index[blocks + block] + gl_LocalInvocationID.x; item < index[blocks + block + 1u];
         item += gl_WorkGroupSize.x) {
        uint row = index[items + item];
        for (uint e = 0u; e < 36u; ++e) {
            sum[e] += scratch[36u * row + e];
        }
    }
    for (uint e = 0u; e < 36u; e += 2u) {
        gather_sum(sum[e], sum[e + 1u]);
        barrier();
    }
    if (gl_LocalInvocationID.x == 0u) {
        for (uint l = 0u; l < 6u; ++l) {
            for (uint k = 0u; k < 6u; ++k) {
                coarse[(6u * a + k) * n + 6u * b + l] = sum[6u * l + k];
            }
        }
    }
}
