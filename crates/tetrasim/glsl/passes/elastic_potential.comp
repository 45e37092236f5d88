#version 460
// Pass `elastic_potential` (finite elements, when a conjugate-gradient step goes beyond the
// trusted strain; docs/GPU.md, "Finite elements on the GPU"): how much the step's
// incremental potential changes when the nodes move from AT + DX by each step the
// backtracking tries (alpha and its halvings while beyond the trust): invocation j adds
// tet j's energy change and free node j's inertia's, m/(2 dt^2) (|x - y|^2 change), and its
// contact's, (h . d)^2 / 2 change (each expanded in the step, so no change is a difference of
// two potentials), and each workgroup stores its partial of every step's change
// (`elastic_backtrack` decides). The twin of cpu-ref's `potential` in `backtrack`
// (src/backend/cpu/reference/elastic.rs), as changes. Covers max(nodes, tets) invocations.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_tets.glsl"
#include "common/elastic_state.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) readonly restrict buffer ElasticNodesBuffer { vec4 nodes[]; };

vec3 plane(uint k, uint i) {
    return nodes[k * pc.node_count + i].xyz;
}

// Where node k is before the step: the linearisation's end plus the step's moves so far.
vec3 base(uint k) {
    return plane(ELASTIC_PLANE_AT, k) + plane(ELASTIC_PLANE_DX, k);
}

void main() {
    if (state_u[ELASTIC_STATE_CHECK] == 0u || state_u[ELASTIC_STATE_DONE] != 0u) {
        return;
    }
    float steps[9];
    float strain = uintBitsToFloat(state_u[ELASTIC_STATE_STRAIN]);
    uint count = backtrack_steps(state[ELASTIC_STATE_ALPHA], strain, steps);
    uint j = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
    float change[9];
    for (uint k = 0u; k < 9u; ++k) {
        change[k] = 0.0;
    }
    if (j < pc.tet_count) {
        uvec4 tet = tets[j];
        ElasticTet e = elastic_tet_at(j);
        uint p = ELASTIC_PLANE_P;
        elastic_energy_changes(e, base(tet.x), base(tet.y), base(tet.z), base(tet.w),
                               plane(p, tet.x), plane(p, tet.y), plane(p, tet.z), plane(p, tet.w),
                               steps, count, change);
    }
    if (j < n && positions[j].w > 0.0) {
        vec3 p = plane(ELASTIC_PLANE_P, j);
        vec3 off = base(j) - plane(ELASTIC_PLANE_Y, j);
        float inertia = velocities[j].w / (2.0 * pc.dt * pc.dt);
        vec3 h = plane(ELASTIC_PLANE_HELD, j);
        float hp = dot(h, p);
        float hd = dot(h, plane(ELASTIC_PLANE_DX, j));
        for (uint k = 0u; k < count; ++k) {
            float a = steps[k];
            change[k] += inertia * a * (2.0 * dot(off, p) + a * dot(p, p)) + 0.5 * a * hp * (2.0 * hd + a * hp);
        }
    }
    uint groups = gl_NumWorkGroups.x;
    for (uint k = 0u; k < 9u; k += 2u) {
        float a = change[k];
        float b = k + 1u < 9u ? change[k + 1u] : 0.0;
        elastic_workgroup_sum(a, b);
        if (gl_LocalInvocationID.x == 0u) {
            state[ELASTIC_STATE_PARTIALS + k * groups + gl_WorkGroupID.x] = a;
            if (k + 1u < 9u) {
                state[ELASTIC_STATE_PARTIALS + (k + 1u) * groups + gl_WorkGroupID.x] = b;
            }
        }
        barrier();
    }
}
