#version 460
// Pass `elastic_rows` (finite elements, per node; docs/GPU.md, "Finite elements on the
// GPU"): node i's row of the step's Newton system linearised where the nodes end the step so
// far (ElasticNodes' AT plane), its elastic force so far being PHI: the residual
// b_i = -(phi + dE/dx_i + beta (K v)_i) into R (the energy's gradient and Hessian block
// summed over its tets through the node -> tet corners CSR, `elastic_corner` of
// physics/elastic.glsl; K v gathered from `elastic_linearise`'s corners), and the inverse of
// its diagonal block m/dt^2 + (1 + beta/dt) H, stiffened along NORMAL where a contact holds
// it, into INVERSE_A/B, the stiffening into HELD. Zero for a pinned node. The twin of
// ElasticNodes::newton_row (src/schedule/family/elastic.rs).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/elastic.glsl"
#include "physics/newton.glsl"
#include "common/elastic_state.glsl"
#define NODE_TETS
#include "common/elastic_tets.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_ELASTIC_CORNERS) readonly restrict buffer ElasticCornersBuffer { vec4 corners[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) restrict buffer ElasticNodesBuffer { vec4 nodes[]; };

void main() {
    if (!elastic_linearises()) {
        return;
    }
    uint i = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
    if (i >= n) {
        return;
    }
    vec3 r = vec3(0.0);
    Sym3 inverse = Sym3(vec3(0.0), vec3(0.0));
    vec3 h = vec3(0.0);
    if (positions[i].w > 0.0) {
        vec3 grad = vec3(0.0);
        vec3 h0 = vec3(0.0);
        vec3 h1 = vec3(0.0);
        vec3 rate = vec3(0.0);
        uint first = node_tet_offsets[i];
        uint end = node_tet_offsets[i + 1u];
        float beta = node_damping(i);
        uint at = ELASTIC_PLANE_AT * n;
        for (uint item = first; item < end; ++item) {
            uint t = node_tet_items[item] >> 2u;
            uint a = node_tet_items[item] & 3u;
            uvec4 tet = tets[t];
            vec4 r0 = elastic_tets[4u * t];
            vec4 r1 = elastic_tets[4u * t + 1u];
            vec4 r2 = elastic_tets[4u * t + 2u];
            vec4 r3 = elastic_tets[4u * t + 3u];
            elastic_corner(nodes[at + tet.x].xyz, nodes[at + tet.y].xyz, nodes[at + tet.z].xyz,
                           nodes[at + tet.w].xyz, r0.xyz, r1.xyz, r2.xyz, r0.w, r1.w, r2.w, r3.x, a,
                           grad, h0, h1);
            rate += corners[node_tet_items[item]].xyz;
        }
        if (!(beta > 0.0)) {
            rate = vec3(0.0);
        }
        Sym3 block = node_block(velocities[i].w, pc.dt, beta, Sym3(h0, h1));
        block = held_block(block, nodes[ELASTIC_PLANE_NORMAL * n + i].xyz, h);
        sym3_inverse(block, inverse);
        r = -(grad + rate * beta + nodes[ELASTIC_PLANE_PHI * n + i].xyz);
    }
    nodes[ELASTIC_PLANE_R * n + i] = vec4(r, 0.0);
    nodes[ELASTIC_PLANE_INVERSE_A * n + i] = vec4(inverse.a, inverse.b.x);
    nodes[ELASTIC_PLANE_INVERSE_B * n + i] = vec4(inverse.b.yz, 0.0, 0.0);
    // Touching (left out of the coarse correction): a contact pushes it or holds it.
    bool touching = nodes[ELASTIC_PLANE_NORMAL * n + i].w > 0.0 || h != vec3(0.0);
    nodes[ELASTIC_PLANE_HELD * n + i] = vec4(h, touching ? 1.0 : 0.0);
}
