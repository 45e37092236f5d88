#version 460
// Pass `constraint_apply`: ends one Jacobi iteration. Per node,
// F += omega * weight * sum, where weight is the combine mode's apply weight (1, or
// 1 / d_k for the first edition's averaging; physics.md), clears the sum, then re-solves
// the node's floor contact against the new F (the floor is a one-sided constraint solved in
// the same iterations; its force is kept in F.w).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/implicit.glsl"
#include "physics/floor.glsl"

// 1 when the scene has a floor; 0 compiles the contact solve away (specialisation constant 1,
// set by the engine plan).
layout(constant_id = 1) const uint FLOOR = 1u;

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_SUM) restrict buffer Sum { vec4 sums[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    float weight = pc.omega * combine_apply_weight(pc.combine, degrees[i]);
    vec4 f = forces[i];
    f.xyz += weight * sums[i].xyz;
    if (FLOOR != 0u && pc.floor_on != 0u) {
        vec4 p = positions[i];
        f = floor_solve(f, p.y, velocities[i].y, p.w, pc.dt);
    }
    forces[i] = f;
    sums[i] = vec4(0.0);
}
