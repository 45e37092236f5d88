#version 460
// Pass `minres_finish`: after MINRES's iterations (common/minres.glsl), in the row passes'
// shape: the last iteration's rotation's update of the solution, and each compliant row's increment added to its multiplier so far (an implicit
// spring's, or a compliant tet's; SpringMultipliers and VolumeMultipliers, as the sweeps
// keep them). Variants: the segments with multipliers (s: implicit springs, v: volume
// constraints).
// @variant plain:
// @variant s: SPRINGS
// @variant v: VOLUMES
// @variant sv: SPRINGS VOLUMES
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"
#include "physics/implicit.glsl"

#ifdef SPRINGS
layout(std430, set = 0, binding = B_SPRING_MULTIPLIERS) restrict buffer SpringMultipliers { float spring_multipliers[]; };
#endif
#ifdef VOLUMES
layout(std430, set = 0, binding = B_VOLUME_MULTIPLIERS) restrict buffer VolumeMultipliers { float volume_multipliers[]; };
#endif

void main() {
    Recurrence r = load_state(ITERATIONS);
    uint j = row_of_invocation();
    if (j == NO_ROW) {
        return;
    }
    if (r.pending) {
        apply_update(r, j);
    }
    float x = vector_at(P_X, j);
#ifdef SPRINGS
    if (j < SPRING_ROWS) {
        spring_multipliers[j] = multiplier_so_far(spring_multipliers[j], pc.iteration, pc.warm_start) + x;
    }
#endif
#ifdef VOLUMES
    uint t = j - SPRING_ROWS - DISTANCE_ROWS;
    if (j >= SPRING_ROWS + DISTANCE_ROWS && t < TET_ROWS && vector_at(P_SOFTNESS, j) > 0.0) {
        volume_multipliers[t] = multiplier_so_far(volume_multipliers[t], pc.iteration, 0u) + x;
    }
#endif
}
