#version 460
// Pass `distance`: one Jacobi sweep of the implicit distance constraint over one constraint
// group (physics.md), one invocation per spring. Reads x(t), v(t) and the step's current F.
// Variants `ext`/`cas` (the paper's Jacobi, one group): add -lambda grad C to both nodes'
// constraint sums with float atomics. Variant `gather` (Gauss-Seidel by colour groups, no
// atomics): solve group pc.group's springs and write -lambda grad C into the spring's two
// contribution slots; `constraint_apply#gather` sums them per node.
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
// @variant gather: GATHER
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/distance.glsl"
#include "physics/implicit.glsl"
#include "common/constraint_output.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };

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
    float c = distance_constraint(xa.xyz, xb.xyz, sp.rest, ga, gb);
    float a = 0.0;
    float b = 0.0;
    implicit_accumulate(a, b, ga, xa.w, combine_a_scale(pc.combine, degrees[group_node(sp.a)]), velocities[sp.a].xyz, forces[sp.a].xyz, pc.dt);
    implicit_accumulate(a, b, gb, xb.w, combine_a_scale(pc.combine, degrees[group_node(sp.b)]), velocities[sp.b].xyz, forces[sp.b].xyz, pc.dt);
    float lambda = implicit_multiplier(solve_hard(pc.phase, c), a, b, pc.dt, pc.epsilon);
    constraint_output(position, 2u, 0u, sp.a, -lambda * ga, lambda != 0.0);
    constraint_output(position, 2u, 1u, sp.b, -lambda * gb, lambda != 0.0);
}
