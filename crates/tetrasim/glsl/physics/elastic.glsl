// Finite elements (physics.md, fourth edition): stable Neo-Hookean's gradient and Hessian
// block at one corner of a tet, and the force the next step starts from. The twin of src/physics/elastic.rs (same names, same order of
// operations).
#ifndef PHYSICS_ELASTIC_GLSL
#define PHYSICS_ELASTIC_GLSL

// Corner a's shape gradient: rows g1..g3, corner 0 their negative sum.
vec3 elastic_gradient(vec3 g1, vec3 g2, vec3 g3, uint a) {
    if (a == 0u) {
        return -(g1 + g2 + g3);
    }
    return a == 1u ? g1 : (a == 2u ? g2 : g3);
}

// dE/dx_a = V0 P(F) g_a added to `grad`, the Hessian block d2E/dx_a2 to `h` (xx yy zz in
// h0, xy xz yz in h1). mu, lambda: mu_s, lambda_s; alpha: the rest J.
void elastic_corner(vec3 p0, vec3 p1, vec3 p2, vec3 p3, vec3 g1, vec3 g2, vec3 g3,
                    float volume, float mu, float lambda, float alpha, uint a,
                    inout vec3 grad, inout vec3 h0, inout vec3 h1) {
    vec3 e0 = p1 - p0;
    vec3 e1 = p2 - p0;
    vec3 e2 = p3 - p0;
    vec3 f0 = e0 * g1.x + e1 * g2.x + e2 * g3.x;
    vec3 f1 = e0 * g1.y + e1 * g2.y + e2 * g3.y;
    vec3 f2 = e0 * g1.z + e1 * g2.z + e2 * g3.z;
    vec3 c0 = cross(f1, f2);
    vec3 c1 = cross(f2, f0);
    vec3 c2 = cross(f0, f1);
    float j = dot(f0, c0);
    float ic = dot(f0, f0) + dot(f1, f1) + dot(f2, f2);
    vec3 g = elastic_gradient(g1, g2, g3, a);
    vec3 u = f0 * g.x + f1 * g.y + f2 * g.z;
    vec3 w = c0 * g.x + c1 * g.y + c2 * g.z;
    float s = 1.0 / (ic + 1.0);
    float shear = mu * (1.0 - s);
    grad += (u * shear + w * (lambda * (j - alpha))) * volume;
    float d = volume * shear * dot(g, g);
    float cu = volume * 2.0 * mu * s * s;
    float cw = volume * lambda;
    h0 += vec3(d) + cu * u * u + cw * w * w;
    h1 += cu * vec3(u.x * u.y, u.x * u.z, u.y * u.z) + cw * vec3(w.x * w.y, w.x * w.z, w.y * w.z);
}

// The force that starts the next step's solve beside gravity's (elastic_start in Rust): a
// node whose total force this step was `total` (mass `mass`, gravity `gravity`) keeps only
// what it fell along gravity, never faster than free fall.
vec3 elastic_start(vec3 total, float mass, vec3 gravity) {
    float g = length(gravity);
    if (!(g > 0.0 && mass > 0.0)) {
        return vec3(0.0);
    }
    vec3 down = gravity / g;
    float along = min(max(dot(total, down) / mass, 0.0), g);
    return (down * along - gravity) * mass;
}

#endif
