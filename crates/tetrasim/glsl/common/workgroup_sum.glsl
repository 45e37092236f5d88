// Sums of two floats over a workgroup in shared memory, in a fixed order (bit-identical
// reruns). The workgroup size must be a power of two. Include after common/bindings.glsl.
#ifndef COMMON_WORKGROUP_SUM_GLSL
#define COMMON_WORKGROUP_SUM_GLSL

shared float s_sum0[gl_WorkGroupSize.x];
shared float s_sum1[gl_WorkGroupSize.x];

// Every invocation passes its two values and gets the workgroup's two sums.
vec2 workgroup_sum2(float a, float b) {
    uint l = gl_LocalInvocationID.x;
    s_sum0[l] = a;
    s_sum1[l] = b;
    barrier();
    for (uint half_size = gl_WorkGroupSize.x / 2u; half_size > 0u; half_size >>= 1u) {
        if (l < half_size) {
            s_sum0[l] += s_sum0[l + half_size];
            s_sum1[l] += s_sum1[l + half_size];
        }
        barrier();
    }
    vec2 sums = vec2(s_sum0[0], s_sum1[0]);
    barrier();
    return sums;
}

#endif
