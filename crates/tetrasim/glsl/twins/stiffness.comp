#version 460
// A twin check, not a pass: runs physics/stiffness.glsl on pc.node_count cases so that
// tests/gpu_elastic_twin.rs can compare it with src/physics/stiffness.rs in f64. Binding 0
// holds 16 vec4 per case: the tet's constants ((g1, V0), (g2, mu_s), (g3, lambda_s),
// (alpha, 0, 0, 0)), positions p0..p3, corner moves d0..d3 and later positions q0..q3.
// Binding 1 receives 10 vec4 per case: the product at p's stiffness with d (4 corners);
// (its strain, the energy at p, p's volume term, the volume term kept or retaken at q);
// the product of q's stiffness (elastic_relinearise, kept from p) with d (4 corners);
// (the energy at q, 0, 0, 0).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/stiffness.glsl"

layout(std430, set = 0, binding = 0) readonly restrict buffer Cases { vec4 cases[]; };
layout(std430, set = 0, binding = 1) writeonly restrict buffer Results { vec4 results[]; };

void main() {
    uint c = gl_GlobalInvocationID.x;
    if (c >= pc.node_count) {
        return;
    }
    uint at = 16u * c;
    ElasticTet t;
    t.g1 = cases[at].xyz;
    t.volume = cases[at].w;
    t.g2 = cases[at + 1u].xyz;
    t.mu = cases[at + 1u].w;
    t.g3 = cases[at + 2u].xyz;
    t.lambda = cases[at + 2u].w;
    t.alpha = cases[at + 3u].x;
    vec3 p[4];
    vec3 d[4];
    vec3 q[4];
    for (uint k = 0u; k < 4u; ++k) {
        p[k] = cases[at + 4u + k].xyz;
        d[k] = cases[at + 8u + k].xyz;
        q[k] = cases[at + 12u + k].xyz;
    }
    ElasticLinear lin = elastic_linearise(t, p[0], p[1], p[2], p[3]);
    vec3 r0, r1, r2, r3;
    float strain = elastic_product_strain(t, lin, d[0], d[1], d[2], d[3], r0, r1, r2, r3);
    uint out_at = 10u * c;
    results[out_at] = vec4(r0, 0.0);
    results[out_at + 1u] = vec4(r1, 0.0);
    results[out_at + 2u] = vec4(r2, 0.0);
    results[out_at + 3u] = vec4(r3, 0.0);
    ElasticLinear later = elastic_relinearise(t, q[0], q[1], q[2], q[3], lin);
    results[out_at + 4u] = vec4(strain, elastic_energy(t, p[0], p[1], p[2], p[3]), lin.k.w, later.k.w);
    elastic_product_strain(t, later, d[0], d[1], d[2], d[3], r0, r1, r2, r3);
    results[out_at + 5u] = vec4(r0, 0.0);
    results[out_at + 6u] = vec4(r1, 0.0);
    results[out_at + 7u] = vec4(r2, 0.0);
    results[out_at + 8u] = vec4(r3, 0.0);
    results[out_at + 9u] = vec4(elastic_energy(t, q[0], q[1], q[2], q[3]), 0.0, 0.0, 0.0);
}
