// A node's sum shared by LANES consecutive invocations (specialisation constant 4, a power
// of two dividing the workgroup size; the plan's `workgroups::lanes`): lane `lane` sums
// every LANES-th of the node's items, then `lanes_total` adds the lanes' sums in lane
// order in shared memory, so reruns give the same bits. A node's items are a chain of
// dependent loads: lanes shorten the chain and fill the multiprocessors. Used by
// `constraint_apply#gather` (a group's slots) and MINRES's node passes (the entries of the
// node's rows).
#ifndef COMMON_LANES_GLSL
#define COMMON_LANES_GLSL

layout(constant_id = 4) const uint LANES = 1u;

shared vec3 s_lane_sums[gl_WorkGroupSize.x];

// The node and the lane of this invocation.
uint lane_node() {
    return gl_GlobalInvocationID.x / LANES;
}

uint lane_index() {
    return gl_GlobalInvocationID.x % LANES;
}

// The node's total from each lane's `sum`, in every lane. Every invocation of the
// workgroup calls it (a barrier when LANES > 1).
vec3 lanes_total(vec3 sum) {
    if (LANES == 1u) {
        return sum;
    }
    uint first = gl_LocalInvocationID.x - lane_index();
    s_lane_sums[gl_LocalInvocationID.x] = sum;
    barrier();
    vec3 total = vec3(0.0);
    for (uint l = 0u; l < LANES; ++l) {
        total += s_lane_sums[first + l];
    }
    return total;
}

#endif
