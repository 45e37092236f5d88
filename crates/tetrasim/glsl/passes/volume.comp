#version 460
// Pass `volume`: one Jacobi sweep of the implicit volume constraint over one constraint
// group (physics.md), one invocation per tet. Reads x(t), v(t) and the step's current F;
// hard, or compliant with the tet's compliance alpha_t (volume_softness, no damping; then
// lambda is the increment of the tet's multiplier so far in the step, B - s lambda, kept in
// VolumeMultipliers, 0 in iteration 0, growing by omega lambda).
// Variants `ext`/`cas` (the paper's Jacobi, one group): add -lambda grad_k C to the four
// nodes' constraint sums with float atomics. Variant `gather` (Gauss-Seidel by colour
// groups, no atomics): solve group pc.group's tets and write -lambda grad_k C into the
// tet's four contribution slots; `constraint_apply#gather` sums them per node.
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
// @variant gather: GATHER
// Variant `block` (block Gauss-Seidel, physics.md): one workgroup per block of the sweep's
// one group (`model/blocks.rs`), one invocation per tet. The block's nodes are loaded into
// shared memory; then its colours are solved one after another, each tet against the
// forces its block's earlier colours left (a tet's force f moves its node's copy by
// a_scale omega weight f, the node's degree counted in blocks; a hub's, bit 31 of its
// BlockNodes entry, stays), a barrier between colours.
// Every tet writes its forces into its slots as `gather` does; `constraint_apply#gather`
// sums them per node over all blocks.
// @variant block: GATHER BLOCK
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/volume.glsl"
#include "physics/implicit.glsl"
#include "common/constraint_output.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_REST_VOLUMES) readonly restrict buffer RestVolumes { float rest_volumes[]; };
layout(std430, set = 0, binding = B_VOLUME_COMPLIANCE) readonly restrict buffer VolumeCompliance { float volume_compliance[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };
layout(std430, set = 0, binding = B_VOLUME_MULTIPLIERS) restrict buffer VolumeMultipliers { float volume_multipliers[]; };

#ifdef BLOCK
#include "common/block.glsl"
layout(std430, set = 0, binding = B_BLOCK_ROWS) readonly restrict buffer BlockRows { uvec4 block_rows[]; };
layout(std430, set = 0, binding = B_BLOCK_NODES) readonly restrict buffer BlockNodes { uint block_nodes[]; };
layout(std430, set = 0, binding = B_BLOCK_CORNERS) readonly restrict buffer BlockCorners { uvec4 block_corners[]; };
// The block's nodes: position and inverse mass; velocity and a_scale; force and how far a
// force moves the node's copy (a_scale omega weight).
shared vec4 s_x[MAX_BLOCK_NODES];
shared vec4 s_v[MAX_BLOCK_NODES];
shared vec4 s_f[MAX_BLOCK_NODES];
#endif

// The multiplier of tet t with value c, softness `softness` (0: hard; otherwise with its
// multiplier so far) and gradients g on nodes of inverse mass w[k], a-scale s[k], velocity
// v[k] and force f[k].
float tet_multiplier(uint t, float c, float softness, vec3 g[4], float w[4], float s[4], vec3 v[4], vec3 f[4]) {
    float a = 0.0;
    float b = 0.0;
    for (int k = 0; k < 4; ++k) {
        implicit_accumulate(a, b, g[k], w[k], s[k], v[k], f[k], pc.dt);
    }
    float so_far = 0.0;
    if (softness > 0.0) {
        so_far = multiplier_so_far(volume_multipliers[t], pc.iteration, 0u);
    } else {
        c = solve_hard(pc.phase, c);
    }
    float lambda = compliant_multiplier(c, a, b - softness * so_far, pc.dt, softness, 0.0, pc.epsilon);
    if (softness > 0.0) {
        volume_multipliers[t] = so_far + pc.omega * lambda;
    }
    return lambda;
}

#ifdef BLOCK
void main() {
    // Block row: first member, members, first node, nodes | colours << 16.
    uvec4 row = block_rows[gl_WorkGroupID.x];
    uint nodes = row.w & 0xffffu;
    for (uint l = gl_LocalInvocationID.x; l < nodes; l += gl_WorkGroupSize.x) {
        uint entry = block_nodes[row.z + l];
        uint node = entry & 0x7fffffffu;
        float degree = degrees[group_node(node)];
        float s = combine_a_scale(pc.combine, degree);
        // A hub (bit 31) keeps the iteration's force in every block.
        float moves = (entry >> 31) != 0u ? 0.0 : s * pc.omega * combine_apply_weight(pc.combine, degree);
        s_x[l] = positions[node];
        s_v[l] = vec4(velocities[node].xyz, s);
        s_f[l] = vec4(forces[node].xyz, moves);
    }
    uint me = gl_LocalInvocationID.x;
    bool mine = me < row.y;
    uint position = pc.group_first + row.x + me;
    uint t = 0u;
    uint colour = 0xffffffffu;
    uvec4 corner = uvec4(0u);
    if (mine) {
        t = members[pc.member_first + position];
        uvec4 packed = block_corners[position];
        corner = uvec4(packed.x & 0xffffu, packed.x >> 16, packed.y & 0xffffu, packed.y >> 16);
        colour = packed.z;
    }
    barrier();
    vec3 g[4];
    float c = 0.0;
    float softness = 0.0;
    if (mine) {
        c = volume_constraint(s_x[corner.x].xyz, s_x[corner.y].xyz, s_x[corner.z].xyz, s_x[corner.w].xyz, rest_volumes[t], g[0], g[1], g[2], g[3]);
        softness = volume_softness(volume_compliance[t], pc.dt);
    }
    uint colours = row.w >> 16;
    for (uint k = 0u; k < colours; ++k) {
        if (colour == k) {
            float w[4];
            float s[4];
            vec3 v[4];
            vec3 f[4];
            for (uint j = 0u; j < 4u; ++j) {
                uint l = corner[j];
                w[j] = s_x[l].w;
                s[j] = s_v[l].w;
                v[j] = s_v[l].xyz;
                f[j] = s_f[l].xyz;
            }
            float lambda = tet_multiplier(t, c, softness, g, w, s, v, f);
            for (uint j = 0u; j < 4u; ++j) {
                vec3 force = -lambda * g[j];
                uint l = corner[j];
                // A hub's copy stays (tets of one colour may share it).
                if (s_f[l].w != 0.0) {
                    s_f[l].xyz += s_f[l].w * force;
                }
                // The gather path writes slots; the node (an atomics path's) is not read.
                constraint_output(position, 4u, j, 0u, force, lambda != 0.0);
            }
        }
        barrier();
    }
}
#else
void main() {
    uint position;
    uint t;
    if (!constraint_of_invocation(gl_GlobalInvocationID.x, pc.tet_count, position, t)) {
        return;
    }
    uvec4 tet = tets[t];
    vec4 p[4] = vec4[4](positions[tet.x], positions[tet.y], positions[tet.z], positions[tet.w]);
    vec3 g[4];
    float c = volume_constraint(p[0].xyz, p[1].xyz, p[2].xyz, p[3].xyz, rest_volumes[t], g[0], g[1], g[2], g[3]);
    float w[4];
    float s[4];
    vec3 v[4];
    vec3 f[4];
    for (int k = 0; k < 4; ++k) {
        uint node = tet[k];
        w[k] = p[k].w;
        s[k] = combine_a_scale(pc.combine, degrees[group_node(node)]);
        v[k] = velocities[node].xyz;
        f[k] = forces[node].xyz;
    }
    float softness = volume_softness(volume_compliance[t], pc.dt);
    float lambda = tet_multiplier(t, c, softness, g, w, s, v, f);
    for (uint k = 0u; k < 4u; ++k) {
        constraint_output(position, 4u, k, tet[k], -lambda * g[k], lambda != 0.0);
    }
}
#endif
