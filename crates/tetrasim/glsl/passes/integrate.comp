#version 460
// Pass `integrate`: the floor's final solve, symplectic Euler (physics.md Eqs. 2, 3) with
// floor friction, force reset.
//   F.y gets the floor force (physics/integrate.glsl; the only floor solve of springs-only
//   methods, a repeat of constraint_apply's last one otherwise),
//   v += dt * w * F   (F already holds m g); a node in contact (floor force > 0) loses
//   `friction` of its tangential velocity;  x += dt * v;
// finally F = m g for the next step.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor; 0 compiles the contact solve away (specialisation constant 1,
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
    vec4 f = forces[i];
    bool contact = false;
    if (FLOOR != 0u && pc.floor_on != 0u) {
        f = floor_solve(f, p.y, v.y, w, pc.dt);
        contact = f.w > 0.0;
    }
    vec3 xn = p.xyz;
    vec3 vn = integrate_node(xn, v.xyz, f.xyz, w, pc.dt, contact, pc.friction);
    positions[i] = vec4(xn, w);
    velocities[i] = vec4(vn, v.w);
    forces[i] = vec4(0.0, -pc.gravity * v.w, 0.0, 0.0);
}
