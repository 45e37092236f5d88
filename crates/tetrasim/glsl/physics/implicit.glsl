// Implicit constraint multiplier (physics.md Eqs. 13-17 and "Momentum-conserving scaling"),
// mirroring src/physics:
//   A = sum_k s_k w_k |grad_k C|^2,  B = C / dt^2 + sum_k grad_k C . (v_k / dt + w_k F_k),
//   lambda = B / A (hard) or (B - kd s C / dt) / (A + s) (compliant, softness s, damping kd);
//   the force on node k is -lambda grad_k C. The constraint is skipped
//   (lambda = 0) when A <= epsilon or A is not finite, as src/physics/constraint.rs does.
#ifndef PHYSICS_IMPLICIT_GLSL
#define PHYSICS_IMPLICIT_GLSL

#include "physics/solve.glsl"

// The two per-node factors of ConstraintCombine::node_factors for a node touched by
// `degree` constraints: the scale s_k of its inverse mass in A, and the weight of its summed
// constraint forces.
float combine_a_scale(uint combine, float degree) {
    return combine == COMBINE_SCALED ? max(degree, 1.0) : 1.0;
}
float combine_apply_weight(uint combine, float degree) {
    return combine == COMBINE_AVERAGE ? 1.0 / max(degree, 1.0) : 1.0;
}

// Adds node k's terms to A and to the sum part of B; s is combine_a_scale of the node.
void implicit_accumulate(inout float a, inout float b, vec3 grad, float w, float s, vec3 v, vec3 f, float dt) {
    a += s * w * dot(grad, grad);
    b += dot(grad, v / dt + w * f);
}

// The direction a node's contacts hold it along (held_direction in
// src/physics/constraint.rs): +Y where the floor pushes it, else the direction of the
// colliders' force on it, else 0.
vec3 held_direction(bool floor_pushes, vec3 collider_force) {
    if (floor_pushes) {
        return vec3(0.0, 1.0, 0.0);
    }
    return collider_force != vec3(0.0) ? normalize(collider_force) : vec3(0.0);
}

// The part of a global volume constraint's A that a contact takes from a surface node it
// holds along `held` (contact_held in src/physics/constraint.rs): w (g . held)^2 where the
// gradient points into the contact, else 0.
float contact_held(vec3 grad, float w, vec3 held) {
    float along = dot(grad, held);
    return along < 0.0 ? w * along * along : 0.0;
}

// The multiplier of a compliant, damped constraint (compliant_multiplier in
// src/physics/constraint.rs): lambda = (C / dt^2 + b - damping s C / dt) / (A + s) with the
// softness s of spring_softness or volume_softness (0: hard); 0 (skip) where Rust returns
// None (A <= epsilon or not finite).
float compliant_multiplier(float c, float a, float b, float dt, float softness, float damping, float epsilon) {
    if (!(a > epsilon) || isinf(a)) {
        return 0.0;
    }
    return (c / (dt * dt) + b - damping * softness * c / dt) / (a + softness);
}

// The multiplier accumulated so far in this step by a compliant constraint whose stored
// value is `stored` (iteration 0 starts the step: whatever is stored is the last step's,
// which counts only when the step is warm-started with it, `warm` != 0: then
// `spring_warm_start` has already applied it as a force).
float multiplier_so_far(float stored, uint iteration, uint warm) {
    return iteration == 0u && warm == 0u ? 0.0 : stored;
}

// lambda of a hard constraint from its value and the accumulated A and B sums
// (implicit_multiplier: compliant_multiplier with softness 0).
float implicit_multiplier(float c, float a, float b, float dt, float epsilon) {
    return compliant_multiplier(c, a, b, dt, 0.0, 0.0, epsilon);
}

// The multiplier of a global volume constraint (global_multiplier in
// src/physics/constraint.rs): A less the contacts' held terms when the push is outward
// (c / dt^2 + b < 0).
float global_multiplier(float c, float a, float b, float held, float dt, float epsilon) {
    float a_free = c / (dt * dt) + b < 0.0 ? a - held : a;
    return implicit_multiplier(c, a_free, b, dt, epsilon);
}

// Softness 1 / (k dt^2 + kd dt) [1/kg] of a spring of stiffness k and damping kd solved as
// a compliant constraint (spring_softness).
float spring_softness(float stiffness, float damping, float dt) {
    return 1.0 / (stiffness * dt * dt + damping * dt);
}

// Softness alpha / dt^2 of a volume constraint of compliance alpha [m^3/Pa] (0: hard;
// volume_softness).
float volume_softness(float compliance, float dt) {
    return compliance / (dt * dt);
}

#endif
