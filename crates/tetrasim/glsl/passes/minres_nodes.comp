#version 460
// Pass `minres_nodes`: the first of a MINRES iteration's two passes (common/minres.glsl),
// in two parts that each workgroup w runs in turn (a workgroup-uniform choice). First node
// workgroup w, LANES invocations per node (common/lanes.glsl; phase 1 of
// src/backend/cpu/minres/mod.rs): u = W J^T y for its nodes through the rows' transpose,
// unscaled (minres_product divides by beta). In iteration 0 y is the rows' first; later it
// is the next Lanczos vector after the last iteration, M^-1 (av - alpha / beta r2),
// computed entry by entry from the last iteration's vectors (nothing has written it yet).
// Then row workgroup w sums that vector's norm and advances the recurrence (the last
// iteration's phase 3, lanczos_norm). So an iteration takes two dispatches, not three; the
// dispatch has as many workgroups as the larger part needs.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"
#include "common/lanes.glsl"

// Row j's y of iteration k: the rows' own in iteration 0, else the next vector's after `r`.
float y_of(uint k, Recurrence r, uint j) {
    if (k == 0u) {
        return vector_at(P_Y, j);
    }
    float y;
    next_vector(r, j, y);
    return y;
}

// Node workgroup w's part: u for its nodes.
void node_sums(uint k) {
    // The recurrence whose vectors give y: iteration 0's own, else the last iteration's.
    Recurrence r = load_state(k == 0u ? 0u : k - 1u);
    if (!r.going) {
        return;
    }
    uint i = lane_node();
    uint lane = lane_index();
    vec3 sum = vec3(0.0);
    if (i < pc.node_count) {
        TRANSPOSE_SUM(sum, i, lane, LANES, y_of(k, r, row))
    }
    sum = lanes_total(sum);
    if (i < pc.node_count && lane == 0u) {
        node_vectors[i] = vec4(mobility_apply(i, sum), 0.0);
    }
}

void main() {
    uint k = pc.iteration;
    uint w = gl_WorkGroupID.x;
    uint node_workgroups = (pc.node_count * LANES + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x;
    if (w < node_workgroups) {
        node_sums(k);
    }
    if (k > 0u && w < PARTIALS) {
        lanczos_norm(k, w);
    }
}
