#version 460
// Pass `clamp_drive`: pins that move (collider::drive in src/collider/clamp.rs), first in
// every step, before any force. Every clamped node gets the velocity that takes it from
// where it is to its target at the step's end, (target - x) / dt, with
// target = centre + p(t + dt) + R(t + dt) (rest - centre): the host computes each clamp's
// centre + p and R in f64 for every step of the frame and writes them into the frame slot's
// rows of ClampPoses before the submit (pc.step_row selects the step's). Symplectic Euler
// with w = 0 then lands the node on its target, and the constraints, which predict
// positions as x + dt v, see the move.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/contact.glsl"

// Clamped nodes (specialisation constant 1, set by the engine plan).
layout(constant_id = 1) const uint CLAMPED = 0u;
// Clamps (specialisation constant 2): the rows of one step in ClampPoses.
layout(constant_id = 2) const uint CLAMPS = 1u;

// One clamped node (src/gpu/layout.rs, GpuClampNode).
struct ClampNode {
    uint node;
    uint clamp;
    uint pad0;
    uint pad1;
    vec4 offset; // rest position - the clamp's centre [m]
};

// One clamp at a step's end (src/gpu/layout.rs, GpuClampPose).
struct ClampPose {
    vec4 position; // centre + translation [m]
    vec4 rotation; // unit quaternion (x, y, z, w)
};

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_CLAMP_NODES) readonly restrict buffer ClampNodes { ClampNode clamp_nodes[]; };
layout(std430, set = 0, binding = B_CLAMP_POSES) readonly restrict buffer ClampPoses { ClampPose clamp_poses[]; };

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (k >= CLAMPED) {
        return;
    }
    ClampNode c = clamp_nodes[k];
    ClampPose pose = clamp_poses[pc.step_row * CLAMPS + c.clamp];
    vec3 target = pose.position.xyz + rotate(pose.rotation, c.offset.xyz);
    vec4 v = velocities[c.node];
    velocities[c.node] = vec4((target - positions[c.node].xyz) / pc.dt, v.w);
}
