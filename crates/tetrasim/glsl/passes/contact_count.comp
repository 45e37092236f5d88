#version 460
// Pass `contact_count`: the first third of body contact's broad phase (physics/bodies.glsl),
// once per step. Every surface triangle adds 1 (integer atomics) to the count of the hash
// bucket of each cell its predicted bounds, grown by the reach, cover (a triangle over
// more than MAX_TRIANGLE_CELLS cells sets status flag 4 and is left out; so does
// contact_fill). The counts are 0 before: contact_fill takes every one back out.
#include "common/version.glsl"
#include "common/bindings.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
#include "physics/bodies.glsl"
layout(std430, set = 0, binding = B_CONTACT_HASH) restrict buffer ContactHash { uint hash[]; };
layout(std430, set = 0, binding = B_STATUS) restrict buffer Status {
    uint flags;
    uint first_bad;
    float speed_limit;
    uint fastest;
} status;

void main() {
    uint t = gl_GlobalInvocationID.x;
    if (t >= TRIANGLE_COUNT) {
        return;
    }
    ivec3 lo, hi;
    bool too_many;
    if (!triangle_cells(t, lo, hi, too_many)) {
        if (too_many) {
            atomicOr(status.flags, FLAG_CONTACT_OVERFLOW);
        }
        return;
    }
    for (int i = lo.x; i <= hi.x; ++i) {
        for (int j = lo.y; j <= hi.y; ++j) {
            for (int k = lo.z; k <= hi.z; ++k) {
                atomicAdd(hash[HASH_COUNTS + bucket_of(ivec3(i, j, k))], 1u);
            }
        }
    }
}
