#version 460
// Pass `distance`: one Jacobi iteration of the implicit distance constraint (physics.md),
// one invocation per spring. Reads x(t), v(t) and the step's current F; adds -lambda grad C
// to both nodes' constraint sums with float atomics (`constraint_apply` then folds the sums
// into F).
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
#include "common/version.glsl"
#include "common/atomics.glsl"
#include "common/bindings.glsl"
#include "physics/distance.glsl"
#include "physics/implicit.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_SUM) buffer SumF { float sum_f[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_SUM) buffer SumU { uint sum_u[]; };
DECLARE_ATOMIC_ADD_CAS(sum_u)

void main() {
    uint s = gl_GlobalInvocationID.x;
    if (s >= pc.spring_count) {
        return;
    }
    Spring sp = springs[s];
    vec4 xa = positions[sp.a];
    vec4 xb = positions[sp.b];
    vec3 ga = distance_gradient_i(xa.xyz, xb.xyz);
    float a = 0.0;
    float b = 0.0;
    implicit_accumulate(a, b, ga, xa.w, combine_a_scale(pc.combine, degrees[sp.a]), velocities[sp.a].xyz, forces[sp.a].xyz, pc.dt);
    implicit_accumulate(a, b, -ga, xb.w, combine_a_scale(pc.combine, degrees[sp.b]), velocities[sp.b].xyz, forces[sp.b].xyz, pc.dt);
    float lambda = implicit_lambda(distance_value(xa.xyz, xb.xyz, sp.rest), a, b, pc.dt, pc.epsilon);
    if (lambda != 0.0) {
        ATOMIC_ADD_VEC3(sum_f, sum_u, sp.a, -lambda * ga);
        ATOMIC_ADD_VEC3(sum_f, sum_u, sp.b, lambda * ga);
    }
}
