// The body of pass `elastic_curvature` (finite elements, per node, every conjugate-gradient iteration;
// docs/GPU.md, "Finite elements on the GPU"): node i's entry of the Newton matrix times the
// search direction, q_i = m/dt^2 p_i + h (h . p_i) + (1 + beta/dt) (K p)_i (K p gathered
// from `elastic_product`'s corners; zero for a pinned node), into the Q plane, and its share
// of the curvature p . q as its workgroup's partial (`elastic_alpha` adds them). The
// twin of ElasticNodes::product (src/schedule/family/elastic.rs).
// With CORRECTION (`elastic_correction_curvature`): the rigid-part correction's moves (in P)
// at the last iteration, whether or not the solve is done.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#define NODE_TETS
#include "common/elastic_tets.glsl"
#include "common/elastic_state.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_ELASTIC_CORNERS) readonly restrict buffer ElasticCornersBuffer { vec4 corners[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) restrict buffer ElasticNodesBuffer { vec4 nodes[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
#ifdef CORRECTION
    bool done = false;
#else
    bool done = state_u[ELASTIC_STATE_DONE] != 0u;
#endif
    float share = 0.0;
    if (i < n && !done) {
        vec3 p = nodes[ELASTIC_PLANE_P * n + i].xyz;
        vec3 q = vec3(0.0);
        if (positions[i].w > 0.0) {
            uint first = node_tet_offsets[i];
            uint end = node_tet_offsets[i + 1u];
            float beta = node_damping(i);
            vec3 k = vec3(0.0);
            for (uint item = first; item < end; ++item) {
                k += corners[node_tet_items[item]].xyz;
            }
            vec3 h = nodes[ELASTIC_PLANE_HELD * n + i].xyz;
            q = node_increment(velocities[i].w, pc.dt, h, p, 1.0) + k * (1.0 + beta / pc.dt);
        }
        nodes[ELASTIC_PLANE_Q * n + i] = vec4(q, 0.0);
        share = dot(p, q);
    }
    store_partial(share);
}
