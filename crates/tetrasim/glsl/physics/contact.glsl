// Contact with kinematic colliders (physics.md, "Kinematic colliders"), mirroring
// src/physics/contact.rs (end_position, contact_push, surface_friction) and
// src/collider/{mod.rs,grid.rs} (the shapes' distances, grid_distance, colliders_solve,
// friction_of) function by function: per node the one-sided constraint phi(x) - r >= 0 of
// each collider at the step's end pose, solved like the floor's in the same iterations.
//
// The pure functions are always there; the collider data (Colliders, ColliderGrids,
// ColliderPoses), the grabs' attachments (GrabNodes, GrabTargets; collider/grab.rs) and what
// reads them only with COLLIDERS_ON, in a pass that declares the specialisation constants
// COLLIDERS (the collider count) and GRABBED (the grabbed nodes' count) before including
// this file.
#ifndef PHYSICS_CONTACT_GLSL
#define PHYSICS_CONTACT_GLSL

#include "physics/solve.glsl"
#include "physics/integrate.glsl"

// Shape codes (src/collider/mod.rs, Shape::code).
#define SHAPE_PLANE 0u
#define SHAPE_SPHERE 1u
#define SHAPE_CUBOID 2u
#define SHAPE_CAPSULE 3u
#define SHAPE_GRID 4u

// Where a node at x with velocity v, total force f and inverse mass w ends the step of dt
// by symplectic Euler: x + dt (v + dt w f).
vec3 end_position(vec3 x, vec3 v, vec3 f, float w, float dt) {
    return x + (v + f * (w * dt)) * dt;
}

// The normal force that moves a node whose end position is at signed distance phi out to
// `thickness`: (thickness - phi) / (dt^2 w); 0 when it is there already or pinned.
float contact_push(float phi, float thickness, float w, float dt) {
    if (!(w > 0.0) || phi >= thickness) {
        return 0.0;
    }
    return (thickness - phi) / (dt * dt * w);
}

// Friction against a surface moving at `surface`: coulomb_friction (physics/integrate.glsl)
// of the velocity relative to it, `pressed` = push w dt, the velocity the contact's push gave
// the node along the normal in the step.
vec3 surface_friction(vec3 v, vec3 surface, vec3 normal, float friction, float pressed) {
    return surface + coulomb_friction(v - surface, normal, friction, pressed);
}

// How the unit quaternion q (x, y, z, w) turns r: R r - r.
vec3 rotation_change(vec4 q, vec3 r) {
    vec3 t = 2.0 * cross(q.xyz, r);
    return q.w * t + cross(q.xyz, t);
}

// R r for the unit quaternion q (x, y, z, w).
vec3 rotate(vec4 q, vec3 r) {
    return r + rotation_change(q, r);
}

// x >= 0 ? 1 : -1 per component (Rust's signum but at -0).
vec3 signum(vec3 x) {
    return mix(vec3(-1.0), vec3(1.0), greaterThanEqual(x, vec3(0.0)));
}

// Distance to a ball of radius r about the origin and the outward normal (a point at the
// centre goes up).
float ball(vec3 p, float r, out vec3 normal) {
    float len = length(p);
    if (len > 0.0) {
        normal = p / len;
        return len - r;
    }
    normal = vec3(0.0, 1.0, 0.0);
    return -r;
}

// Distance to the box |p| <= h: outside, to its nearest point; inside, minus the depth below
// its nearest face, whose normal is the normal.
float cuboid(vec3 p, vec3 h, out vec3 normal) {
    vec3 q = abs(p) - h;
    vec3 outside = max(q, vec3(0.0));
    if (any(greaterThan(outside, vec3(0.0)))) {
        float len = length(outside);
        normal = signum(p) * outside / len;
        return len;
    }
    vec3 axis = (q.x >= q.y && q.x >= q.z) ? vec3(1.0, 0.0, 0.0)
        : (q.y >= q.z ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0));
    normal = axis * signum(p);
    return max(q.x, max(q.y, q.z));
}

// Distance to the capsule of radius r around the local Y segment |y| <= half_length.
float capsule(vec3 p, float half_length, float r, out vec3 normal) {
    return ball(p - vec3(0.0, clamp(p.y, -half_length, half_length), 0.0), r, normal);
}

#ifdef COLLIDERS_ON

// One collider's static data (src/gpu/layout.rs, GpuCollider).
struct Collider {
    uint shape;       // SHAPE_*
    float reach;      // no point within the thickness is farther from its centre [m]
    float friction;   // tangential fraction removed per step, relative to its surface
    float thickness;  // contact thickness r [m]
    vec4 size;        // sphere (radius), box (half extents), capsule (half length, radius)
    vec4 grid_origin; // mesh: its grid's origin (local) [m], w its cell [m]
    uvec4 grid_dims;  // mesh: samples along X, Y, Z; w its first sample in grid_values
};

// One collider's placement over the current step (src/gpu/layout.rs, GpuColliderPose).
struct ColliderPose {
    vec4 end_position; // [m]
    vec4 end_rotation; // unit quaternion (x, y, z, w)
    vec4 moved;        // end position - start position [m]
    vec4 turned;       // start rotation * end rotation^-1 (x, y, z, w)
};

layout(std430, set = 0, binding = B_COLLIDERS) readonly restrict buffer Colliders { Collider colliders[]; };
layout(std430, set = 0, binding = B_COLLIDER_GRIDS) readonly restrict buffer ColliderGrids { float grid_values[]; };
layout(std430, set = 0, binding = B_COLLIDER_POSES) readonly restrict buffer ColliderPoses { ColliderPose poses[]; };
layout(std430, set = 0, binding = B_GRAB_NODES) readonly restrict buffer GrabNodes { uint grab_nodes[]; };
layout(std430, set = 0, binding = B_GRAB_TARGETS) readonly restrict buffer GrabTargets { vec4 grab_targets[]; };

// Attachment::force of node i's grab, if one holds it this step (collider/grab.rs): the
// force that ends the step on its target (hard: stiffness infinite), or the implicit
// zero-length spring's k (target - x_e) / (1 + k dt^2 w), x_e where the node ends under
// its other forces `other`.
vec3 grab_force(uint i, vec3 x, vec3 v, vec3 other, float w, float dt) {
    if (GRABBED == 0u) {
        return vec3(0.0);
    }
    uint row = grab_nodes[i];
    if (row == 0xFFFFFFFFu) {
        return vec3(0.0);
    }
    vec4 a = grab_targets[pc.grab_first + row];
    if (!(a.w > 0.0)) {
        return vec3(0.0);
    }
    vec3 gap = a.xyz - end_position(x, v, other, w, dt);
    if (isinf(a.w)) {
        return gap / (dt * dt * w);
    }
    return gap * (a.w / (1.0 + a.w * dt * dt * w));
}

// A mesh collider's grid sample (i, j, k).
float grid_at(Collider c, uint i, uint j, uint k) {
    return grid_values[c.grid_dims.w + i + c.grid_dims.x * (j + c.grid_dims.y * k)];
}

// DistanceGrid::sample: trilinear in the cell holding p with the interpolant's gradient as
// the normal; outside the sampled box, the distance at its nearest point plus the distance
// to it (the normal pointing away from the box).
float grid_distance(Collider c, vec3 p, out vec3 normal) {
    vec3 origin = c.grid_origin.xyz;
    float cell = c.grid_origin.w;
    vec3 dims = vec3(c.grid_dims.xyz);
    vec3 q = clamp(p, origin, origin + (dims - 1.0) * cell);
    float outside = length(p - q);
    vec3 u = (q - origin) / cell;
    vec3 base = clamp(floor(u), vec3(0.0), dims - 2.0);
    vec3 t = u - base;
    uint i = uint(base.x), j = uint(base.y), k = uint(base.z);
    float c000 = grid_at(c, i, j, k), c100 = grid_at(c, i + 1u, j, k);
    float c010 = grid_at(c, i, j + 1u, k), c110 = grid_at(c, i + 1u, j + 1u, k);
    float c001 = grid_at(c, i, j, k + 1u), c101 = grid_at(c, i + 1u, j, k + 1u);
    float c011 = grid_at(c, i, j + 1u, k + 1u), c111 = grid_at(c, i + 1u, j + 1u, k + 1u);
    float x00 = c000 + (c100 - c000) * t.x;
    float x10 = c010 + (c110 - c010) * t.x;
    float x01 = c001 + (c101 - c001) * t.x;
    float x11 = c011 + (c111 - c011) * t.x;
    float y0 = x00 + (x10 - x00) * t.y;
    float y1 = x01 + (x11 - x01) * t.y;
    float value = y0 + (y1 - y0) * t.z;
    float dx0 = (c100 - c000) + ((c110 - c010) - (c100 - c000)) * t.y;
    float dx1 = (c101 - c001) + ((c111 - c011) - (c101 - c001)) * t.y;
    vec3 gradient = vec3(dx0 + (dx1 - dx0) * t.z, (x10 - x00) + ((x11 - x01) - (x10 - x00)) * t.z, y1 - y0);
    if (outside > 0.0) {
        normal = (p - q) / outside;
    } else {
        float g = length(gradient);
        normal = g > 0.0 ? gradient / g : vec3(0.0, 1.0, 0.0);
    }
    return value + outside;
}

// Shape::distance: signed distance of the local point p and the outward normal there.
float shape_distance(Collider c, vec3 p, out vec3 normal) {
    switch (c.shape) {
    case SHAPE_SPHERE:
        return ball(p, c.size.x, normal);
    case SHAPE_CUBOID:
        return cuboid(p, c.size.xyz, normal);
    case SHAPE_CAPSULE:
        return capsule(p, c.size.x, c.size.y, normal);
    case SHAPE_GRID:
        return grid_distance(c, p, normal);
    default:
        normal = vec3(0.0, 1.0, 0.0);
        return p.y;
    }
}

// ColliderAt::distance: the world point x against collider k at the step's end pose.
float collider_distance(uint k, vec3 x, out vec3 normal) {
    ColliderPose pose = poses[pc.collider_first + k];
    vec4 inverse = vec4(-pose.end_rotation.xyz, pose.end_rotation.w);
    vec3 local;
    float phi = shape_distance(colliders[k], rotate(inverse, x - pose.end_position.xyz), local);
    normal = rotate(pose.end_rotation, local);
    return phi;
}

// ColliderAt::distance_at_start: the world point x against collider k at the step's start
// pose (position end - moved, rotation turned * end).
float collider_distance_at_start(uint k, vec3 x) {
    ColliderPose pose = poses[pc.collider_first + k];
    vec3 r = x - (pose.end_position.xyz - pose.moved.xyz);
    vec3 in_end = rotate(vec4(-pose.turned.xyz, pose.turned.w), r);
    vec3 local = rotate(vec4(-pose.end_rotation.xyz, pose.end_rotation.w), in_end);
    vec3 unused;
    return shape_distance(colliders[k], local, unused);
}

// ColliderAt::surface_velocity: (x - start.apply(end.invert(x))) / dt, written as
// (moved - (R_turned r - r)) / dt with r = x - end position.
vec3 surface_velocity(uint k, vec3 x, float dt) {
    ColliderPose pose = poses[pc.collider_first + k];
    return (pose.moved.xyz - rotation_change(pose.turned, x - pose.end_position.xyz)) / dt;
}

// solve_node_attached: re-solves node i's collider contacts against its total force f,
// which holds the colliders' force found so far, `contact`; first its grab's attachment
// (grab_force), then each collider in order pushes the node's end position out to its
// thickness along its normal (in split contact's velocity solve, pc.phase, keeping the
// penetration the node starts the step with: solve_slack). Returns the new total force;
// `contact` becomes the colliders' new force, `touching` the last collider that pushed
// (-1: none), `normal` its normal and `pressed` the velocity its push gives the node along
// it (push w dt: Coulomb's bound on the friction). A pinned node (w = 0) gets none.
vec3 colliders_solve(uint i, vec3 f, inout vec3 contact, vec3 x, vec3 v, float w, float dt,
                     out int touching, out vec3 normal, out float pressed) {
    vec3 other = f - contact;
    contact = vec3(0.0);
    touching = -1;
    normal = vec3(0.0);
    pressed = 0.0;
    if (!(w > 0.0)) {
        return other;
    }
    contact = grab_force(i, x, v, other, w, dt);
    for (uint k = 0u; k < COLLIDERS; ++k) {
        vec3 end = end_position(x, v, other + contact, w, dt);
        // ColliderAt::may_touch: out of reach of the end pose's centre, no contact.
        vec3 away = end - poses[pc.collider_first + k].end_position.xyz;
        float reach = colliders[k].reach;
        if (dot(away, away) > reach * reach) {
            continue;
        }
        vec3 n;
        float phi = collider_distance(k, end, n);
        float thickness = colliders[k].thickness;
        if (pc.phase == PHASE_VELOCITY) {
            phi += solve_slack(pc.phase, collider_distance_at_start(k, x) - thickness);
        }
        float push = contact_push(phi, thickness, w, dt);
        if (push > 0.0) {
            contact += n * push;
            touching = int(k);
            normal = n;
            pressed = push * w * dt;
        }
    }
    return other + contact;
}

// friction_of: the velocity v1 after the step's update of a node at x, with the friction
// of the collider it touches relative to that collider's surface velocity at x + dt v1.
vec3 friction_of(int touching, vec3 normal, float pressed, vec3 x, vec3 v1, float dt) {
    if (touching < 0) {
        return v1;
    }
    vec3 surface = surface_velocity(uint(touching), x + v1 * dt, dt);
    return surface_friction(v1, surface, normal, colliders[touching].friction, pressed);
}

#endif // COLLIDERS_ON

#endif
