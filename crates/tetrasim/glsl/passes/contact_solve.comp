#version 460
// Pass `contact_solve`: one Jacobi sweep of the step's body contacts (BodyContact::sweep in
// src/contact/mod.rs), after each iteration's other constraints (once per step for
// springs-only methods). Every surface node with a contact (contact_find) evaluates
// C = n . (x_p - sum_k b_k x_k) - r at x(t) and the multiplier's increment against the
// forces F every contact reads alike (each node's inverse mass scaled by the combine mode
// for its contact degree), keeps the accumulated multiplier at or below 0 (a contact
// pushes, never pulls), and adds -delta grad_k C to its four nodes' sums with float
// atomics (so the sums' order, and a multi-body run's last bits, vary from run to run);
// contact_apply applies them.
// @variant ext: ATOMICS_EXT
// @variant cas: ATOMICS_CAS
#include "common/version.glsl"
#include "common/atomics.glsl"
#include "common/bindings.glsl"
#include "physics/implicit.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
#include "physics/bodies.glsl"
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_CONTACTS) restrict buffer Contacts { BodyContactRecord contacts[]; };
layout(std430, set = 0, binding = B_CONTACT_SUMS) buffer ContactSumsF { float sums_f[]; };
layout(std430, set = 0, binding = B_CONTACT_SUMS) buffer ContactSumsU { uint sums_u[]; };
DECLARE_ATOMIC_ADD_CAS(sums_u)

void main() {
    uint s = gl_GlobalInvocationID.x;
    if (s >= BODY_NODE_COUNT) {
        return;
    }
    BodyContactRecord rec = contacts[s];
    if (rec.nodes.x == NO_CONTACT) {
        return;
    }
    uint ids[4] = uint[4](rec.nodes.x, rec.nodes.y, rec.nodes.z, rec.nodes.w);
    vec3 n = rec.normal.xyz;
    vec3 b = rec.bary_lambda.xyz;
    vec3 grad[4] = vec3[4](n, -n * b.x, -n * b.y, -n * b.z);
    float c = contact_separation(rec, positions[ids[0]].xyz, positions[ids[1]].xyz,
                                 positions[ids[2]].xyz, positions[ids[3]].xyz) - THICKNESS;
    c += solve_slack(pc.phase, c);
    float a_sum = 0.0, b_sum = 0.0;
    for (uint k = 0u; k < 4u; ++k) {
        uint i = ids[k];
        float scale = combine_a_scale(pc.combine, float(sums_u[4u * i + 3u]));
        implicit_accumulate(a_sum, b_sum, grad[k], positions[i].w, scale, velocities[i].xyz, forces[i].xyz, pc.dt);
    }
    float delta = implicit_multiplier(c, a_sum, b_sum, pc.dt, pc.epsilon);
    float lambda = rec.bary_lambda.w;
    float total = min(lambda + delta, 0.0);
    delta = total - lambda;
    contacts[s].bary_lambda.w = total;
    if (delta != 0.0) {
        for (uint k = 0u; k < 4u; ++k) {
            ATOMIC_ADD_VEC3(sums_f, sums_u, ids[k], -delta * grad[k]);
        }
    }
}
