#version 460
// Pass `global_volume`: one iteration of the global volume constraints (physics.md, "One
// global volume constraint"), after the iteration's local constraint groups. One workgroup
// per object: with C_g, A and the surface gradients of `global_volume_prepare`,
// B = C_g / dt^2 + sum_k grad_k . (v_k / dt + w_k F_k) is reduced in shared memory in a
// fixed order (bit-identical reruns), then every surface node gets F -= lambda grad_k and
// its floor contact is solved again. Mirrors global_pass in src/cpu/parallel.rs.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "physics/implicit.glsl"
#include "physics/integrate.glsl"

// 1 when the scene has a floor (specialisation constant 1, as in constraint_apply).
layout(constant_id = 1) const uint FLOOR = 1u;

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_GLOBAL_OBJECTS) readonly restrict buffer GlobalObjects { GlobalObject objects[]; };
layout(std430, set = 0, binding = B_SURFACE_NODES) readonly restrict buffer SurfaceNodes { uint surface_nodes[]; };
layout(std430, set = 0, binding = B_SURFACE_GRADIENTS) readonly restrict buffer SurfaceGradients { vec4 surface_gradients[]; };
layout(std430, set = 0, binding = B_GLOBAL_STATE) readonly restrict buffer GlobalState { vec4 global_state[]; };

void main() {
    GlobalObject object = objects[gl_WorkGroupID.x];
    vec4 state = global_state[gl_WorkGroupID.x];
    uint l = gl_LocalInvocationID.x;
    uint stride = gl_WorkGroupSize.x;
    float unused_a = 0.0;
    float b = 0.0;
    for (uint k = l; k < object.node_count; k += stride) {
        uint node = surface_nodes[object.node_first + k];
        vec4 g = surface_gradients[object.node_first + k];
        implicit_accumulate(unused_a, b, g.xyz, g.w, 1.0, velocities[node].xyz, forces[node].xyz, pc.dt);
    }
    b = workgroup_sum2(b, 0.0).x;
    float lambda = implicit_multiplier(state.x, state.y, b, pc.dt, pc.epsilon);
    for (uint k = l; k < object.node_count; k += stride) {
        uint node = surface_nodes[object.node_first + k];
        vec4 f = forces[node];
        f.xyz -= lambda * surface_gradients[object.node_first + k].xyz;
        if (FLOOR != 0u && pc.floor_on != 0u) {
            vec4 p = positions[node];
            f = floor_solve(f, p.y, velocities[node].y, p.w, pc.dt);
        }
        forces[node] = f;
    }
}
