#version 460
// Pass `contact_fill`: the last third of body contact's broad phase, once per step. Every
// surface triangle takes one count back out of each bucket it counted itself into
// (contact_count, the same cells) and writes its index at that place of the bucket's range
// (counting sort: the counts are 0 again afterwards; items beyond the capacity are dropped,
// contact_scan has flagged them). The order within a bucket depends on the atomics, which
// contact_find's deterministic choice does not see.
#include "common/version.glsl"
#include "common/bindings.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
#include "physics/bodies.glsl"
layout(std430, set = 0, binding = B_CONTACT_HASH) restrict buffer ContactHash { uint hash[]; };

void main() {
    uint t = gl_GlobalInvocationID.x;
    if (t >= TRIANGLE_COUNT) {
        return;
    }
    ivec3 lo, hi;
    bool too_many;
    if (!triangle_cells(t, lo, hi, too_many)) {
        return;
    }
    for (int i = lo.x; i <= hi.x; ++i) {
        for (int j = lo.y; j <= hi.y; ++j) {
            for (int k = lo.z; k <= hi.z; ++k) {
                uint b = bucket_of(ivec3(i, j, k));
                uint slot = hash[HASH_OFFSETS + b] + atomicAdd(hash[HASH_COUNTS + b], 0xFFFFFFFFu) - 1u;
                if (slot < CAPACITY) {
                    hash[HASH_ITEMS + slot] = t;
                }
            }
        }
    }
}
