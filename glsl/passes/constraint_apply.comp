#version 460
// Pass `constraint_apply`: ends one Jacobi iteration. Per node,
// F += omega * weight * sum, where weight is 1 / (constraints of this kind touching the
// node) for averaging or 1 for plain summation (physics.md); then clears the sum.
#include "common/version.glsl"
#include "common/bindings.glsl"

layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_SUM) restrict buffer Sum { vec4 sums[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_WEIGHT) readonly restrict buffer Weights { float weights[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    forces[i] = vec4(forces[i].xyz + pc.omega * weights[i] * sums[i].xyz, 0.0);
    sums[i] = vec4(0.0);
}
