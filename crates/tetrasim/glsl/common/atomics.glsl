// Float atomic add on a storage buffer, behind one macro:
//   ATOMIC_ADD_F(float_array, uint_array, index, value)
// where `float_array` and `uint_array` are two views of the same buffer (same binding).
// The pass is compiled twice (build.rs `// @variant`): with ATOMICS_EXT it uses
// `atomicAdd` on float (VK_EXT_shader_atomic_float, shaderBufferFloat32AtomicAdd); with
// ATOMICS_CAS it loops on an integer compare-and-swap of the float's bits, which every
// Vulkan device supports. Two modules, not a specialization constant, because a module
// that merely contains the float atomic declares a capability the device must support.
#ifndef COMMON_ATOMICS_GLSL
#define COMMON_ATOMICS_GLSL

#if defined(ATOMICS_EXT)
#extension GL_EXT_shader_atomic_float : require
#define ATOMIC_ADD_F(fview, uview, index, value) atomicAdd(fview[index], (value))
#elif defined(ATOMICS_CAS)
#define ATOMIC_ADD_F(fview, uview, index, value) atomic_add_cas_##uview((index), (value))
// Declares the CAS helper for one uint view; a pass calls it once per view it adds into.
#define DECLARE_ATOMIC_ADD_CAS(uview)                                                     \
    void atomic_add_cas_##uview(uint index, float value) {                                \
        uint seen = uview[index];                                                         \
        for (;;) {                                                                        \
            uint wanted = floatBitsToUint(uintBitsToFloat(seen) + value);                 \
            uint found = atomicCompSwap(uview[index], seen, wanted);                      \
            if (found == seen) break;                                                     \
            seen = found;                                                                 \
        }                                                                                 \
    }
#else
#error "define ATOMICS_EXT or ATOMICS_CAS (see build.rs, // @variant)"
#endif

#if defined(ATOMICS_EXT)
#define DECLARE_ATOMIC_ADD_CAS(uview)
#endif

// Adds a vec3 into element `node` of a vec4-per-node buffer seen as floats/uints.
#define ATOMIC_ADD_VEC3(fview, uview, node, v)                     \
    {                                                              \
        vec3 v_ = (v);                                             \
        ATOMIC_ADD_F(fview, uview, 4u * (node) + 0u, v_.x);        \
        ATOMIC_ADD_F(fview, uview, 4u * (node) + 1u, v_.y);        \
        ATOMIC_ADD_F(fview, uview, 4u * (node) + 2u, v_.z);        \
    }

#endif
