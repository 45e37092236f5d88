#version 460
// Pass `elastic_coarse_inverse` (finite elements' coarse level, with `elastic_coarse_factor`
// every COARSE_REBUILD_STEPS steps; docs/GPU.md, "Finite elements on the GPU"): the coarse
// matrix's inverse from its factor L L^T, one column per invocation and no barrier: column
// j solves L y = e_j forward and L^T x = y back, in place in its own column after the factor
// and the flags (entry (i, j) at coarse[U * U + U + j * U + i]), an unknown left out of the
// factor (flag 0) getting 0 as in CoarseSpace::solve. `elastic_coarse_solve` then applies it
// as one product per iteration: a triangular solve in one workgroup waits on two barriers
// per unknown, the inverse's product on none.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

layout(constant_id = 1) const uint UNKNOWNS = 6u;

layout(std430, set = 0, binding = B_COARSE_MATRIX) restrict buffer CoarseMatrix { float coarse[]; };

#include "common/coarse_dot.glsl"

void main() {
    if (!coarse_rebuilds()) {
        return;
    }
    uint n = UNKNOWNS;
    uint j = gl_GlobalInvocationID.x;
    if (j >= n) {
        return;
    }
    uint column = n * n + n + j * n;
    // L y = e_j: y is 0 above row j.
    for (uint i = 0u; i < n; ++i) {
        float y = 0.0;
        if (i >= j && coarse[n * n + i] > 0.5) {
            float s = (i == j ? 1.0 : 0.0) - coarse_dot(j * n + i, n, column + j, 1u, i - j);
            y = s / coarse[i * n + i];
        }
        coarse[column + i] = y;
    }
    // L^T x = y.
    for (uint i = n; i-- > 0u;) {
        float x = 0.0;
        if (coarse[n * n + i] > 0.5) {
            float s = coarse[column + i] - coarse_dot(i * n + i + 1u, 1u, column + i + 1u, 1u, n - 1u - i);
            x = s / coarse[i * n + i];
        }
        coarse[column + i] = x;
    }
}
