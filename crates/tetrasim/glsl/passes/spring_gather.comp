#version 460
// Pass `spring_gather`: spring forces, node-centric (physics.md Eq. 1). One invocation per
// node adds the forces of its adjacent springs (CSR node -> springs), each with its own
// stiffness and damping, to its F (m g, as `integrate` and the initial upload leave it), so
// no atomics are needed.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/spring.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_SPRING_DAMPING) readonly restrict buffer SpringDamping { float spring_damping[]; };
layout(std430, set = 0, binding = B_NODE_SPRING_OFFSETS) readonly restrict buffer NodeSpringOffsets { uint node_spring_offsets[]; };
layout(std430, set = 0, binding = B_NODE_SPRING_ITEMS) readonly restrict buffer NodeSpringItems { uint node_spring_items[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.node_count) {
        return;
    }
    vec3 xi = positions[i].xyz;
    vec4 vi = velocities[i];
    vec3 f = forces[i].xyz;
    uint end = node_spring_offsets[i + 1];
    for (uint k = node_spring_offsets[i]; k < end; ++k) {
        uint s = node_spring_items[k];
        Spring sp = springs[s];
        uint j = sp.a == i ? sp.b : sp.a;
        f += spring_force(xi, positions[j].xyz, vi.xyz, velocities[j].xyz, sp.rest, sp.stiffness, spring_damping[s]);
    }
    forces[i] = vec4(f, 0.0);
}
