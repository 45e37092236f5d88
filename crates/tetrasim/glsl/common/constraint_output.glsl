// Where a constraint pass (`spring_constraint`, `distance`, `volume`) gets its constraint and puts its forces,
// for both paths: the atomic Jacobi sweep (variants ATOMICS_EXT / ATOMICS_CAS: one
// invocation per constraint, forces added to the per-node sums with float atomics) and the
// gather path (variant GATHER: one invocation per constraint of group pc.group, forces
// written to the constraint's own slots, summed per node by `constraint_apply#gather`).
// Include after common/bindings.glsl.
#ifndef COMMON_CONSTRAINT_OUTPUT_GLSL
#define COMMON_CONSTRAINT_OUTPUT_GLSL

#ifdef GATHER
layout(std430, set = 0, binding = B_GROUP_MEMBERS) readonly restrict buffer Members { uint members[]; };
layout(std430, set = 0, binding = B_CONTRIBUTIONS) writeonly restrict buffer Contributions { vec4 contributions[]; };
#else
#include "common/atomics.glsl"
layout(std430, set = 0, binding = B_CONSTRAINT_SUM) buffer SumF { float sum_f[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_SUM) buffer SumU { uint sum_u[]; };
DECLARE_ATOMIC_ADD_CAS(sum_u)
#endif

// The constraint of invocation `id`: its position in the output order (on the gather path,
// within its sweep) and its index.
// False when the invocation has none (past the end of the group or of all constraints).
bool constraint_of_invocation(uint id, uint count, out uint position, out uint constraint) {
#ifdef GATHER
    position = pc.group_first + id;
    constraint = id < pc.group_count ? members[pc.member_first + position] : 0u;
    return id < pc.group_count;
#else
    position = id;
    constraint = id;
    return id < count;
#endif
}

// The force `f` of the constraint at `position` on its corner `corner` (of `corners`),
// node `node`; `nonzero` false when the constraint was skipped (lambda 0).
void constraint_output(uint position, uint corners, uint corner, uint node, vec3 f, bool nonzero) {
#ifdef GATHER
    contributions[pc.slot_first + corners * position + corner] = vec4(f, 0.0);
#else
    if (nonzero) {
        ATOMIC_ADD_VEC3(sum_f, sum_u, node, f);
    }
#endif
}

#endif
