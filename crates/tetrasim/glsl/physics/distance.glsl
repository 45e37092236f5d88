// Distance constraint, squared form (physics.md, paper Eq. 6), mirroring src/physics:
//   C = |x_i - x_j|^2 - L^2,  grad_i C = 2 (x_i - x_j),  grad_j C = -grad_i C.
#ifndef PHYSICS_DISTANCE_GLSL
#define PHYSICS_DISTANCE_GLSL

// C and its gradients (distance_constraint in src/physics/constraint.rs).
float distance_constraint(vec3 xi, vec3 xj, float rest, out vec3 gi, out vec3 gj) {
    vec3 d = xi - xj;
    gi = d * 2.0;
    gj = d * -2.0;
    return dot(d, d) - rest * rest;
}

#endif
