// The body of the passes that end a solve, `integrate` and `split_velocity`
// (passes/integrate.comp, passes/split_velocity.comp): per node the floor's final solve,
// then, with COLLIDERS_ON, the kinematic colliders'; symplectic Euler with floor friction
// and the touched collider's friction; the force (and the colliders' force) reset for the
// next solve (with ELASTIC_WARM, to gravity plus the finite elements' start). Defines:
//   SPLIT_VELOCITY_PASS: split contact's velocity solve ends here; the new velocity goes to
//     SplitVelocities, positions and velocities stay;
//   SPLIT_ON (integrate only): the new positions are this solve's, the new velocities the
//     velocity solve's, from SplitVelocities.
// The floor and the colliders read pc.phase (physics/solve.glsl): full in `integrate`,
// velocity in `split_velocity`.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/solve.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor; 0 compiles the contact solve away (specialisation constant 1,
// set by the engine plan).
layout(constant_id = 1) const uint FLOOR = 1u;
// The kinematic colliders (specialisation constant 2, set by the engine plan).
layout(constant_id = 2) const uint COLLIDERS = 0u;
// The nodes grabs hold (specialisation constant 3): the rows of one step's GrabTargets.
layout(constant_id = 3) const uint GRABBED = 0u;
// 1 with the finite elements: the next step starts from this step's elastic forces
// (elastic_start, physics/elastic.glsl) beside gravity (specialisation constant 4).
layout(constant_id = 4) const uint ELASTIC_WARM = 0u;
// 1 when the frame reports the forces its supports exert (`reactions`): each node's
// holding inputs go to ReactionInputs every step, the last step's stay (constant 5).
layout(constant_id = 5) const uint REACTIONS = 0u;
#include "physics/contact.glsl"
#include "physics/elastic.glsl"

layout(std430, set = 0, binding = B_POSITIONS) restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) restrict buffer ColliderContacts { vec4 contacts[]; };
#endif
#ifndef SPLIT_VELOCITY_PASS
layout(std430, set = 0, binding = B_REACTION_INPUTS) writeonly restrict buffer ReactionInputs { vec4 reaction_inputs[]; };
#endif
#if defined(SPLIT_VELOCITY_PASS) || defined(SPLIT_ON)
layout(std430, set = 0, binding = B_SPLIT_VELOCITIES) restrict buffer SplitVelocities { vec4 split_velocities[]; };
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
    float n = 0.0; // the floor's force
    if (FLOOR != 0u && pc.floor_on != 0u) {
        f = floor_solve(f, p.y + solve_slack(pc.phase, p.y), v.y, w, pc.dt);
        n = f.w;
    }
    vec3 xn = p.xyz;
    // The colliders' force on the node and which pushes it (-1: none).
    vec3 pushed = vec3(0.0);
    int pusher = -1;
#ifdef COLLIDERS_ON
    int touching = -1;
    vec3 normal = vec3(0.0);
    float pressed = 0.0;
    {
        vec3 c = contacts[i].xyz;
        f.xyz = colliders_solve(i, f.xyz, c, xn, v.xyz, w, pc.dt, touching, normal, pressed);
        // Reset for the next solve; w keeps whether a collider pushed the node in this
        // solve (contact_measure counts it after the frame's last step, whose last solve is
        // `integrate`'s).
        contacts[i] = vec4(0.0, 0.0, 0.0, touching >= 0 ? 1.0 : 0.0);
        pushed = c;
        pusher = touching;
    }
    // integrate_node with the collider's friction before the position update.
    vec3 vn = v.xyz + pc.dt * w * f.xyz;
    if (n > 0.0) {
        vn = floor_friction(vn, pc.friction, n * w * pc.dt);
    }
    vn = friction_of(touching, normal, pressed, xn, vn, pc.dt);
    xn += pc.dt * vn;
#else
    vec3 vn = integrate_node(xn, v.xyz, f.xyz, w, pc.dt, n, pc.friction);
#endif
#ifndef SPLIT_VELOCITY_PASS
    if (REACTIONS != 0u) {
        // What a pin holds the node against: every force on it (the finite elements: but
        // the elastic force, which `reactions` takes from the tets where the nodes end).
        vec3 outer = pc.gravity * v.w + vec3(0.0, n, 0.0) + pushed;
        reaction_inputs[2u * i] = vec4(ELASTIC_WARM != 0u ? outer : f.xyz, n);
        reaction_inputs[2u * i + 1u] = vec4(pushed, float(pusher + 1));
    }
#endif
    vec3 warm = ELASTIC_WARM != 0u ? elastic_start(f.xyz, v.w, pc.gravity) : vec3(0.0);
    forces[i] = vec4(pc.gravity * v.w + warm, 0.0);
#ifdef SPLIT_VELOCITY_PASS
    split_velocities[i] = vec4(vn, 0.0);
#else
#ifdef SPLIT_ON
    vn = split_velocities[i].xyz;
#endif
    positions[i] = vec4(xn, w);
    velocities[i] = vec4(vn, v.w);
#endif
}
