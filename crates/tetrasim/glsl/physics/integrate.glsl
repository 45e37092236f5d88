// Time integration and the floor (physics.md, "Time integration" and "Contact without false
// restitution"), mirroring src/physics/integrate.rs function by function: the floor y = 0 as
// a one-sided constraint on one node, solved exactly (no position is projected, no correction
// becomes velocity), and symplectic Euler with floor friction.
#ifndef PHYSICS_INTEGRATE_GLSL
#define PHYSICS_INTEGRATE_GLSL

// The floor's normal force [N] on a node at height y [m] with vertical velocity vy [m/s],
// other vertical force fy_other [N] and inverse mass w [1/kg]: the smallest n >= 0 with
// y + dt (vy + dt w (fy_other + n)) >= 0. Pinned nodes (w = 0) get none.
float floor_force(float y, float vy, float fy_other, float w, float dt) {
    if (!(w > 0.0)) {
        return 0.0;
    }
    return max(-(y + dt * vy) / (dt * dt * w) - fy_other, 0.0);
}

// Re-solves the floor force against a node's total force f, whose w component holds the
// floor force found so far (it is part of f.y); returns f with both updated (Rust's
// floor_solve takes and returns the force and n separately).
vec4 floor_solve(vec4 f, float y, float vy, float w, float dt) {
    float other = f.y - f.w;
    float n = floor_force(y, vy, other, w, dt);
    return vec4(f.x, other + n, f.z, n);
}

// Friction bounded by Coulomb's law (mu = friction) on a velocity relative to the surface:
// its part tangential to `normal` loses `friction` of itself but never more than
// friction * pressed, the velocity the contact's force gave the node along the normal in the
// step (n w dt); the normal part is kept.
vec3 coulomb_friction(vec3 relative, vec3 normal, float friction, float pressed) {
    vec3 normal_part = normal * dot(relative, normal);
    vec3 sliding = relative - normal_part;
    float speed = length(sliding);
    float removed = speed > pressed ? friction * pressed / speed : friction;
    return normal_part + sliding * (1.0 - removed);
}

// Friction of a node on the floor: coulomb_friction about the up direction, `pressed` the
// velocity its floor force n gave it in the step (n w dt).
vec3 floor_friction(vec3 v, float friction, float pressed) {
    return coulomb_friction(v, vec3(0.0, 1.0, 0.0), friction, pressed);
}

// Symplectic Euler with floor friction: v' = v + dt w F; a node on the floor (floor force
// n > 0) gets floor_friction with pressed = n w dt; then x' = x + dt v'. Returns v' and
// writes x' to x.
vec3 integrate_node(inout vec3 x, vec3 v, vec3 f, float w, float dt, float n, float friction) {
    vec3 v1 = v + dt * w * f;
    if (n > 0.0) {
        v1 = floor_friction(v1, friction, n * w * dt);
    }
    x += dt * v1;
    return v1;
}

#endif
