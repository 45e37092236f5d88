#version 460
// Pass `contact_scan`: the second third of body contact's broad phase, once per step, in
// one workgroup (any other returns): the exclusive prefix sum of the buckets' counts into
// the offsets (each invocation sums a contiguous run of buckets, invocation 0 scans the
// runs' sums, each writes its run's ends); a total beyond the item array's capacity sets
// status flag 4 (contact_fill then drops what does not fit and the frame fails). It also
// clears every surface node's contact degree for contact_find.
#include "common/version.glsl"
#include "common/bindings.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
#include "physics/bodies.glsl"
layout(std430, set = 0, binding = B_CONTACT_HASH) restrict buffer ContactHash { uint hash[]; };
layout(std430, set = 0, binding = B_CONTACT_SUMS) writeonly restrict buffer ContactSumsU { uint sums_u[]; };
layout(std430, set = 0, binding = B_STATUS) restrict buffer Status {
    uint flags;
    uint first_bad;
    float speed_limit;
    uint fastest;
} status;

shared uint s_runs[gl_WorkGroupSize.x];

void main() {
    if (gl_WorkGroupID.x != 0u) {
        return;
    }
    uint l = gl_LocalInvocationID.x;
    uint size = gl_WorkGroupSize.x;
    uint per = (BUCKETS + size - 1u) / size;
    uint first = min(l * per, BUCKETS);
    uint last = min(first + per, BUCKETS);
    uint sum = 0u;
    for (uint b = first; b < last; ++b) {
        sum += hash[HASH_COUNTS + b];
    }
    s_runs[l] = sum;
    barrier();
    if (l == 0u) {
        uint running = 0u;
        for (uint k = 0u; k < size; ++k) {
            uint v = s_runs[k];
            s_runs[k] = running;
            running += v;
        }
        hash[HASH_OFFSETS] = 0u;
        if (running > CAPACITY) {
            atomicOr(status.flags, FLAG_CONTACT_OVERFLOW);
        }
    }
    barrier();
    uint running = s_runs[l];
    for (uint b = first; b < last; ++b) {
        running += hash[HASH_COUNTS + b];
        hash[HASH_OFFSETS + b + 1u] = running;
    }
    for (uint k = l; k < BODY_NODE_COUNT; k += size) {
        sums_u[4u * body_node(k).x + 3u] = 0u;
    }
}
