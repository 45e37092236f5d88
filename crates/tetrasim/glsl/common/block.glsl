// Block Gauss-Seidel's limits (model/blocks.rs): the most nodes one block touches, held in
// a workgroup's shared memory (`MAX_BLOCK_NODES` there; a unit test checks they agree).
#ifndef COMMON_BLOCK_GLSL
#define COMMON_BLOCK_GLSL
#define MAX_BLOCK_NODES 320
#endif
