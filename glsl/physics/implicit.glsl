// Implicit constraint multiplier (physics.md Eqs. 13-17 and "Momentum-conserving scaling"),
// mirroring src/physics:
//   A = sum_k s_k w_k |grad_k C|^2,  B = C / dt^2 + sum_k grad_k C . (v_k / dt + w_k F_k),
//   lambda = B / A; the force on node k is -lambda grad_k C. The constraint is skipped
//   (lambda = 0) when A <= epsilon or A is not finite, as src/physics/constraint.rs does.
#ifndef PHYSICS_IMPLICIT_GLSL
#define PHYSICS_IMPLICIT_GLSL

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

// lambda from the constraint value and the accumulated A and B sums (0, i.e. skip, where
// Rust's implicit_multiplier returns None).
float implicit_multiplier(float c, float a, float b, float dt, float epsilon) {
    if (!(a > epsilon) || isinf(a)) {
        return 0.0;
    }
    return (c / (dt * dt) + b) / a;
}

#endif
