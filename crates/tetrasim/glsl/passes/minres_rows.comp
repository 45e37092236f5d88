#version 460
// Pass `minres_rows`: MINRES's rows at the forces the sweeps left (common/minres.glsl;
// StepRows in src/physics/minres.rs and the backends' rows_of), one invocation per fixed
// row and one workgroup per global volume constraint. Each row: its gradients at x(t)
// into MinresGrads, its residual r = C / dt^2 + sum_k grad_k . (v_k / dt + w_k F_k)
// - s lambda_so_far - kd s C / dt (a hard one's C as the solve asks, Solve::hard), its
// preconditioner 1 / (sum_k grad_k . M_k grad_k + s) with each node's mobility (0 where
// the held nodes leave it less than HELD_SHARE of its free mobility: left to the sweeps),
// the solve's vectors started (x, r1, w1, w = 0; r2 = r on the live rows, y = M^-1 r2),
// and the first norm r2 . y (the last workgroup starts the recurrence). Variants: a letter per row segment the step has
// (s: implicit springs, d: distance constraints, v: volume constraints, g: global volume).
// @variant s: SPRINGS
// @variant d: DISTANCES
// @variant sd: SPRINGS DISTANCES
// @variant v: VOLUMES
// @variant sv: SPRINGS VOLUMES
// @variant dv: DISTANCES VOLUMES
// @variant sdv: SPRINGS DISTANCES VOLUMES
// @variant g: GLOBAL
// @variant sg: SPRINGS GLOBAL
// @variant dg: DISTANCES GLOBAL
// @variant sdg: SPRINGS DISTANCES GLOBAL
// @variant vg: VOLUMES GLOBAL
// @variant svg: SPRINGS VOLUMES GLOBAL
// @variant dvg: DISTANCES VOLUMES GLOBAL
// @variant sdvg: SPRINGS DISTANCES VOLUMES GLOBAL
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"
#include "physics/implicit.glsl"
#include "physics/spring.glsl"
#include "physics/distance.glsl"
#include "physics/volume.glsl"

// A row keeps at least this share of its mobility when its held nodes are taken out, or it
// is left to the sweeps (HELD_SHARE in src/physics/minres.rs).
const float HELD_SHARE = 0.5;

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
#if defined(SPRINGS) || defined(DISTANCES)
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
#endif
#ifdef SPRINGS
layout(std430, set = 0, binding = B_SPRING_DAMPING) readonly restrict buffer SpringDamping { float spring_damping[]; };
layout(std430, set = 0, binding = B_SPRING_MULTIPLIERS) readonly restrict buffer SpringMultipliers { float spring_multipliers[]; };
#endif
#ifdef VOLUMES
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_REST_VOLUMES) readonly restrict buffer RestVolumes { float rest_volumes[]; };
layout(std430, set = 0, binding = B_VOLUME_COMPLIANCE) readonly restrict buffer VolumeCompliance { float volume_compliance[]; };
layout(std430, set = 0, binding = B_VOLUME_MULTIPLIERS) readonly restrict buffer VolumeMultipliers { float volume_multipliers[]; };
#endif
#ifdef GLOBAL
layout(std430, set = 0, binding = B_GLOBAL_OBJECTS) readonly restrict buffer GlobalObjects { GlobalObject objects[]; };
layout(std430, set = 0, binding = B_SURFACE_NODES) readonly restrict buffer SurfaceNodes { uint surface_nodes[]; };
layout(std430, set = 0, binding = B_SURFACE_GRADIENTS) readonly restrict buffer SurfaceGradients { vec4 surface_gradients[]; };
layout(std430, set = 0, binding = B_GLOBAL_STATE) readonly restrict buffer GlobalState { vec4 global_state[]; };
#endif

// A row's sums over its entries: the velocity part of its numerator B, and its mobility
// with the held directions out and without (the preconditioner and HELD_SHARE's test).
struct RowSums {
    float b;
    float held;
    float free;
};

// Entry e of node `node` with gradient g: stored, and added to the row's sums.
void add_entry(inout RowSums sums, uint e, uint node, vec3 g) {
    grads[e] = vec4(g, 0.0);
    float w = positions[node].w;
    sums.b += dot(g, velocities[node].xyz / pc.dt + w * forces[node].xyz);
    sums.held += dot(g, mobility_apply(node, g));
    sums.free += dot(g, g) * w;
}

// Row j's start: its preconditioner, softness and vectors; its share of the first norm.
float start_row(uint j, float residual, float softness, RowSums sums) {
    float inverse = sums.held > 0.0 && sums.held >= HELD_SHARE * sums.free ? 1.0 / (sums.held + softness) : 0.0;
    float r2 = inverse > 0.0 ? residual : 0.0;
    float y = r2 * inverse;
    set_vector(P_INVERSE, j, inverse);
    set_vector(P_SOFTNESS, j, softness);
    set_vector(P_X, j, 0.0);
    set_vector(P_R1, j, 0.0);
    set_vector(P_R2, j, r2);
    set_vector(P_Y, j, y);
    set_vector(P_W1, j, 0.0);
    set_vector(P_W, j, 0.0);
    return r2 * y;
}

// Fixed row j: a spring's, a distance constraint's or a tet's.
float fixed_row(uint j) {
    uint first = fixed_first_entry(j);
    RowSums sums = RowSums(0.0, 0.0, 0.0);
    float c = 0.0;
    float softness = 0.0;
    float damping = 0.0;
    float so_far = 0.0;
    if (j < SPRING_ROWS) {
#ifdef SPRINGS
        Spring sp = springs[j];
        vec3 g[2];
        c = spring_constraint(positions[sp.a].xyz, positions[sp.b].xyz, sp.rest, g[0], g[1]);
        damping = spring_damping[j];
        softness = spring_softness(sp.stiffness, damping, pc.dt);
        so_far = multiplier_so_far(spring_multipliers[j], pc.iteration, pc.warm_start);
        add_entry(sums, first, sp.a, g[0]);
        add_entry(sums, first + 1u, sp.b, g[1]);
#endif
    } else if (j < SPRING_ROWS + DISTANCE_ROWS) {
#ifdef DISTANCES
        Spring sp = springs[j - SPRING_ROWS];
        vec3 g[2];
        c = solve_hard(pc.phase, distance_constraint(positions[sp.a].xyz, positions[sp.b].xyz, sp.rest, g[0], g[1]));
        add_entry(sums, first, sp.a, g[0]);
        add_entry(sums, first + 1u, sp.b, g[1]);
#endif
    } else {
#ifdef VOLUMES
        uint t = j - SPRING_ROWS - DISTANCE_ROWS;
        uvec4 tet = tets[t];
        vec3 g[4];
        c = volume_constraint(positions[tet.x].xyz, positions[tet.y].xyz, positions[tet.z].xyz, positions[tet.w].xyz, rest_volumes[t], g[0], g[1], g[2], g[3]);
        softness = volume_softness(volume_compliance[t], pc.dt);
        if (softness > 0.0) {
            so_far = multiplier_so_far(volume_multipliers[t], pc.iteration, 0u);
        } else {
            c = solve_hard(pc.phase, c);
        }
        for (uint k = 0u; k < 4u; ++k) {
            add_entry(sums, first + k, tet[k], g[k]);
        }
#endif
    }
    float residual = c / (pc.dt * pc.dt) + sums.b - softness * so_far - damping * softness * c / pc.dt;
    return start_row(j, residual, softness, sums);
}

void main() {
    float norm = 0.0;
    if (gl_WorkGroupID.x < FIXED_WORKGROUPS) {
        uint j = gl_GlobalInvocationID.x;
        if (j < FIXED_ROWS) {
            norm = fixed_row(j);
        }
    } else {
#ifdef GLOBAL
        // An object's row (hard): its surface nodes shared out over the workgroup, its
        // volume from the chunks global_volume_prepare left.
        uint o = gl_WorkGroupID.x - FIXED_WORKGROUPS;
        GlobalObject object = objects[o];
        uvec2 entries = object_entries(o);
        RowSums sums = RowSums(0.0, 0.0, 0.0);
        for (uint p = gl_LocalInvocationID.x; p < object.node_count; p += gl_WorkGroupSize.x) {
            uint at = object.node_first + p;
            add_entry(sums, entries.x + p, surface_nodes[at], surface_gradients[at].xyz);
        }
        float volume = 0.0;
        for (uint chunk = gl_LocalInvocationID.x; chunk < GLOBAL_CHUNKS; chunk += gl_WorkGroupSize.x) {
            volume += global_state[o * GLOBAL_CHUNKS + chunk].x;
        }
        minres_workgroup_sum(sums.b, sums.held);
        minres_workgroup_sum(sums.free, volume);
        if (gl_LocalInvocationID.x == 0u) {
            float c = solve_hard(pc.phase, volume - object.rest_volume);
            norm = start_row(FIXED_ROWS + o, c / (pc.dt * pc.dt) + sums.b, 0.0, sums);
        }
#endif
    }
    if (reduce_last(norm) && gl_LocalInvocationID.x == 0u) {
        store_state(0u, recurrence_start(norm));
    }
}
