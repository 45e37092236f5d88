#version 460
// Pass `integrate`: the floor's final solve, symplectic Euler (physics.md Eqs. 2, 3) with
// floor friction, force reset.
//   F.y gets the floor force (physics/integrate.glsl; the only floor solve of springs-only
//   methods, a repeat of constraint_apply's last one otherwise),
//   v += dt * w * F   (F already holds m g); a node in contact (floor force > 0) loses
//   `friction` of its tangential velocity;  x += dt * v;
// finally F = m g for the next step. Variant `colliders`: after the floor's solve the
// kinematic colliders' (physics/contact.glsl), and after the floor's friction the friction
// of the collider the node touches; the colliders' force is reset to 0 for the next step (w:
// whether one pushed the node).
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor; 0 compiles the contact solve away (specialisation constant 1,
// set by the engine plan).
layout(constant_id = 1) const uint FLOOR = 1u;
// The kinematic colliders (specialisation constant 2, set by the engine plan).
layout(constant_id = 2) const uint COLLIDERS = 0u;
// The nodes grabs hold (specialisation constant 3): the rows of one step's GrabTargets.
layout(constant_id = 3) const uint GRABBED = 0u;
#include "physics/contact.glsl"

layout(std430, set = 0, binding = B_POSITIONS) restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) restrict buffer ColliderContacts { vec4 contacts[]; };
#endif

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
#ifdef COLLIDERS_ON
    int touching = -1;
    vec3 normal = vec3(0.0);
    {
        vec3 c = contacts[i].xyz;
        f.xyz = colliders_solve(i, f.xyz, c, xn, v.xyz, w, pc.dt, touching, normal);
        // Reset for the next step; w keeps whether a collider pushed the node in this, the
        // step's last solve (contact_measure counts it after the frame's last step).
        contacts[i] = vec4(0.0, 0.0, 0.0, touching >= 0 ? 1.0 : 0.0);
    }
    // integrate_node with the collider's friction before the position update.
    vec3 vn = v.xyz + pc.dt * w * f.xyz;
    if (contact) {
        vn = floor_friction(vn, pc.friction);
    }
    vn = friction_of(touching, normal, xn, vn, pc.dt);
    xn += pc.dt * vn;
#else
    vec3 vn = integrate_node(xn, v.xyz, f.xyz, w, pc.dt, contact, pc.friction);
#endif
    positions[i] = vec4(xn, w);
    velocities[i] = vec4(vn, v.w);
    forces[i] = vec4(0.0, -pc.gravity * v.w, 0.0, 0.0);
}
