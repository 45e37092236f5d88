#version 460
// Pass `elastic_linearise` (finite elements, per tet; docs/GPU.md, "Finite elements on the
// GPU"), at each linearisation (`elastic_linearises`): tet t's stiffness where its corners
// end the step so far (ElasticNodes' AT plane), the step's first linearisation (iteration
// 0) taking it anew, a later one keeping the one stored where F moved by at most
// KEPT_STIFFNESS_STRAIN (physics/stiffness.glsl); then the stiffness times the corners' velocities over the step so far, (AT - x) / dt, at
// each corner into ElasticCorners: the Rayleigh damping's shares of K v, which
// `elastic_rows` gathers. The twin of the linearisation in cpu-ref's
// `conjugate_gradients` (src/backend/cpu/reference/elastic.rs).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"
#include "common/elastic_tets.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) readonly restrict buffer ElasticNodesBuffer { vec4 nodes[]; };
layout(std430, set = 0, binding = B_ELASTIC_LINEAR) restrict buffer ElasticLinearBuffer { vec4 linear[]; };
layout(std430, set = 0, binding = B_ELASTIC_CORNERS) writeonly restrict buffer ElasticCornersBuffer { vec4 corners[]; };

void main() {
    if (!elastic_linearises()) {
        return;
    }
    uint t = gl_GlobalInvocationID.x;
    if (t >= pc.tet_count) {
        return;
    }
    uvec4 tet = tets[t];
    ElasticTet e = elastic_tet_at(t);
    uint at = ELASTIC_PLANE_AT * pc.node_count;
    vec3 p0 = nodes[at + tet.x].xyz;
    vec3 p1 = nodes[at + tet.y].xyz;
    vec3 p2 = nodes[at + tet.z].xyz;
    vec3 p3 = nodes[at + tet.w].xyz;
    ElasticLinear lin;
    if (pc.iteration == 0u) {
        lin = elastic_linearise(e, p0, p1, p2, p3);
    } else {
        ElasticLinear kept = elastic_linear_of(linear[6u * t], linear[6u * t + 1u], linear[6u * t + 2u],
                                               linear[6u * t + 3u], linear[6u * t + 4u], linear[6u * t + 5u]);
        lin = elastic_relinearise(e, p0, p1, p2, p3, kept);
    }
    linear[6u * t] = vec4(lin.f0, lin.k.x);
    linear[6u * t + 1u] = vec4(lin.f1, lin.k.y);
    linear[6u * t + 2u] = vec4(lin.f2, lin.k.z);
    linear[6u * t + 3u] = vec4(lin.c0, lin.k.w);
    linear[6u * t + 4u] = vec4(lin.c1, 0.0);
    linear[6u * t + 5u] = vec4(lin.c2, 0.0);
    float rate = 1.0 / pc.dt;
    vec3 q0, q1, q2, q3;
    elastic_product_strain(e, lin, (p0 - positions[tet.x].xyz) * rate, (p1 - positions[tet.y].xyz) * rate,
                           (p2 - positions[tet.z].xyz) * rate, (p3 - positions[tet.w].xyz) * rate,
                           q0, q1, q2, q3);
    corners[4u * t] = vec4(q0, 0.0);
    corners[4u * t + 1u] = vec4(q1, 0.0);
    corners[4u * t + 2u] = vec4(q2, 0.0);
    corners[4u * t + 3u] = vec4(q3, 0.0);
}
