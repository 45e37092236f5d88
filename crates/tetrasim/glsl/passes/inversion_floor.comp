#version 460
// Pass `inversion_floor`: one sweep of the inversion floor over one group of the volume
// constraints (docs/PHYSICS.md, "Inversion floor"), after the step's iterations, one
// invocation per tet. Each tet measures its volume where its nodes end the step
// (end_position of x(t), v(t) and the current F) and, below INVERSION_FLOOR times its rest
// volume, adds the hard one-sided force that lifts it back to the floor to first order at
// those positions (inversion_floor in src/physics/constraint.rs): lambda = C / (dt^2 A),
// A = sum_k s_k w_k |grad_k C|^2, force -lambda grad_k C. Outputs as `volume` does:
// variants `ext`/`cas` add to the per-node sums with float atomics, `gather` writes the
// tet's four contribution slots for `constraint_apply#gather`. Nothing in split contact's
// velocity solve (pc.phase): the full solve's positions are restored, with no velocity.
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
// @variant gather: GATHER
// Variant `block` (block Gauss-Seidel, physics.md): one workgroup per block of the volume
// sweep, colour after colour in shared memory (common/block_sweep.glsl), each tet measured
// where the block's copies of its nodes end the step.
// @variant block: GATHER BLOCK
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/volume.glsl"
#include "physics/implicit.glsl"
#include "physics/contact.glsl"
#include "common/constraint_output.glsl"
#include "common/block.glsl"

// The fraction of the rest volume below which a tet is pushed back (the bits of a float).
layout(constant_id = 1) const float INVERSION_FLOOR = 0.1;

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_REST_VOLUMES) readonly restrict buffer RestVolumes { float rest_volumes[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };

// The floor's multiplier of tet t at the end positions q of its nodes (inverse masses w[k],
// a-scales s[k]), and its gradients g there: 0 above the floor, and in split contact's
// velocity solve (a position correction, no velocity).
float floor_multiplier(uint t, vec3 q[4], float w[4], float s[4], out vec3 g[4]) {
    float c = volume_constraint(q[0], q[1], q[2], q[3], INVERSION_FLOOR * rest_volumes[t], g[0], g[1], g[2], g[3]);
    if (!(c < 0.0) || pc.phase == PHASE_VELOCITY) {
        return 0.0;
    }
    float a = 0.0;
    for (int k = 0; k < 4; ++k) {
        a += s[k] * w[k] * dot(g[k], g[k]);
    }
    return compliant_multiplier(c, a, 0.0, pc.dt, 0.0, 0.0, pc.epsilon);
}

#ifdef BLOCK
#define BLOCK_ARITY 4u

void block_prepare(uint t, uvec4 corner) {}

float block_solve(uint t, uvec4 corner, out vec3 force[4]) {
    vec3 q[4];
    float w[4];
    float s[4];
    for (uint j = 0u; j < 4u; ++j) {
        uint l = corner[j];
        w[j] = s_x[l].w;
        s[j] = s_v[l].w;
        q[j] = end_position(s_x[l].xyz, s_v[l].xyz, s_f[l].xyz, w[j], pc.dt);
    }
    vec3 g[4];
    float lambda = floor_multiplier(t, q, w, s, g);
    for (uint j = 0u; j < 4u; ++j) {
        force[j] = -lambda * g[j];
    }
    return lambda;
}
#include "common/block_sweep.glsl"
#else
void main() {
    uint position;
    uint t;
    if (!constraint_of_invocation(gl_GlobalInvocationID.x, pc.tet_count, position, t)) {
        return;
    }
    uvec4 tet = tets[t];
    vec3 q[4];
    float w[4];
    float s[4];
    for (int k = 0; k < 4; ++k) {
        uint node = tet[k];
        vec4 x = positions[node];
        w[k] = x.w;
        s[k] = combine_a_scale(pc.combine, degrees[group_node(node)]);
        q[k] = end_position(x.xyz, velocities[node].xyz, forces[node].xyz, x.w, pc.dt);
    }
    vec3 g[4];
    float lambda = floor_multiplier(t, q, w, s, g);
    for (uint k = 0u; k < 4u; ++k) {
        constraint_output(position, 4u, k, tet[k], -lambda * g[k], lambda != 0.0);
    }
}
#endif
