// Springs (physics.md Eq. 1 and "Compliant (implicit) springs"), mirroring src/physics.
#ifndef PHYSICS_SPRING_GLSL
#define PHYSICS_SPRING_GLSL

// Explicit spring force (spring_force in src/physics/spring.rs): the force on node i of the
// spring (i, j); the force on j is its negation. A zero-length spring exerts no force.
vec3 spring_force(vec3 xi, vec3 xj, vec3 vi, vec3 vj, float rest, float ks, float kd) {
    vec3 d = xj - xi;
    float l = length(d);
    if (l <= 0.0) {
        return vec3(0.0);
    }
    vec3 n = d / l;
    return (ks * (l - rest) + kd * dot(vj - vi, n)) * n;
}

// An implicit spring's constraint (spring_constraint in src/physics/constraint.rs):
// C = |x_i - x_j| - L [m], gradients n and -n with n = (x_i - x_j) / |x_i - x_j| (zero for a
// spring of zero length, which is then skipped, as its A is 0).
float spring_constraint(vec3 xi, vec3 xj, float rest, out vec3 gi, out vec3 gj) {
    vec3 d = xi - xj;
    float l = length(d);
    if (l <= 0.0) {
        gi = vec3(0.0);
        gj = vec3(0.0);
        return -rest;
    }
    vec3 n = d * (1.0 / l);
    gi = n;
    gj = -n;
    return l - rest;
}

#endif
