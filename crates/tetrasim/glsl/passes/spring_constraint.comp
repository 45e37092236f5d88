#version 460
// Pass `spring_constraint`: one Jacobi sweep of the implicit (compliant) springs over one
// constraint group (physics.md, "Compliant (implicit) springs"), one invocation per spring.
// Reads x(t), v(t) and the step's current F; C = |x_i - x_j| - L with the compliance
// 1 / k_e and the damping kd_e of the spring's own material (its Spring.stiffness and
// SpringDamping), lambda = compliant_multiplier with spring_softness(k_e, kd_e, dt), solved
// for the increment delta of the spring's multiplier so far in the step (B - s lambda, from
// SpringMultipliers, 0 in iteration 0; with pc.warm_start the stored last step's value,
// which `spring_warm_start` applied as a force), which then grows by omega delta.
// Variants `ext`/`cas` (Jacobi, one group): add -lambda grad C to both nodes' constraint
// sums with float atomics. Variant `gather` (Gauss-Seidel by colour groups, no atomics):
// solve group pc.group's springs and write -lambda grad C into the spring's two
// contribution slots; `constraint_apply#gather` sums them per node.
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
// @variant gather: GATHER
// Variant `block` (block Gauss-Seidel, physics.md): one workgroup per block of the sweep's
// one group, colour after colour in shared memory (common/block_sweep.glsl).
// @variant block: GATHER BLOCK
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/spring.glsl"
#include "physics/implicit.glsl"
#include "common/constraint_output.glsl"
#include "common/block.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_SPRING_DAMPING) readonly restrict buffer SpringDamping { float spring_damping[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };
layout(std430, set = 0, binding = B_SPRING_MULTIPLIERS) restrict buffer SpringMultipliers { float spring_multipliers[]; };

// The multiplier increment of spring s with value c, damping `damping` and softness
// `softness` (multiplier so far `so_far`) and gradients g on nodes of inverse mass w[k],
// a-scale sc[k], velocity v[k] and force f[k]; its multiplier so far grows by omega times it.
float spring_multiplier(uint s, float c, float damping, float softness, float so_far, vec3 g[2], float w[2], float sc[2], vec3 v[2], vec3 f[2]) {
    float a = 0.0;
    float b = 0.0;
    for (int k = 0; k < 2; ++k) {
        implicit_accumulate(a, b, g[k], w[k], sc[k], v[k], f[k], pc.dt);
    }
    float lambda = compliant_multiplier(c, a, b - softness * so_far, pc.dt, softness, damping, pc.epsilon);
    spring_multipliers[s] = so_far + pc.omega * lambda;
    return lambda;
}

#ifdef BLOCK
#define BLOCK_ARITY 2u
// The spring's value and gradients (at x(t), from the block's copies), damping, softness
// and multiplier so far.
float b_c;
vec3 b_g[2];
float b_damping;
float b_softness;
float b_so_far;

void block_prepare(uint s, uvec4 corner) {
    Spring sp = springs[s];
    b_c = spring_constraint(s_x[corner.x].xyz, s_x[corner.y].xyz, sp.rest, b_g[0], b_g[1]);
    b_damping = spring_damping[s];
    b_softness = spring_softness(sp.stiffness, b_damping, pc.dt);
    b_so_far = multiplier_so_far(spring_multipliers[s], pc.iteration, pc.warm_start);
}

float block_solve(uint s, uvec4 corner, out vec3 force[4]) {
    float w[2];
    float sc[2];
    vec3 v[2];
    vec3 f[2];
    for (uint j = 0u; j < 2u; ++j) {
        uint l = corner[j];
        w[j] = s_x[l].w;
        sc[j] = s_v[l].w;
        v[j] = s_v[l].xyz;
        f[j] = s_f[l].xyz;
    }
    float lambda = spring_multiplier(s, b_c, b_damping, b_softness, b_so_far, b_g, w, sc, v, f);
    // The block's next sweep starts from the multiplier this one left.
    b_so_far += pc.omega * lambda;
    force[0] = -lambda * b_g[0];
    force[1] = -lambda * b_g[1];
    force[2] = vec3(0.0);
    force[3] = vec3(0.0);
    return lambda;
}
#include "common/block_sweep.glsl"
#else
void main() {
    uint position;
    uint s;
    if (!constraint_of_invocation(gl_GlobalInvocationID.x, pc.spring_count, position, s)) {
        return;
    }
    Spring sp = springs[s];
    vec4 x[2] = vec4[2](positions[sp.a], positions[sp.b]);
    vec3 g[2];
    float c = spring_constraint(x[0].xyz, x[1].xyz, sp.rest, g[0], g[1]);
    uint node[2] = uint[2](sp.a, sp.b);
    float w[2];
    float sc[2];
    vec3 v[2];
    vec3 f[2];
    for (int k = 0; k < 2; ++k) {
        w[k] = x[k].w;
        sc[k] = combine_a_scale(pc.combine, degrees[group_node(node[k])]);
        v[k] = velocities[node[k]].xyz;
        f[k] = forces[node[k]].xyz;
    }
    float damping = spring_damping[s];
    float softness = spring_softness(sp.stiffness, damping, pc.dt);
    float so_far = multiplier_so_far(spring_multipliers[s], pc.iteration, pc.warm_start);
    float lambda = spring_multiplier(s, c, damping, softness, so_far, g, w, sc, v, f);
    constraint_output(position, 2u, 0u, sp.a, -lambda * g[0], lambda != 0.0);
    constraint_output(position, 2u, 1u, sp.b, -lambda * g[1], lambda != 0.0);
}
#endif
