#version 460
// Pass `spring_warm_start`: the warm start of implicit springs (`warm_start`), once per time
// step before the first constraint iteration. Node-centric like `spring_gather` (CSR node ->
// springs, no atomics): one invocation per node adds -lambda_s grad_i C_s at x(t) for each
// of its springs s to its F (m g, as `integrate` and the initial upload leave it), with
// lambda_s the spring's stored multiplier (SpringMultipliers: the last step's final value,
// 0 initially), which `spring_constraint` then takes as its multiplier so far in
// iteration 0 (pc.warm_start).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/spring.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_SPRING_MULTIPLIERS) readonly restrict buffer SpringMultipliers { float spring_multipliers[]; };
layout(std430, set = 0, binding = B_NODE_SPRING_OFFSETS) readonly restrict buffer NodeSpringOffsets { uint node_spring_offsets[]; };
layout(std430, set = 0, binding = B_NODE_SPRING_ITEMS) readonly restrict buffer NodeSpringItems { uint node_spring_items[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    vec3 xi = positions[i].xyz;
    vec4 f = forces[i];
    uint end = node_spring_offsets[i + 1];
    for (uint k = node_spring_offsets[i]; k < end; ++k) {
        uint s = node_spring_items[k];
        Spring sp = springs[s];
        uint j = sp.a == i ? sp.b : sp.a;
        vec3 gi;
        vec3 gj;
        spring_constraint(xi, positions[j].xyz, sp.rest, gi, gj);
        f.xyz -= spring_multipliers[s] * gi;
    }
    forces[i] = f;
}
