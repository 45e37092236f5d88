// Sums of eight floats (two vec4) over a workgroup in shared memory, in the same fixed
// order as common/workgroup_sum.glsl's workgroup_sum2 (bit-identical sums, a quarter of
// its barriers for eight values). The workgroup size must be a power of two. Include after
// common/bindings.glsl; it takes 32 bytes of shared memory per invocation.
#ifndef COMMON_WORKGROUP_SUM8_GLSL
#define COMMON_WORKGROUP_SUM8_GLSL

shared vec4 s_sum8a[gl_WorkGroupSize.x];
shared vec4 s_sum8b[gl_WorkGroupSize.x];

// Every invocation passes its eight values and gets the workgroup's eight sums.
void workgroup_sum8(inout vec4 a, inout vec4 b) {
    uint l = gl_LocalInvocationID.x;
    s_sum8a[l] = a;
    s_sum8b[l] = b;
    barrier();
    for (uint half_size = gl_WorkGroupSize.x / 2u; half_size > 0u; half_size >>= 1u) {
        if (l < half_size) {
            s_sum8a[l] += s_sum8a[l + half_size];
            s_sum8b[l] += s_sum8b[l + half_size];
        }
        barrier();
    }
    a = s_sum8a[0];
    b = s_sum8b[0];
    barrier();
}

#endif
