// The chunks of the global volume passes (global_volume_prepare, global_volume_sum,
// global_volume): every object gets CHUNKS workgroups (specialisation constant 2, from the
// engine plan), workgroup w takes chunk w % CHUNKS of object w / CHUNKS, and invocation l of
// it the object's face and surface node at position chunk * workgroup size + l. Each chunk
// keeps its partial sums in GlobalState[w]: x = its faces' share of the object's volume,
// y = its share of A, z = its share of B (this iteration's). Include after
// common/bindings.glsl.
#ifndef COMMON_GLOBAL_CHUNK_GLSL
#define COMMON_GLOBAL_CHUNK_GLSL

layout(constant_id = 2) const uint CHUNKS = 1u;

uint global_object_index() {
    return gl_WorkGroupID.x / CHUNKS;
}

// This invocation's position within its object's faces and surface nodes.
uint global_chunk_item() {
    return (gl_WorkGroupID.x % CHUNKS) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
}

#endif
