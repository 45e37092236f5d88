// Spring force (physics.md Eq. 1), mirroring src/physics: the force on node i of the spring
// (i, j); the force on j is its negation. A zero-length spring exerts no force.
#ifndef PHYSICS_SPRING_GLSL
#define PHYSICS_SPRING_GLSL

vec3 spring_force(vec3 xi, vec3 xj, vec3 vi, vec3 vj, float rest, float ks, float kd) {
    vec3 d = xj - xi;
    float l = length(d);
    if (l <= 0.0) {
        return vec3(0.0);
    }
    vec3 n = d / l;
    return (ks * (l - rest) + kd * dot(vj - vi, n)) * n;
}

#endif
