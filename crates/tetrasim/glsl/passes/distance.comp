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
// Variant `block` (block Gauss-Seidel, physics.md): one workgroup per block of the sweep's
// one group, colour after colour in shared memory (common/block_sweep.glsl).
// @variant block: GATHER BLOCK
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/distance.glsl"
#include "physics/implicit.glsl"
#include "common/constraint_output.glsl"
#include "common/block.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };

// The multiplier of a hard distance constraint with value c and gradients g on nodes of
// inverse mass w[k], a-scale sc[k], velocity v[k] and force f[k].
float distance_multiplier(float c, vec3 g[2], float w[2], float sc[2], vec3 v[2], vec3 f[2]) {
    float a = 0.0;
    float b = 0.0;
    for (int k = 0; k < 2; ++k) {
        implicit_accumulate(a, b, g[k], w[k], sc[k], v[k], f[k], pc.dt);
    }
    return implicit_multiplier(solve_hard(pc.phase, c), a, b, pc.dt, pc.epsilon);
}

#ifdef BLOCK
#define BLOCK_ARITY 2u
// The constraint's value and gradients (at x(t), from the block's copies).
float b_c;
vec3 b_g[2];

void block_prepare(uint s, uvec4 corner) {
    b_c = distance_constraint(s_x[corner.x].xyz, s_x[corner.y].xyz, springs[s].rest, b_g[0], b_g[1]);
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
    float lambda = distance_multiplier(b_c, b_g, w, sc, v, f);
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
    float c = distance_constraint(x[0].xyz, x[1].xyz, sp.rest, g[0], g[1]);
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
    float lambda = distance_multiplier(c, g, w, sc, v, f);
    constraint_output(position, 2u, 0u, sp.a, -lambda * g[0], lambda != 0.0);
    constraint_output(position, 2u, 1u, sp.b, -lambda * g[1], lambda != 0.0);
}
#endif
