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
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/spring.glsl"
#include "physics/implicit.glsl"
#include "common/constraint_output.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_SPRING_DAMPING) readonly restrict buffer SpringDamping { float spring_damping[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };
layout(std430, set = 0, binding = B_SPRING_MULTIPLIERS) restrict buffer SpringMultipliers { float spring_multipliers[]; };

void main() {
    uint position;
    uint s;
    if (!constraint_of_invocation(gl_GlobalInvocationID.x, pc.spring_count, position, s)) {
        return;
    }
    Spring sp = springs[s];
    vec4 xa = positions[sp.a];
    vec4 xb = positions[sp.b];
    vec3 ga;
    vec3 gb;
    float c = spring_constraint(xa.xyz, xb.xyz, sp.rest, ga, gb);
    float a = 0.0;
    float b = 0.0;
    implicit_accumulate(a, b, ga, xa.w, combine_a_scale(pc.combine, degrees[group_node(sp.a)]), velocities[sp.a].xyz, forces[sp.a].xyz, pc.dt);
    implicit_accumulate(a, b, gb, xb.w, combine_a_scale(pc.combine, degrees[group_node(sp.b)]), velocities[sp.b].xyz, forces[sp.b].xyz, pc.dt);
    float damping = spring_damping[s];
    float softness = spring_softness(sp.stiffness, damping, pc.dt);
    float so_far = multiplier_so_far(spring_multipliers[s], pc.iteration, pc.warm_start);
    float lambda = compliant_multiplier(c, a, b - softness * so_far, pc.dt, softness, damping, pc.epsilon);
    spring_multipliers[s] = so_far + pc.omega * lambda;
    constraint_output(position, 2u, 0u, sp.a, -lambda * ga, lambda != 0.0);
    constraint_output(position, 2u, 1u, sp.b, -lambda * gb, lambda != 0.0);
}
