#version 460
// Pass `global_volume_sum`: the first half of one iteration of the global volume
// constraints (physics.md, "One global volume constraint"), after the iteration's local
// constraint groups, over the whole GPU: every chunk of an object
// (common/global_chunk.glsl) sums its surface nodes' share of
// B = sum_k grad_k . (v_k / dt + w_k F_k) and of the contacts' held terms (contact_held
// along held_direction: the floor's, whose force is F.w, and in the `colliders` variant the
// kinematic colliders', whose force is in ColliderContacts) in a fixed order
// (common/workgroup_sum.glsl), into the z and w of its GlobalState entry; global_volume
// then adds the chunks up. Mirrors global_sums in src/backend/cpu/parallel/iterations.rs.
// @variant plain:
// @variant colliders: COLLIDERS_ON
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/global_chunk.glsl"
#include "physics/implicit.glsl"

WORKGROUP_SUM_PAIR(workgroup_sum2, float)

layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_GLOBAL_OBJECTS) readonly restrict buffer GlobalObjects { GlobalObject objects[]; };
layout(std430, set = 0, binding = B_SURFACE_NODES) readonly restrict buffer SurfaceNodes { uint surface_nodes[]; };
layout(std430, set = 0, binding = B_SURFACE_GRADIENTS) readonly restrict buffer SurfaceGradients { vec4 surface_gradients[]; };
layout(std430, set = 0, binding = B_GLOBAL_STATE) restrict buffer GlobalState { vec4 global_state[]; };
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) readonly restrict buffer ColliderContacts { vec4 contacts[]; };
#endif

void main() {
    GlobalObject object = objects[global_object_index()];
    uint k = global_chunk_item();
    float unused_a = 0.0;
    float b = 0.0;
    float held = 0.0;
    if (k < object.node_count) {
        uint node = surface_nodes[object.node_first + k];
        vec4 g = surface_gradients[object.node_first + k];
        vec4 f = forces[node];
        implicit_accumulate(unused_a, b, g.xyz, g.w, 1.0, velocities[node].xyz, f.xyz, pc.dt);
#ifdef COLLIDERS_ON
        vec3 push = contacts[node].xyz;
#else
        vec3 push = vec3(0.0);
#endif
        held = contact_held(g.xyz, g.w, held_direction(f.w > 0.0, push));
    }
    workgroup_sum2(b, held);
    if (gl_LocalInvocationID.x == 0u) {
        global_state[gl_WorkGroupID.x].zw = vec2(b, held);
    }
}
