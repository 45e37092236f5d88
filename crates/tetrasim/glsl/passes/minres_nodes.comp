#version 460
// Pass `minres_nodes`: the first of a MINRES iteration's three passes (common/minres.glsl;
// phase 1 of src/backend/cpu/minres/mod.rs), LANES invocations per node (common/lanes.glsl):
// while the solve goes on (the recurrence of iteration pc.iteration), u = W J^T v for its
// node through the rows' transpose, v = y / beta.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"
#include "common/lanes.glsl"

void main() {
    Recurrence r = load_state(pc.iteration);
    if (!r.going) {
        return;
    }
    uint i = lane_node();
    vec3 sum = i < pc.node_count ? transpose_sum(i, P_Y, lane_index(), LANES) : vec3(0.0);
    sum = lanes_total(sum);
    if (i >= pc.node_count || lane_index() != 0u) {
        return;
    }
    node_vectors[i] = vec4(mobility_apply(i, sum * (1.0 / r.beta)), 0.0);
}
