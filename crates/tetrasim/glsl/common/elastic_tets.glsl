// The finite elements' per-tet constants (ElasticTets: 4 vec4 per tet, the shape gradients
// of corners 1..3 with V0, mu_s and lambda_s in w, then alpha and the damping time) as an
// ElasticTet, and, in a pass that defines NODE_TETS first, the node -> tet corners CSR and
// each node's damping time. Include after common/bindings.glsl and physics/stiffness.glsl.
#ifndef COMMON_ELASTIC_TETS_GLSL
#define COMMON_ELASTIC_TETS_GLSL

layout(std430, set = 0, binding = B_ELASTIC_TETS) readonly restrict buffer ElasticTets { vec4 elastic_tets[]; };

// Tet t's element constants.
ElasticTet elastic_tet_at(uint t) {
    vec4 r0 = elastic_tets[4u * t];
    vec4 r1 = elastic_tets[4u * t + 1u];
    vec4 r2 = elastic_tets[4u * t + 2u];
    ElasticTet e;
    e.g1 = r0.xyz;
    e.volume = r0.w;
    e.g2 = r1.xyz;
    e.mu = r1.w;
    e.g3 = r2.xyz;
    e.lambda = r2.w;
    e.alpha = elastic_tets[4u * t + 3u].x;
    return e;
}

#ifdef NODE_TETS
layout(std430, set = 0, binding = B_NODE_TET_OFFSETS) readonly restrict buffer NodeTetOffsets { uint node_tet_offsets[]; };
layout(std430, set = 0, binding = B_NODE_TET_ITEMS) readonly restrict buffer NodeTetItems { uint node_tet_items[]; };

// Node i's damping time [s]: its first tet's (ElasticNodes::damping; 0 for a node of none).
float node_damping(uint i) {
    uint first = node_tet_offsets[i];
    return first < node_tet_offsets[i + 1u] ? elastic_tets[4u * (node_tet_items[first] >> 2u) + 3u].y : 0.0;
}
#endif

#endif
