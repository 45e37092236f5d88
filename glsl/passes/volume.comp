#version 460
// Pass `volume`: one Jacobi iteration of the implicit volume constraint (physics.md), one
// invocation per tet. Reads x(t), v(t) and the step's current F; adds -lambda grad_k C to
// the four nodes' constraint sums with float atomics (`constraint_apply` folds them into F).
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
#include "common/version.glsl"
#include "common/atomics.glsl"
#include "common/bindings.glsl"
#include "physics/volume.glsl"
#include "physics/implicit.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_REST_VOLUMES) readonly restrict buffer RestVolumes { float rest_volumes[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_DEGREE) readonly restrict buffer Degrees { float degrees[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_SUM) buffer SumF { float sum_f[]; };
layout(std430, set = 0, binding = B_CONSTRAINT_SUM) buffer SumU { uint sum_u[]; };
DECLARE_ATOMIC_ADD_CAS(sum_u)

void main() {
    uint t = gl_GlobalInvocationID.x;
    if (t >= pc.tet_count) {
        return;
    }
    uvec4 tet = tets[t];
    vec4 p[4] = vec4[4](positions[tet.x], positions[tet.y], positions[tet.z], positions[tet.w]);
    vec3 g[4];
    volume_gradients(p[0].xyz, p[1].xyz, p[2].xyz, p[3].xyz, g[0], g[1], g[2], g[3]);
    float a = 0.0;
    float b = 0.0;
    for (int k = 0; k < 4; ++k) {
        uint node = tet[k];
        implicit_accumulate(a, b, g[k], p[k].w, combine_a_scale(pc.combine, degrees[node]), velocities[node].xyz, forces[node].xyz, pc.dt);
    }
    float c = volume_value(p[0].xyz, p[1].xyz, p[2].xyz, p[3].xyz, rest_volumes[t]);
    float lambda = implicit_lambda(c, a, b, pc.dt, pc.epsilon);
    if (lambda != 0.0) {
        for (int k = 0; k < 4; ++k) {
            ATOMIC_ADD_VEC3(sum_f, sum_u, tet[k], -lambda * g[k]);
        }
    }
}
