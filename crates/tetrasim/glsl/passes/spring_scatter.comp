#version 460
// Pass `spring_scatter`: spring forces, spring-centric (physics.md Eq. 1). One invocation per
// spring adds f to its first node and -f to its second with float atomics (into F = m g,
// which `integrate` and the initial upload leave), each spring with its own stiffness and
// damping.
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
#include "common/version.glsl"
#include "common/atomics.glsl"
#include "common/bindings.glsl"
#include "physics/spring.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_SPRING_DAMPING) readonly restrict buffer SpringDamping { float spring_damping[]; };
layout(std430, set = 0, binding = B_FORCES) buffer ForcesF { float forces_f[]; };
layout(std430, set = 0, binding = B_FORCES) buffer ForcesU { uint forces_u[]; };
DECLARE_ATOMIC_ADD_CAS(forces_u)

void main() {
    uint s = gl_GlobalInvocationID.x;
    if (s >= pc.spring_count) {
        return;
    }
    Spring sp = springs[s];
    vec3 f = spring_force(positions[sp.a].xyz, positions[sp.b].xyz, velocities[sp.a].xyz, velocities[sp.b].xyz,
                          sp.rest, sp.stiffness, spring_damping[s]);
    ATOMIC_ADD_VEC3(forces_f, forces_u, sp.a, f);
    ATOMIC_ADD_VEC3(forces_f, forces_u, sp.b, -f);
}
