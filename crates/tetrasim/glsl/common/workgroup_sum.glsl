// Sums of a pair of values over a workgroup in shared memory, in a fixed order (a tree over
// the invocations, the same for every component: bit-identical reruns). The workgroup size
// must be a power of two. Include after common/bindings.glsl, then instantiate for the
// pass's type:
//   WORKGROUP_SUM_PAIR(NAME, T)
// defines `void NAME(inout T a, inout T b)`, which every invocation calls with its two
// values and returns with the workgroup's two sums, and its two shared arrays of T per
// invocation (`float` for the global volume's scalars, `vec4` for Anderson's eight terms at
// a time: a quarter of the barriers for eight values).
#ifndef COMMON_WORKGROUP_SUM_GLSL
#define COMMON_WORKGROUP_SUM_GLSL

#define WORKGROUP_SUM_PAIR(NAME, T)                                                          \
    shared T NAME##_a[gl_WorkGroupSize.x];                                                   \
    shared T NAME##_b[gl_WorkGroupSize.x];                                                   \
    void NAME(inout T a, inout T b) {                                                        \
        uint l = gl_LocalInvocationID.x;                                                     \
        NAME##_a[l] = a;                                                                     \
        NAME##_b[l] = b;                                                                     \
        barrier();                                                                           \
        for (uint half_size = gl_WorkGroupSize.x / 2u; half_size > 0u; half_size >>= 1u) {  \
            if (l < half_size) {                                                             \
                NAME##_a[l] += NAME##_a[l + half_size];                                      \
                NAME##_b[l] += NAME##_b[l + half_size];                                      \
            }                                                                                \
            barrier();                                                                       \
        }                                                                                    \
        a = NAME##_a[0];                                                                     \
        b = NAME##_b[0];                                                                     \
        barrier();                                                                           \
    }

#endif
