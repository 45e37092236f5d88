#version 460
// Pass `elastic_scalars` (finite elements, one workgroup; docs/GPU.md, "Finite elements on
// the GPU"): the node passes' partials added in workgroup order (the same total whichever
// workgroup finished last), then the conjugate gradients' scalars. Variant `start`: r . z
// of the linearisation (done if not positive). Variant `alpha`: the curvature p . A p and
// the step alpha = r . z / p . A p (done at non-positive curvature). Variant `beta`: the
// new r . z, beta = its ratio to the last (done if not positive), and the largest strain
// cleared for the next product.
// @variant start: START
// @variant alpha: ALPHA
// @variant beta: BETA
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

// Workgroups of the node pass whose partials are added.
layout(constant_id = 1) const uint PARTIALS = 1u;

void main() {
    float total = 0.0;
    for (uint w = gl_LocalInvocationID.x; w < PARTIALS; w += gl_WorkGroupSize.x) {
        total += state[ELASTIC_STATE_PARTIALS + w];
    }
    float unused = 0.0;
    elastic_workgroup_sum(total, unused);
    if (gl_LocalInvocationID.x != 0u) {
        return;
    }
#ifdef START
    state[ELASTIC_STATE_RZ] = total;
    state_u[ELASTIC_STATE_DONE] = total > 0.0 ? 0u : 1u;
    state_u[ELASTIC_STATE_STRAIN] = 0u;
#endif
#ifdef ALPHA
    if (state_u[ELASTIC_STATE_DONE] == 0u) {
        state[ELASTIC_STATE_CURVATURE] = total;
        if (total > 0.0) {
            state[ELASTIC_STATE_ALPHA] = state[ELASTIC_STATE_RZ] / total;
        } else {
            state_u[ELASTIC_STATE_DONE] = 1u;
        }
    }
#endif
#ifdef BETA
    if (state_u[ELASTIC_STATE_DONE] == 0u) {
        state[ELASTIC_STATE_BETA] = total / state[ELASTIC_STATE_RZ];
        state[ELASTIC_STATE_RZ] = total;
        state_u[ELASTIC_STATE_DONE] = total > 0.0 ? 0u : 1u;
    }
    state_u[ELASTIC_STATE_STRAIN] = 0u;
#endif
}
