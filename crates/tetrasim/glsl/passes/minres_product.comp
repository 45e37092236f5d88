#version 460
// Pass `minres_product`: the second of a MINRES iteration's two passes
// (common/minres.glsl; phase 2 of src/backend/cpu/minres/mod.rs), one invocation per row
// and one workgroup per global volume constraint: the last iteration's update of the
// search directions and the solution, its next Lanczos vectors (the CPU's phase 3 writes,
// lanczos_advance; minres_nodes summed their norm), then v = y / beta,
// av = J u / beta + s v (0 on the rows left to the sweeps; u is minres_nodes' unscaled
// W J^T y) less beta / old_beta r1, and alpha = v . av (the last workgroup keeps it in the
// recurrence).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"

// The product J u of row j (a fixed row: its own entries).
float fixed_product(uint j) {
    uint first = fixed_first_entry(j);
    float sum = 0.0;
    for (uint k = 0u; k < fixed_arity(j); ++k) {
        uint e = first + k;
        sum += dot(grads[e].xyz, node_vectors[entry_node(e)].xyz);
    }
    return sum;
}

void main() {
    Recurrence r = load_state(pc.iteration);
    uint j = row_of_invocation();
    if (r.pending && j != NO_ROW) {
        apply_update(r, j);
    }
    if (!r.going) {
        return;
    }
    if (pc.iteration > 0u && j != NO_ROW) {
        lanczos_advance(load_state(pc.iteration - 1u), j);
    }
    float product = 0.0;
    if (gl_WorkGroupID.x < FIXED_WORKGROUPS) {
        product = j != NO_ROW ? fixed_product(j) : 0.0;
    } else {
        // An object's row: its surface entries shared out over the workgroup.
        uvec2 entries = object_entries(gl_WorkGroupID.x - FIXED_WORKGROUPS);
        for (uint e = entries.x + gl_LocalInvocationID.x; e < entries.y; e += gl_WorkGroupSize.x) {
            product += dot(grads[e].xyz, node_vectors[entry_node(e)].xyz);
        }
        float unused = 0.0;
        minres_workgroup_sum(product, unused);
    }
    float alpha = 0.0;
    if (j != NO_ROW) {
        float over_beta = 1.0 / r.beta;
        float v = vector_at(P_Y, j) * over_beta;
        float live = vector_at(P_INVERSE, j) > 0.0 ? product * over_beta + vector_at(P_SOFTNESS, j) * v : 0.0;
        float back = r.old_beta > 0.0 ? r.beta / r.old_beta : 0.0;
        float av = live - back * vector_at(P_R1, j);
        set_vector(P_V, j, v);
        set_vector(P_AV, j, av);
        alpha = v * av;
    }
    if (reduce_last(alpha) && gl_LocalInvocationID.x == 0u) {
        state[4u * pc.iteration + 1u].w = alpha;
    }
}
