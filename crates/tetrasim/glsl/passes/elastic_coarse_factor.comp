#version 460
// Pass `elastic_coarse_factor` (finite elements' coarse level, every COARSE_REBUILD_STEPS
// steps; docs/GPU.md, "Finite elements on the GPU"): factors the coarse matrix P^T A P of
// UNKNOWNS unknowns (6 per aggregate, at most 384) as L L^T in one workgroup, in place, the
// twin of CoarseSpace::factor (src/physics/coarse.rs): a column whose pivot falls to 1e-10
// of its diagonal or below is left out (zeroed, its flag 0), as the reference leaves out
// modes the fine matrix does not see. Left-looking by columns: every invocation forms its
// rows' entries of column j from the columns before, then divides by the pivot. Entry (i, k),
// i >= k, is at coarse[k * UNKNOWNS + i] (column-major: invocations i read consecutive
// floats); the flags follow the matrix. Its workgroup is at least 128 invocations whatever the
// plan's (`coarse_factor_workgroup`): with fewer, an invocation's rows at the most aggregates
// come near lavapipe's loop limit (common/coarse_dot.glsl).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

layout(constant_id = 1) const uint UNKNOWNS = 6u;

layout(std430, set = 0, binding = B_COARSE_MATRIX) restrict buffer CoarseMatrix { float coarse[]; };

#include "common/coarse_dot.glsl"

shared float diagonal;

void main() {
    if (!coarse_rebuilds()) {
        return;
    }
    uint n = UNKNOWNS;
    uint lanes = gl_WorkGroupSize.x;
    for (uint j = 0u; j < n; ++j) {
        if (gl_LocalInvocationID.x == 0u) {
            diagonal = coarse[j * n + j];
        }
        barrier();
        // s_i = A(i, j) - sum_k<j L(i, k) L(j, k), into the column's slots.
        for (uint i = j + gl_LocalInvocationID.x; i < n; i += lanes) {
            coarse[j * n + i] -= coarse_dot(i, n, j, n, j);
        }
        memoryBarrierBuffer();
        barrier();
        float d = coarse[j * n + j];
        bool kept = !isnan(d) && !isinf(d) && d > 1e-10 * abs(diagonal);
        float pivot = kept ? sqrt(d) : 0.0;
        barrier();
        for (uint i = j + gl_LocalInvocationID.x; i < n; i += lanes) {
            coarse[j * n + i] = !kept ? 0.0 : (i == j ? pivot : coarse[j * n + i] / pivot);
        }
        if (gl_LocalInvocationID.x == 0u) {
            coarse[n * n + j] = kept ? 1.0 : 0.0;
        }
        memoryBarrierBuffer();
        barrier();
    }
}
