#version 460
// Pass `check`: divergence detection, once per frame after the last time step. A node whose
// position or velocity is NaN or infinite sets flag 1, one faster than the speed limit sets
// flag 2 and raises `fastest` to its speed (atomicMax on the bits: for non-negative floats
// their order is the numbers' order); either lowers `first_bad` to its index (atomicMin: the
// lowest bad node wins). The frame copies the 16-byte status to the host with the volume
// partials, so reading it costs no extra round trip, and a report needs no state read-back
// (with frames in flight, the state is already a later frame's). The flags are sticky: a
// diverged run stops.
#include "common/version.glsl"
#include "common/bindings.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_STATUS) restrict buffer Status {
    uint flags;
    uint first_bad;
    float speed_limit;
    uint fastest;
} status;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    vec3 x = positions[i].xyz;
    vec3 v = velocities[i].xyz;
    bool non_finite = any(isnan(x)) || any(isinf(x)) || any(isnan(v)) || any(isinf(v));
    float limit = status.speed_limit;
    bool too_fast = !non_finite && dot(v, v) > limit * limit;
    if (non_finite || too_fast) {
        atomicOr(status.flags, non_finite ? 1u : 2u);
        atomicMin(status.first_bad, i);
        if (too_fast) {
            atomicMax(status.fastest, floatBitsToUint(length(v)));
        }
    }
}
