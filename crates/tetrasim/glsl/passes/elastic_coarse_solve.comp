#version 460
// Pass `elastic_coarse_solve` (finite elements' preconditioner, every conjugate-gradient
// iteration; docs/GPU.md, "Finite elements on the GPU"): solves A_c u = b in place in one
// workgroup with the factor `elastic_coarse_factor` left, the twin of CoarseSpace::solve
// (src/physics/coarse.rs): an unknown left out of the factor gets 0. By columns: each
// unknown, once known, is taken off the later (forward) or earlier (back) rows by every
// invocation at once; the vector stays in shared memory.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

layout(constant_id = 1) const uint UNKNOWNS = 6u;

layout(std430, set = 0, binding = B_COARSE_MATRIX) readonly restrict buffer CoarseMatrix { float coarse[]; };
layout(std430, set = 0, binding = B_COARSE_VECTOR) restrict buffer CoarseVector { float vector[]; };

shared float u[UNKNOWNS];

void main() {
    if (!elastic_preconditions()) {
        return;
    }
    uint n = UNKNOWNS;
    uint lanes = gl_WorkGroupSize.x;
    uint me = gl_LocalInvocationID.x;
    for (uint i = me; i < n; i += lanes) {
        u[i] = vector[i];
    }
    barrier();
    // L y = b.
    for (uint k = 0u; k < n; ++k) {
        bool kept = coarse[n * n + k] > 0.5;
        float y = kept ? u[k] / coarse[k * n + k] : 0.0;
        barrier();
        for (uint i = k + 1u + me; i < n; i += lanes) {
            u[i] -= coarse[k * n + i] * y;
        }
        if (me == 0u) {
            u[k] = y;
        }
        barrier();
    }
    // L^T x = y.
    for (uint k = n; k-- > 0u;) {
        bool kept = coarse[n * n + k] > 0.5;
        float x = kept ? u[k] / coarse[k * n + k] : 0.0;
        barrier();
        for (uint i = me; i < k; i += lanes) {
            u[i] -= coarse[i * n + k] * x;
        }
        if (me == 0u) {
            u[k] = x;
        }
        barrier();
    }
    for (uint i = me; i < n; i += lanes) {
        vector[i] = u[i];
    }
}
