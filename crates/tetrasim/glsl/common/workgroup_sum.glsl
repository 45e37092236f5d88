// Sums of a pair of values over a workgroup in a fixed order, so reruns give the same bits:
// a butterfly of subgroup shuffles inside each subgroup (every lane ends with its
// subgroup's sum, the pairs added in the same order), the subgroups' sums through shared
// memory, added by the first subgroup in subgroup order and by the same butterfly. Two
// workgroup barriers, where a shared-memory tree over the invocations takes one per level
// (11 for 1024 invocations: on lavapipe MINRES's product pass spent a third of its time in
// them). A workgroup narrower than the subgroup (a `--workgroup-size` below it) is added
// by its first invocation in invocation order. The workgroup size must be a power of two.
// Include after common/bindings.glsl, then instantiate for the pass's type:
//   WORKGROUP_SUM_PAIR(NAME, T)
// defines `void NAME(inout T a, inout T b)`, which every invocation calls with its two
// values (in uniform control flow) and returns with the workgroup's two sums, and its
// shared arrays of T (`float` for the global volume's scalars, `vec4` for Anderson's eight
// terms at a time).
#ifndef COMMON_WORKGROUP_SUM_GLSL
#define COMMON_WORKGROUP_SUM_GLSL

#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require

#define WORKGROUP_SUM_PAIR(NAME, T)                                                          \
    shared T NAME##_a[gl_WorkGroupSize.x];                                                   \
    shared T NAME##_b[gl_WorkGroupSize.x];                                                   \
    shared T NAME##_total_a;                                                                 \
    shared T NAME##_total_b;                                                                 \
    void NAME##_butterfly(inout T a, inout T b) {                                            \
        for (uint mask = 1u; mask < gl_SubgroupSize; mask <<= 1u) {                          \
            a += subgroupShuffleXor(a, mask);                                                \
            b += subgroupShuffleXor(b, mask);                                                \
        }                                                                                    \
    }                                                                                        \
    void NAME(inout T a, inout T b) {                                                        \
        if (gl_WorkGroupSize.x < gl_SubgroupSize) {                                          \
            uint l = gl_LocalInvocationID.x;                                                 \
            NAME##_a[l] = a;                                                                 \
            NAME##_b[l] = b;                                                                 \
            barrier();                                                                       \
            if (l == 0u) {                                                                   \
                for (uint i = 1u; i < gl_WorkGroupSize.x; ++i) {                             \
                    a += NAME##_a[i];                                                        \
                    b += NAME##_b[i];                                                        \
                }                                                                            \
                NAME##_total_a = a;                                                          \
                NAME##_total_b = b;                                                          \
            }                                                                                \
        } else {                                                                             \
            NAME##_butterfly(a, b);                                                          \
            if (subgroupElect()) {                                                           \
                NAME##_a[gl_SubgroupID] = a;                                                 \
                NAME##_b[gl_SubgroupID] = b;                                                 \
            }                                                                                \
            barrier();                                                                       \
            if (gl_SubgroupID == 0u) {                                                       \
                a = T(0.0);                                                                  \
                b = T(0.0);                                                                  \
                for (uint s = gl_SubgroupInvocationID; s < gl_NumSubgroups; s += gl_SubgroupSize) { \
                    a += NAME##_a[s];                                                        \
                    b += NAME##_b[s];                                                        \
                }                                                                            \
                NAME##_butterfly(a, b);                                                      \
                if (subgroupElect()) {                                                       \
                    NAME##_total_a = a;                                                      \
                    NAME##_total_b = b;                                                      \
                }                                                                            \
            }                                                                                \
        }                                                                                    \
        barrier();                                                                           \
        a = NAME##_total_a;                                                                  \
        b = NAME##_total_b;                                                                  \
    }

#endif
