// The finite elements' Newton step per node (physics.md, fourth edition; docs/PHYSICS.md,
// "Finite elements"): the node vectors' planes, a tet's stored stiffness, and a node's row of
// the step's system: its diagonal block, stiffened along a contact that holds it, and its
// inverse. The twin of ElasticNodes::newton_row (src/schedule/family/elastic.rs) with
// node_block, sym3_inverse (src/physics/elastic.rs) and held_block (src/physics/held.rs);
// tests/gpu_elastic_rows_twin.rs runs it against them.
#ifndef PHYSICS_NEWTON_GLSL
#define PHYSICS_NEWTON_GLSL

#include "physics/stiffness.glsl"

// HELD_STIFFNESS and HELD_GAP in src/physics/held.rs.
#define HELD_STIFFNESS 1.0e3
#define HELD_GAP 1.0e-3

// The planes of ElasticNodes (a vec4 per node each, plane k of node i at k * N + i).
#define ELASTIC_PLANE_AT 0u        // where the node ends the step so far (the linearisation)
#define ELASTIC_PLANE_Y 1u         // where inertia and gravity alone would take it
#define ELASTIC_PLANE_DX 2u        // the displacement the iterations added to AT
#define ELASTIC_PLANE_R 3u         // the residual
#define ELASTIC_PLANE_Z 4u         // the preconditioned residual
#define ELASTIC_PLANE_P 5u         // the search direction
#define ELASTIC_PLANE_Q 6u         // the system's matrix times P
#define ELASTIC_PLANE_INVERSE_A 7u // the inverse diagonal block: xx yy zz xy
#define ELASTIC_PLANE_INVERSE_B 8u // ... xz yz
#define ELASTIC_PLANE_HELD 9u      // the contact's stiffening h; w: 1 when touching
#define ELASTIC_PLANE_PHI 10u      // the elastic force so far at the linearisation
#define ELASTIC_PLANE_NORMAL 11u   // the direction a contact holds the node along (or 0)
#define ELASTIC_PLANE_SUM 12u      // the iteration's force increment on the node
#define ELASTIC_PLANE_NODE 13u     // fixed: x = the node's reach (1 / its thinnest tet's height)
#define ELASTIC_PLANES 14u

// Words of ElasticState: the conjugate gradients' scalars (floats unless said), then one
// partial sum per workgroup of the node passes from ELASTIC_STATE_PARTIALS on.
#define ELASTIC_STATE_RZ 0u          // r . z
#define ELASTIC_STATE_CURVATURE 1u   // p . A p
#define ELASTIC_STATE_ALPHA 2u       // the step along p
#define ELASTIC_STATE_BETA 3u        // the next direction's share of p
#define ELASTIC_STATE_STRAIN 4u      // uint: the float bits of the largest strain of p's step
#define ELASTIC_STATE_DONE 5u        // uint: 1 once converged or at non-positive curvature
#define ELASTIC_STATE_CHECK 6u       // uint: 1 when alpha p goes beyond the trusted strain
#define ELASTIC_STATE_RELINEARISE 7u // uint: 1 when the next iteration begins a Newton step
#define ELASTIC_STATE_STEP 8u        // uint: the steps taken so far (the coarse level's clock)
#define ELASTIC_STATE_PARTIALS 16u

// TRUSTED_STRAIN, TRUSTED_RATIO and MOST_HALVINGS in src/schedule/family/elastic.rs.
#define TRUSTED_STRAIN 0.01
#define TRUSTED_RATIO 0.5
#define MOST_HALVINGS 8u
// The steps the backtracking tries: alpha and its halvings.
#define BACKTRACK_STEPS (MOST_HALVINGS + 1u)

// The steps the backtracking tries (alpha / 2^k while alpha / 2^k * strain is beyond the
// trust; `backtrack`) into `steps`, their count returned.
uint backtrack_steps(float alpha, float strain, out float steps[9]) {
    uint count = 0u;
    float step = alpha;
    for (uint k = 0u; k < BACKTRACK_STEPS; ++k) {
        steps[k] = step;
        if (step * strain > TRUSTED_STRAIN) {
            count = k + 1u;
        }
        step *= 0.5;
    }
    return count;
}

// A symmetric 3x3 matrix: xx yy zz in a, xy xz yz in b (Sym3's order).
struct Sym3 {
    vec3 a;
    vec3 b;
};

vec3 sym3_apply(Sym3 m, vec3 v) {
    return vec3(m.a.x * v.x + m.b.x * v.y + m.b.y * v.z,
                m.b.x * v.x + m.a.y * v.y + m.b.z * v.z,
                m.b.y * v.x + m.b.z * v.y + m.a.z * v.z);
}

// The node's block m/dt^2 I + (1 + beta/dt) H (`node_block`).
Sym3 node_block(float mass, float dt, float beta, Sym3 hessian) {
    float inertia = mass / (dt * dt);
    float damp = 1.0 + beta / dt;
    return Sym3(hessian.a * damp + vec3(inertia), hessian.b * damp);
}

// The block stiffened along `normal` (unit, or zero) and the stiffening h (`held_block`).
Sym3 held_block(Sym3 block, vec3 normal, out vec3 h) {
    float along = dot(normal, sym3_apply(block, normal));
    if (!(along > 0.0)) {
        h = vec3(0.0);
        return block;
    }
    h = normal * sqrt(HELD_STIFFNESS * along);
    return Sym3(block.a + h * h, block.b + vec3(h.x * h.y, h.x * h.z, h.y * h.z));
}

// The inverse of m (its adjugate over its determinant), false when not positive definite
// enough to invert (`sym3_inverse`).
bool sym3_inverse(Sym3 m, out Sym3 inverse) {
    float a = m.a.x, b = m.a.y, c = m.a.z, d = m.b.x, e = m.b.y, f = m.b.z;
    float c00 = b * c - f * f;
    float c01 = e * f - d * c;
    float c02 = d * f - b * e;
    float det = a * c00 + d * c01 + e * c02;
    if (!(det > 0.0) || isinf(det)) {
        inverse = Sym3(vec3(0.0), vec3(0.0));
        return false;
    }
    float c11 = a * c - e * e;
    float c12 = d * e - a * f;
    float c22 = a * b - d * d;
    float inv = 1.0 / det;
    inverse = Sym3(vec3(c00, c11, c22) * inv, vec3(c01, c02, c12) * inv);
    return true;
}

// The elastic force a move alpha p of a node adds (`ElasticNodes::increment`): its inertia's
// m/dt^2 alpha p and, where a contact holds it (h not zero), the stiffening's h (h . alpha p).
vec3 node_increment(float mass, float dt, vec3 h, vec3 p, float alpha) {
    return p * (alpha * mass / (dt * dt)) + h * (dot(h, p) * alpha);
}

// A held node's increment with the stiffening's share away from the contact cut to what the
// contacts push it with (`held_increment`).
vec3 held_increment(vec3 increment, vec3 h, vec3 d, vec3 pushed) {
    float length_h = length(h);
    if (h == vec3(0.0)) {
        return increment;
    }
    float away = dot(h, d) * length_h;
    float push = dot(h, pushed) / length_h;
    return away > push ? increment - h * ((away - push) / length_h) : increment;
}

// A tet's stiffness from its 6 stored vec4 (ElasticLinear: F's columns with k.x k.y k.z,
// the cofactor's first column with k.w, then its other two).
ElasticLinear elastic_linear_of(vec4 s0, vec4 s1, vec4 s2, vec4 s3, vec4 s4, vec4 s5) {
    ElasticLinear lin;
    lin.f0 = s0.xyz;
    lin.f1 = s1.xyz;
    lin.f2 = s2.xyz;
    lin.c0 = s3.xyz;
    lin.c1 = s4.xyz;
    lin.c2 = s5.xyz;
    lin.k = vec4(s0.w, s1.w, s2.w, s3.w);
    return lin;
}

#endif
