#version 460
// Pass `volume`: one Jacobi sweep of the implicit volume constraint over one constraint
// group (physics.md), one invocation per tet. Reads x(t), v(t) and the step's current F;
// hard, or compliant with the tet's compliance alpha_t (volume_softness, no damping; then
// lambda is the increment of the tet's multiplier so far in the step, B - s lambda, kept in
// VolumeMultipliers, 0 in iteration 0, growing by omega lambda).
// Variants `ext`/`cas` (the paper's Jacobi, one group): add -lambda grad_k C to the four
// nodes' constraint sums with float atomics. Variant `gather` (Gauss-Seidel by colour
// groups, no atomics): solve group pc.group's tets and write -lambda grad_k C into the
// tet's four contribution slots; `constraint_apply#gather` sums them per node.
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
// @variant gather: GATHER
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/volume.glsl"
#include "physics/implicit.glsl"
#include "common/constraint_output.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_REST_VOLUMES) readonly restrict buffer RestVolumes { float rest_volumes[]; };
layout(std430, set = 0, binding = B_VOLUME_COMPLIANCE) readonly restrict buffer VolumeCompliance { float volume_compliance[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };
layout(std430, set = 0, binding = B_VOLUME_MULTIPLIERS) restrict buffer VolumeMultipliers { float volume_multipliers[]; };

void main() {
    uint position;
    uint t;
    if (!constraint_of_invocation(gl_GlobalInvocationID.x, pc.tet_count, position, t)) {
        return;
    }
    uvec4 tet = tets[t];
    vec4 p[4] = vec4[4](positions[tet.x], positions[tet.y], positions[tet.z], positions[tet.w]);
    vec3 g[4];
    float c = volume_constraint(p[0].xyz, p[1].xyz, p[2].xyz, p[3].xyz, rest_volumes[t], g[0], g[1], g[2], g[3]);
    float a = 0.0;
    float b = 0.0;
    for (int k = 0; k < 4; ++k) {
        uint node = tet[k];
        implicit_accumulate(a, b, g[k], p[k].w, combine_a_scale(pc.combine, degrees[group_node(node)]), velocities[node].xyz, forces[node].xyz, pc.dt);
    }
    float softness = volume_softness(volume_compliance[t], pc.dt);
    float so_far = 0.0;
    if (softness > 0.0) {
        so_far = multiplier_so_far(volume_multipliers[t], pc.iteration, 0u);
    } else {
        c = solve_hard(pc.phase, c);
    }
    float lambda = compliant_multiplier(c, a, b - softness * so_far, pc.dt, softness, 0.0, pc.epsilon);
    if (softness > 0.0) {
        volume_multipliers[t] = so_far + pc.omega * lambda;
    }
    for (uint k = 0u; k < 4u; ++k) {
        constraint_output(position, 4u, k, tet[k], -lambda * g[k], lambda != 0.0);
    }
}
