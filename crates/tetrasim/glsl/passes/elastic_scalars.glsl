// The body of the finite elements' scalar passes, one workgroup each (docs/GPU.md,
// "Finite elements on the GPU"): the node passes' partials added in workgroup order (the
// same total whichever workgroup finished last), then the conjugate gradients' scalars in
// ElasticState. Defines (one of):
//   BEGIN (`elastic_begin`, after `elastic_prolong`): at a linearisation (the step's first
//     iteration, or RELINEARISE) r . z begins the Newton step's solve (done if not
//     positive; beta 0, so that `elastic_direction` takes z; the flags cleared; at the
//     step's first iteration the step counter advanced); otherwise, unless done, the new
//     r . z and beta = its ratio to the last (done if not positive). The largest strain is
//     cleared for the next product either way.
//   ALPHA (`elastic_alpha`): the curvature p . A p and the step alpha = r . z / p . A p
//     (done at non-positive curvature), and whether it goes beyond the trusted strain
//     (CHECK).
//   BACKTRACK (`elastic_backtrack`, after `elastic_potential`, whose PARTIALS workgroups
//     left a partial per step tried): cpu-ref's `backtrack` on the potential's changes: the
//     first step tried that lowers the potential is taken, and the Newton step relinearised
//     unless it fell by TRUSTED_RATIO of the quadratic model's prediction; a halving within
//     the trust is taken unchecked and relinearised; none: done.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

// Workgroups of the node pass whose partials are added.
layout(constant_id = 1) const uint PARTIALS = 1u;

// The sum of partial column `k` (PARTIALS partials each), in workgroup order.
float partials_sum(uint k) {
    float total = 0.0;
    for (uint w = gl_LocalInvocationID.x; w < PARTIALS; w += gl_WorkGroupSize.x) {
        total += state[ELASTIC_STATE_PARTIALS + k * PARTIALS + w];
    }
    float unused = 0.0;
    elastic_workgroup_sum(total, unused);
    return total;
}

#ifdef BACKTRACK
shared float changes[9];
#endif

void main() {
#ifdef BACKTRACK
    if (state_u[ELASTIC_STATE_CHECK] == 0u || state_u[ELASTIC_STATE_DONE] != 0u) {
        return;
    }
    for (uint k = 0u; k < 9u; ++k) {
        float change = partials_sum(k);
        if (gl_LocalInvocationID.x == 0u) {
            changes[k] = change;
        }
        barrier();
    }
    if (gl_LocalInvocationID.x != 0u) {
        return;
    }
    float steps[9];
    float alpha = state[ELASTIC_STATE_ALPHA];
    float strain = uintBitsToFloat(state_u[ELASTIC_STATE_STRAIN]);
    uint count = backtrack_steps(alpha, strain, steps);
    float curvature = state[ELASTIC_STATE_CURVATURE];
    for (uint k = 0u; k < BACKTRACK_STEPS; ++k) {
        if (k >= count) {
            // Within the trust: taken unchecked, the Newton step begun anew.
            state[ELASTIC_STATE_ALPHA] = steps[k];
            state_u[ELASTIC_STATE_RELINEARISE] = 1u;
            return;
        }
        if (changes[k] <= 0.0) {
            float predicted = curvature * steps[k] * (alpha - 0.5 * steps[k]);
            state[ELASTIC_STATE_ALPHA] = steps[k];
            state_u[ELASTIC_STATE_RELINEARISE] = -changes[k] < TRUSTED_RATIO * predicted ? 1u : 0u;
            return;
        }
    }
    state_u[ELASTIC_STATE_DONE] = 1u;
    state_u[ELASTIC_STATE_RELINEARISE] = 1u;
#else
    float total = partials_sum(0u);
    if (gl_LocalInvocationID.x != 0u) {
        return;
    }
#endif
#ifdef BEGIN
    if (elastic_linearises()) {
        // A Newton step begins: the first direction is z (beta 0).
        state[ELASTIC_STATE_RZ] = total;
        state[ELASTIC_STATE_BETA] = 0.0;
        state_u[ELASTIC_STATE_DONE] = total > 0.0 ? 0u : 1u;
        state_u[ELASTIC_STATE_CHECK] = 0u;
        state_u[ELASTIC_STATE_RELINEARISE] = 0u;
        if (pc.iteration == 0u) {
            state_u[ELASTIC_STATE_STEP] += 1u;
        }
    } else if (state_u[ELASTIC_STATE_DONE] == 0u) {
        state[ELASTIC_STATE_BETA] = total / state[ELASTIC_STATE_RZ];
        state[ELASTIC_STATE_RZ] = total;
        state_u[ELASTIC_STATE_DONE] = total > 0.0 ? 0u : 1u;
    }
    state_u[ELASTIC_STATE_STRAIN] = 0u;
#endif
#ifdef ALPHA
    if (state_u[ELASTIC_STATE_DONE] == 0u) {
        state[ELASTIC_STATE_CURVATURE] = total;
        if (total > 0.0) {
            float alpha = state[ELASTIC_STATE_RZ] / total;
            float strain = uintBitsToFloat(state_u[ELASTIC_STATE_STRAIN]);
            state[ELASTIC_STATE_ALPHA] = alpha;
            state_u[ELASTIC_STATE_CHECK] = alpha * strain > TRUSTED_STRAIN ? 1u : 0u;
        } else {
            state_u[ELASTIC_STATE_DONE] = 1u;
        }
    }
#endif
}
