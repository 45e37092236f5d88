// The body of pass `elastic_product` (finite elements, per tet, every conjugate-gradient iteration;
// docs/GPU.md, "Finite elements on the GPU"): the tet's stiffness times its corners' search
// directions (ElasticNodes' P plane) into ElasticCorners, and the strain that direction makes
// in it (the Frobenius norm of dF) raised into the state's largest (`atomicMax` of the
// float's bits: non-negative floats order as their bits do). The product half of cpu-ref's
// `elastic_product_strain` loop (src/backend/cpu/reference/elastic.rs).
// With CORRECTION (`elastic_correction_product`): the rigid-part correction's moves (in P)
// at the last iteration, whether or not the solve is done.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_tets.glsl"
#include "common/elastic_state.glsl"

layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) readonly restrict buffer ElasticNodesBuffer { vec4 nodes[]; };
layout(std430, set = 0, binding = B_ELASTIC_LINEAR) readonly restrict buffer ElasticLinearBuffer { vec4 linear[]; };
layout(std430, set = 0, binding = B_ELASTIC_CORNERS) writeonly restrict buffer ElasticCornersBuffer { vec4 corners[]; };

void main() {
    uint t = gl_GlobalInvocationID.x;
#ifdef CORRECTION
    bool done = false;
#else
    bool done = state_u[ELASTIC_STATE_DONE] != 0u;
#endif
    if (t >= pc.tet_count || done) {
        return;
    }
    uvec4 tet = tets[t];
    ElasticTet e = elastic_tet_at(t);
    ElasticLinear lin = elastic_linear_of(linear[6u * t], linear[6u * t + 1u], linear[6u * t + 2u],
                                          linear[6u * t + 3u], linear[6u * t + 4u], linear[6u * t + 5u]);
    uint p = ELASTIC_PLANE_P * pc.node_count;
    vec3 q0, q1, q2, q3;
    float strain = elastic_product_strain(e, lin, nodes[p + tet.x].xyz, nodes[p + tet.y].xyz,
                                          nodes[p + tet.z].xyz, nodes[p + tet.w].xyz, q0, q1, q2, q3);
    corners[4u * t] = vec4(q0, 0.0);
    corners[4u * t + 1u] = vec4(q1, 0.0);
    corners[4u * t + 2u] = vec4(q2, 0.0);
    corners[4u * t + 3u] = vec4(q3, 0.0);
    atomicMax(state_u[ELASTIC_STATE_STRAIN], floatBitsToUint(strain));
}
