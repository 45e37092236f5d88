#version 460
// Pass `elastic_start` (finite elements, per node, at each linearisation; docs/GPU.md,
// "Finite elements on the GPU"): where node i ends the step at the forces so far, AT =
// x + dt (v + dt w F), its elastic force so far PHI = F - m g - the floor's normal force
// (F.w) - the colliders' force, Y = AT - w dt^2 PHI (where inertia and gravity alone take
// it), DX = 0, the contacts' push PUSHED, and the direction a contact holds it along,
// NORMAL: the floor's +Y where the floor pushes it or it ends within HELD_GAP of it in
// strain (its reach in ELASTIC_PLANE_NODE), else a collider's push's (NORMAL.w: 1 where the
// floor or a collider pushes it, which `elastic_rows` makes `touching`). The twin of the
// start of a linearisation in cpu-ref's `conjugate_gradients` (end_position,
// StepForces::elastic, collider::held_normal). Without colliders so far: a collider resting
// on a node it does not push yet is the `colliders` variant's, not written yet.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/implicit.glsl"
#include "physics/newton.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) restrict buffer ElasticNodesBuffer { vec4 nodes[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint n = pc.node_count;
    if (i >= n) {
        return;
    }
    vec4 x = positions[i];
    vec4 v = velocities[i];
    vec4 f = forces[i];
    vec3 contact = vec3(0.0);
    vec3 phi = f.xyz - pc.gravity * v.w - vec3(0.0, f.w, 0.0) - contact;
    float w = x.w;
    vec3 at = x.xyz + (v.xyz + f.xyz * (w * pc.dt)) * pc.dt;
    bool floor_pushes = pc.floor_on != 0u && f.w > 0.0;
    float reach = nodes[ELASTIC_PLANE_NODE * n + i].x;
    bool on_floor = pc.floor_on != 0u && (floor_pushes || at.y * reach <= HELD_GAP);
    vec3 pushed = vec3(0.0, f.w, 0.0) + contact;
    nodes[ELASTIC_PLANE_AT * n + i] = vec4(at, 0.0);
    nodes[ELASTIC_PLANE_Y * n + i] = vec4(at - phi * (w * pc.dt * pc.dt), 0.0);
    nodes[ELASTIC_PLANE_DX * n + i] = vec4(0.0);
    nodes[ELASTIC_PLANE_PHI * n + i] = vec4(phi, 0.0);
    nodes[ELASTIC_PLANE_PUSHED * n + i] = vec4(pushed, 0.0);
    bool touching = floor_pushes || contact != vec3(0.0);
    nodes[ELASTIC_PLANE_NORMAL * n + i] = vec4(held_direction(on_floor, contact), touching ? 1.0 : 0.0);
}
