#version 460
// Pass `minres_next`: the last of a MINRES iteration's passes (common/minres.glsl; phase 3
// of src/backend/cpu/minres/mod.rs), in the row passes' shape: the next Lanczos vector
// r2' = av - alpha / beta r2 (r1 = r2, r2 = r2'), y = M^-1 r2', and its norm r2' . y, from
// which the last workgroup advances the recurrence for the next iteration (or the finish).
// A stopped solve passes its recurrence on, stopped.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"

void main() {
    Recurrence r = load_state(pc.iteration);
    if (!r.going) {
        if (gl_GlobalInvocationID.x == 0u) {
            r.pending = false;
            store_state(pc.iteration + 1u, r);
        }
        return;
    }
    float along = r.alpha / r.beta;
    uint j = row_of_invocation();
    float norm = 0.0;
    if (j != NO_ROW) {
        float r2 = vector_at(P_R2, j);
        float next = vector_at(P_AV, j) - along * r2;
        float y = next * vector_at(P_INVERSE, j);
        set_vector(P_R1, j, r2);
        set_vector(P_R2, j, next);
        set_vector(P_Y, j, y);
        norm = next * y;
    }
    if (reduce_last(norm) && gl_LocalInvocationID.x == 0u) {
        store_state(pc.iteration + 1u, recurrence_next(r, norm));
    }
}
