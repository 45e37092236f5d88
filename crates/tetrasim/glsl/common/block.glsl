// Block Gauss-Seidel (model/blocks.rs): its limit, and, in a constraint pass's `block`
// variant (BLOCK), its buffers and the block's nodes in shared memory. Include after
// common/bindings.glsl; common/block_sweep.glsl holds the variant's main.
#ifndef COMMON_BLOCK_GLSL
#define COMMON_BLOCK_GLSL

// The most nodes one block touches (`MAX_BLOCK_NODES` in model/blocks.rs; a unit test
// checks they agree).
#define MAX_BLOCK_NODES 320

#ifdef BLOCK
// Per block (from pc.block_first, the sweep's first): its first member position within the
// sweep, its members, its first entry in BlockNodes, its nodes | its colours << 16.
layout(std430, set = 0, binding = B_BLOCK_ROWS) readonly restrict buffer BlockRows { uvec4 block_rows[]; };
// The blocks' nodes (bit 31: a hub, whose copies stay).
layout(std430, set = 0, binding = B_BLOCK_NODES) readonly restrict buffer BlockNodes { uint block_nodes[]; };
// Per member of every sweep (from pc.member_first): its corners' local indices, two 16-bit
// halves in x and y, and its colour in z.
layout(std430, set = 0, binding = B_BLOCK_CORNERS) readonly restrict buffer BlockCorners { uvec4 block_corners[]; };
// The block's nodes by local index: position and inverse mass; velocity and a_scale; force
// and how far a force moves the node's copy (a_scale omega weight; 0 for a hub).
// Sweeps of each block per iteration (`block_sweeps`; the inversion floor's: 1), and the
// one running (a compliant constraint's multiplier so far restarts only in the first sweep
// of the step's first iteration: block_iteration).
layout(constant_id = 2) const uint BLOCK_SWEEPS = 1u;
uint b_sweep = 0u;

// The iteration as a compliant constraint's multiplier so far reads it: 0 only in the
// first sweep of the step's first iteration.
uint block_iteration() {
    return pc.iteration + b_sweep;
}

shared vec4 s_x[MAX_BLOCK_NODES];
shared vec4 s_v[MAX_BLOCK_NODES];
shared vec4 s_f[MAX_BLOCK_NODES];
#endif

#endif
