#version 460
// Pass `minres_nodes`: the first of a MINRES iteration's three passes (common/minres.glsl;
// phase 1 of src/backend/cpu/minres/mod.rs), one invocation per node: while the solve goes
// on (the recurrence of iteration pc.iteration), u = W J^T v for its node through the rows'
// transpose, v = y / beta.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"

void main() {
    Recurrence r = load_state(pc.iteration);
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count || !r.going) {
        return;
    }
    vec3 sum = transpose_sum(i, P_Y);
    node_vectors[i] = vec4(mobility_apply(i, sum * (1.0 / r.beta)), 0.0);
}
