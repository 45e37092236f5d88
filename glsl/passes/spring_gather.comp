#version 460
// Pass `spring_gather`: spring forces, node-centric (physics.md Eq. 1). One invocation per
// node sums the forces of its adjacent springs (CSR node -> springs) and writes
// F = m g + sum, so no atomics are needed and the force reset is implied.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/spring.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_NODE_SPRING_OFFSETS) readonly restrict buffer NodeSpringOffsets { uint node_spring_offsets[]; };
layout(std430, set = 0, binding = B_NODE_SPRING_ITEMS) readonly restrict buffer NodeSpringItems { uint node_spring_items[]; };
layout(std430, set = 0, binding = B_FORCES) writeonly restrict buffer Forces { vec4 forces[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    vec3 xi = positions[i].xyz;
    vec4 vi = velocities[i];
    vec3 f = vec3(0.0, -pc.gravity * vi.w, 0.0);
    uint end = node_spring_offsets[i + 1];
    for (uint k = node_spring_offsets[i]; k < end; ++k) {
        Spring sp = springs[node_spring_items[k]];
        uint j = sp.a == i ? sp.b : sp.a;
        f += spring_force(xi, positions[j].xyz, vi.xyz, velocities[j].xyz, sp.rest, pc.ks, pc.kd);
    }
    forces[i] = vec4(f, 0.0);
}
