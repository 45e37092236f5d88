// Distance constraint, squared form (physics.md, paper Eq. 6), mirroring src/physics:
//   C = |x_i - x_j|^2 - L^2,  grad_i C = 2 (x_i - x_j),  grad_j C = -grad_i C.
#ifndef PHYSICS_DISTANCE_GLSL
#define PHYSICS_DISTANCE_GLSL

float distance_value(vec3 xi, vec3 xj, float rest) {
    vec3 d = xi - xj;
    return dot(d, d) - rest * rest;
}

vec3 distance_gradient_i(vec3 xi, vec3 xj) {
    return 2.0 * (xi - xj);
}

#endif
