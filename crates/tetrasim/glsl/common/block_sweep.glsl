// The `block` variant's main of a constraint pass (block Gauss-Seidel, physics.md): one
// workgroup per block of the sweep's one group, one invocation per constraint. The block's
// nodes are loaded into shared memory (common/block.glsl); then its colours are solved one
// after another, each constraint against the copies its block's earlier colours moved (a
// constraint's force f moves its node's copy by a_scale omega weight f, the node's degree
// counted in blocks; a hub's copy stays), with a barrier between colours, BLOCK_SWEEPS
// times. Every constraint writes its forces, summed over the sweeps, into its slots as the
// `gather` variant does, and `constraint_apply#gather` sums them per node over all blocks.
//
// The pass declares positions, velocities, forces and degrees, defines BLOCK_ARITY (its
// nodes per constraint) and, before including this file:
//   void block_prepare(uint constraint, uvec4 corner): what stays through the colours (the
//     value and gradients at x(t), the material), kept in the pass's own globals;
//   float block_solve(uint constraint, uvec4 corner, out vec3 force[4]): the multiplier
//     against the block's copies, and the forces on the corners.
#ifndef COMMON_BLOCK_SWEEP_GLSL
#define COMMON_BLOCK_SWEEP_GLSL

void main() {
    uvec4 row = block_rows[pc.block_first + gl_WorkGroupID.x];
    uint nodes = row.w & 0xffffu;
    for (uint l = gl_LocalInvocationID.x; l < nodes; l += gl_WorkGroupSize.x) {
        uint entry = block_nodes[row.z + l];
        uint node = entry & 0x7fffffffu;
        float degree = degrees[group_node(node)];
        float s = combine_a_scale(pc.combine, degree);
        float moves = (entry >> 31) != 0u ? 0.0 : s * pc.omega * combine_apply_weight(pc.combine, degree);
        s_x[l] = positions[node];
        s_v[l] = vec4(velocities[node].xyz, s);
        s_f[l] = vec4(forces[node].xyz, moves);
    }
    uint me = gl_LocalInvocationID.x;
    bool mine = me < row.y;
    uint position = pc.group_first + row.x + me;
    uint constraint = 0u;
    uint colour = 0xffffffffu;
    uvec4 corner = uvec4(0u);
    if (mine) {
        constraint = members[pc.member_first + position];
        uvec4 packed = block_corners[pc.member_first + position];
        corner = uvec4(packed.x & 0xffffu, packed.x >> 16, packed.y & 0xffffu, packed.y >> 16);
        colour = packed.z;
    }
    barrier();
    if (mine) {
        block_prepare(constraint, corner);
    }
    uint colours = row.w >> 16;
    vec3 total[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
    bool acted = false;
    for (b_sweep = 0u; b_sweep < BLOCK_SWEEPS; ++b_sweep) {
        for (uint k = 0u; k < colours; ++k) {
            if (colour == k) {
                vec3 force[4];
                float lambda = block_solve(constraint, corner, force);
                acted = acted || lambda != 0.0;
                for (uint j = 0u; j < BLOCK_ARITY; ++j) {
                    uint l = corner[j];
                    // A hub's copy stays (constraints of one colour may share it).
                    if (s_f[l].w != 0.0) {
                        s_f[l].xyz += s_f[l].w * force[j];
                    }
                    total[j] += force[j];
                }
            }
            barrier();
        }
    }
    if (mine) {
        // The gather path writes slots; the node (an atomics path's) is not read.
        for (uint j = 0u; j < BLOCK_ARITY; ++j) {
            constraint_output(position, BLOCK_ARITY, j, 0u, total[j], acted);
        }
    }
}

#endif
