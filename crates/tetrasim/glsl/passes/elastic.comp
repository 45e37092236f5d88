#version 460
// Pass `elastic`: finite elements (method `neo-hookean`), one Newton step of Vertex Block
// Descent per node of node colour group pc.group (physics/elastic.glsl; physics.md, fourth
// edition). Each invocation reads its node's tets through the node -> tet corner CSR, sums
// the stable Neo-Hookean gradient and Hessian block at the step's end positions
// x + dt (v + dt w F), and writes the force increment m dx / dt^2 into its one contribution
// slot; `constraint_apply#gather` adds it and solves the floor and the colliders. The
// elastic force so far is F less gravity, the floor's force (F.w) and the colliders'.
// The Vulkan backend does not run this method yet (it refuses `neo-hookean`); the pass is
// compiled and kept as the CPU backends' twin.
// @variant gather: GATHER
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/elastic.glsl"
#include "common/constraint_output.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_ELASTIC_TETS) readonly restrict buffer ElasticTets { vec4 elastic_tets[]; };
layout(std430, set = 0, binding = B_NODE_TET_OFFSETS) readonly restrict buffer NodeTetOffsets { uint node_tet_offsets[]; };
layout(std430, set = 0, binding = B_NODE_TET_ITEMS) readonly restrict buffer NodeTetItems { uint node_tet_items[]; };
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) readonly restrict buffer ColliderContacts { vec4 contacts[]; };

vec3 end_of_step(uint k) {
    vec4 x = positions[k];
    return x.xyz + (velocities[k].xyz + forces[k].xyz * (x.w * pc.dt)) * pc.dt;
}

void main() {
    uint position;
    uint i;
    if (!constraint_of_invocation(gl_GlobalInvocationID.x, pc.node_count, position, i)) {
        return;
    }
    vec4 x = positions[i];
    vec3 df = vec3(0.0);
    if (x.w > 0.0) {
        vec3 grad = vec3(0.0);
        vec3 h0 = vec3(0.0);
        vec3 h1 = vec3(0.0);
        float beta = 0.0;
        for (uint e = node_tet_offsets[i]; e < node_tet_offsets[i + 1u]; ++e) {
            uint t = node_tet_items[e] >> 2u;
            uint a = node_tet_items[e] & 3u;
            uvec4 tet = tets[t];
            vec4 r0 = elastic_tets[4u * t];
            vec4 r1 = elastic_tets[4u * t + 1u];
            vec4 r2 = elastic_tets[4u * t + 2u];
            vec4 r3 = elastic_tets[4u * t + 3u];
            elastic_corner(end_of_step(tet.x), end_of_step(tet.y), end_of_step(tet.z), end_of_step(tet.w),
                           r0.xyz, r1.xyz, r2.xyz, r0.w, r1.w, r2.w, r3.x, a, grad, h0, h1);
            beta = r3.y;
        }
        float mass = velocities[i].w;
        vec4 f = forces[i];
        vec3 phi = f.xyz - pc.gravity * mass - vec3(0.0, f.w, 0.0) - contacts[i].xyz;
        vec3 moved = end_of_step(i) - x.xyz;
        df = elastic_step(mass, pc.dt, beta, phi, grad, h0, h1, moved);
    }
    constraint_output(position, 1u, 0u, i, df, true);
}
