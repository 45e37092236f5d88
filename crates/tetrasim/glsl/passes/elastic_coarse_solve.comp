#version 460
// Pass `elastic_coarse_solve` (finite elements' preconditioner, every conjugate-gradient
// iteration; docs/GPU.md, "Finite elements on the GPU"): u = A_c^-1 b, the coarse level's
// correction of the restricted residual b (CoarseVector's first UNKNOWNS floats, from
// `elastic_restrict`) into CoarseVector's second UNKNOWNS, with the inverse
// `elastic_coarse_inverse` left: one invocation per row, reading the inverse's columns
// across the invocations (consecutive floats). The twin of CoarseSpace::solve
// (src/physics/coarse.rs); an unknown left out of the factor gets 0.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

layout(constant_id = 1) const uint UNKNOWNS = 6u;

layout(std430, set = 0, binding = B_COARSE_MATRIX) readonly restrict buffer CoarseMatrix { float coarse[]; };
layout(std430, set = 0, binding = B_COARSE_VECTOR) restrict buffer CoarseVector { float vector[]; };

void main() {
    if (!elastic_preconditions()) {
        return;
    }
    uint n = UNKNOWNS;
    uint i = gl_GlobalInvocationID.x;
    if (i >= n) {
        return;
    }
    uint inverse = n * n + n;
    float u = 0.0;
    for (uint j = 0u; j < n; ++j) {
        u += coarse[inverse + j * n + i] * vector[j];
    }
    vector[n + i] = u;
}
