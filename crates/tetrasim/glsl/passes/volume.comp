#version 460
// Pass `volume`: one Jacobi sweep of the implicit volume constraint over one constraint
// group (physics.md), one invocation per tet. Reads x(t), v(t) and the step's current F;
// hard, or compliant with the tet's compliance alpha_t (volume_softness, no damping; then
// lambda is the increment of the tet's multiplier so far in the step, B - s lambda, kept in
// VolumeMultipliers, 0 in iteration 0, growing by omega lambda).
// Variants `ext`/`cas` (the paper's Jacobi, one group): add -lambda grad_k C to the four
// nodes' constraint sums with float atomics. Variant `gather` (Gauss-Seidel by colour
// groups, no atomics): solve group pc.group's tets and write -lambda grad_k C into the
// tet's four contribution slots; `constraint_apply#gather` sums them per node.
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
// @variant gather: GATHER
// Variant `block` (block Gauss-Seidel, physics.md): one workgroup per block of the sweep's
// one group, colour after colour in shared memory (common/block_sweep.glsl).
// @variant block: GATHER BLOCK
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/volume.glsl"
#include "physics/implicit.glsl"
#include "common/constraint_output.glsl"
#include "common/block.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_REST_VOLUMES) readonly restrict buffer RestVolumes { float rest_volumes[]; };
layout(std430, set = 0, binding = B_VOLUME_COMPLIANCE) readonly restrict buffer VolumeCompliance { float volume_compliance[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };
layout(std430, set = 0, binding = B_VOLUME_MULTIPLIERS) restrict buffer VolumeMultipliers { float volume_multipliers[]; };

// The multiplier of tet t with value c, softness `softness` (0: hard; otherwise with its
// multiplier so far) and gradients g on nodes of inverse mass w[k], a-scale s[k], velocity
// v[k] and force f[k].
float tet_multiplier(uint t, float c, float softness, vec3 g[4], float w[4], float s[4], vec3 v[4], vec3 f[4]) {
    float a = 0.0;
    float b = 0.0;
    for (int k = 0; k < 4; ++k) {
        implicit_accumulate(a, b, g[k], w[k], s[k], v[k], f[k], pc.dt);
    }
    float so_far = 0.0;
    if (softness > 0.0) {
#ifdef BLOCK
        so_far = multiplier_so_far(volume_multipliers[t], block_iteration(), 0u);
#else
        so_far = multiplier_so_far(volume_multipliers[t], pc.iteration, 0u);
#endif
    } else {
        c = solve_hard(pc.phase, c);
    }
    float lambda = compliant_multiplier(c, a, b - softness * so_far, pc.dt, softness, 0.0, pc.epsilon);
    if (softness > 0.0) {
        volume_multipliers[t] = so_far + pc.omega * lambda;
    }
    return lambda;
}

#ifdef BLOCK
#define BLOCK_ARITY 4u
// The tet's value, gradients (at x(t), from the block's copies) and softness.
float b_c;
vec3 b_g[4];
float b_softness;

void block_prepare(uint t, uvec4 corner) {
    b_c = volume_constraint(s_x[corner.x].xyz, s_x[corner.y].xyz, s_x[corner.z].xyz, s_x[corner.w].xyz, rest_volumes[t], b_g[0], b_g[1], b_g[2], b_g[3]);
    b_softness = volume_softness(volume_compliance[t], pc.dt);
}

float block_solve(uint t, uvec4 corner, out vec3 force[4]) {
    float w[4];
    float s[4];
    vec3 v[4];
    vec3 f[4];
    for (uint j = 0u; j < 4u; ++j) {
        uint l = corner[j];
        w[j] = s_x[l].w;
        s[j] = s_v[l].w;
        v[j] = s_v[l].xyz;
        f[j] = s_f[l].xyz;
    }
    float lambda = tet_multiplier(t, b_c, b_softness, b_g, w, s, v, f);
    for (uint j = 0u; j < 4u; ++j) {
        force[j] = -lambda * b_g[j];
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
    vec4 p[4] = vec4[4](positions[tet.x], positions[tet.y], positions[tet.z], positions[tet.w]);
    vec3 g[4];
    float c = volume_constraint(p[0].xyz, p[1].xyz, p[2].xyz, p[3].xyz, rest_volumes[t], g[0], g[1], g[2], g[3]);
    float w[4];
    float s[4];
    vec3 v[4];
    vec3 f[4];
    for (int k = 0; k < 4; ++k) {
        uint node = tet[k];
        w[k] = p[k].w;
        s[k] = combine_a_scale(pc.combine, degrees[group_node(node)]);
        v[k] = velocities[node].xyz;
        f[k] = forces[node].xyz;
    }
    float softness = volume_softness(volume_compliance[t], pc.dt);
    float lambda = tet_multiplier(t, c, softness, g, w, s, v, f);
    for (uint k = 0u; k < 4u; ++k) {
        constraint_output(position, 4u, k, tet[k], -lambda * g[k], lambda != 0.0);
    }
}
#endif
