#version 460
// Pass `integrate`: symplectic Euler (physics.md Eqs. 2, 3), floor contact, force reset.
//   v += dt * w * F   (F already holds m g),   x += dt * v,
// then a node below y = 0 goes back onto it, its normal velocity is clamped to >= 0 and its
// tangential velocity scaled by (1 - friction); finally F = m g for the next step.
#include "common/version.glsl"
#include "common/bindings.glsl"

// 1 when the scene has a floor; 0 compiles the contact test away (specialisation constant 1,
// set by the engine plan).
layout(constant_id = 1) const uint FLOOR = 1u;

layout(std430, set = 0, binding = B_POSITIONS) restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    vec4 p = positions[i];
    vec4 v = velocities[i];
    float w = p.w;
    vec3 vn = v.xyz + pc.dt * w * forces[i].xyz;
    vec3 xn = p.xyz + pc.dt * vn;
    if (FLOOR != 0u && pc.floor_on != 0u && xn.y < 0.0) {
        xn.y = 0.0;
        vn.y = max(vn.y, 0.0);
        vn.xz *= 1.0 - pc.friction;
    }
    positions[i] = vec4(xn, w);
    velocities[i] = vec4(vn, v.w);
    forces[i] = vec4(0.0, -pc.gravity * v.w, 0.0, 0.0);
}
