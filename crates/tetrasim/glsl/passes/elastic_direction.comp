#version 460
// Pass `elastic_direction` (finite elements, per node; docs/GPU.md, "Finite elements on the
// GPU"): the next search direction P = Z + beta P, after `elastic_begin` (beta 0 at a
// linearisation: the first direction is Z).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"

layout(std430, set = 0, binding = B_ELASTIC_NODES) restrict buffer ElasticNodesBuffer { vec4 nodes[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
    if (i >= n || state_u[ELASTIC_STATE_DONE] != 0u) {
        return;
    }
    float beta = state[ELASTIC_STATE_BETA];
    vec4 z = nodes[ELASTIC_PLANE_Z * n + i];
    nodes[ELASTIC_PLANE_P * n + i] = beta == 0.0 ? z : z + nodes[ELASTIC_PLANE_P * n + i] * beta;
}
