// MINRES after the sweeps on the GPU (docs/GPU.md, "MINRES"; the CPU's solve is
// src/backend/cpu/minres/mod.rs, whose phases these passes follow one for one):
// `minres_setup` (each node's mobility), `minres_rows` (the rows and the first Lanczos
// vector), per iteration `minres_nodes` (the CPU's phase 1 in its node workgroups, the
// last iteration's phase 3 norm in its row workgroups) and `minres_product` (phase 2, after
// the last iteration's phase 3 vectors), then `minres_next` (the last iteration's norm),
// `minres_finish` (the last update, the multipliers) and `minres_forces` (the nodes'
// forces, the floor and colliders again). Shared here: the rows' layout, the vectors'
// planes, the dot products' partial sums and the recurrence's scalars.
//
// Rows (src/schedule/minres.rs): SPRING_ROWS implicit springs, DISTANCE_ROWS distance
// constraints, TET_ROWS volume constraints (one invocation each, in the first
// FIXED_WORKGROUPS workgroups), then one workgroup per global volume constraint
// (OBJECTS). A dot product is summed per workgroup into MinresSums (PARTIALS values per
// product), and every workgroup that needs it adds all of them in the same fixed order, so
// all compute the same scalars (bit-identical reruns, no float atomics).
// Include after common/bindings.glsl and common/workgroup_sum.glsl.
#ifndef COMMON_MINRES_GLSL
#define COMMON_MINRES_GLSL

layout(constant_id = 5) const uint SPRING_ROWS = 0u;
layout(constant_id = 6) const uint DISTANCE_ROWS = 0u;
layout(constant_id = 7) const uint TET_ROWS = 0u;
layout(constant_id = 8) const uint OBJECTS = 0u;
// MINRES iterations per step (`minres`).
layout(constant_id = 9) const uint ITERATIONS = 1u;
// Chunks per object of the global volume passes (GlobalState's rows per object).
layout(constant_id = 10) const uint GLOBAL_CHUNKS = 1u;

const uint FIXED_ROWS = SPRING_ROWS + DISTANCE_ROWS + TET_ROWS;
const uint ROWS = FIXED_ROWS + OBJECTS;
const uint FIXED_WORKGROUPS = (FIXED_ROWS + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x;
const uint PARTIALS = FIXED_WORKGROUPS + OBJECTS;
// Entries: two per spring row, four per tet row, then the objects' surface nodes.
const uint FIXED_ENTRIES = 2u * (SPRING_ROWS + DISTANCE_ROWS) + 4u * TET_ROWS;
const uint NO_ROW = 0xffffffffu;

// The planes of MinresVectors, ROWS floats each.
#define P_INVERSE 0u
#define P_SOFTNESS 1u
#define P_X 2u
#define P_R1 3u
#define P_R2 4u
#define P_Y 5u
#define P_V 6u
#define P_W1 7u
#define P_W 8u
#define P_AV 9u

// N + 1 offsets of each node's items, an (entry, row) pair per item, each entry's node,
// each object's first entry (OBJECTS + 1).
layout(std430, set = 0, binding = B_MINRES_TRANSPOSE) readonly restrict buffer MinresTranspose { uint transpose[]; };
layout(std430, set = 0, binding = B_MINRES_GRADS) restrict buffer MinresGrads { vec4 grads[]; };
layout(std430, set = 0, binding = B_MINRES_VECTORS) restrict buffer MinresVectors { float vectors[]; };
// Plane 0: the product u = W J^T v per node; plane 1: the mobility (held direction, inverse
// mass).
layout(std430, set = 0, binding = B_MINRES_NODE_VECTORS) restrict buffer MinresNodeVectors { vec4 node_vectors[]; };
// Each row workgroup's partial of the pass's dot product (PARTIALS), then the count of
// workgroups done (the same binding as uints).
layout(std430, set = 0, binding = B_MINRES_SUMS) coherent buffer MinresSums { float sums[]; };
layout(std430, set = 0, binding = B_MINRES_SUMS) coherent buffer MinresDone { uint sums_u[]; };
layout(std430, set = 0, binding = B_MINRES_STATE) restrict buffer MinresState { vec4 state[]; };

float vector_at(uint plane, uint row) {
    return vectors[plane * ROWS + row];
}

void set_vector(uint plane, uint row, float value) {
    vectors[plane * ROWS + row] = value;
}

// Node i's mobility applied to a force u (Held::apply): u less its part along the held
// direction, times the inverse mass.
vec3 mobility_apply(uint i, vec3 u) {
    vec4 held = node_vectors[pc.node_count + i];
    return (u - held.xyz * dot(held.xyz, u)) * held.w;
}

// The row of invocation `local` of row workgroup `w`: its own among the fixed rows, the
// object's for the first invocation of an object's workgroup; NO_ROW otherwise.
uint row_at(uint w, uint local) {
    if (w < FIXED_WORKGROUPS) {
        uint j = w * gl_WorkGroupSize.x + local;
        return j < FIXED_ROWS ? j : NO_ROW;
    }
    return local == 0u ? FIXED_ROWS + (w - FIXED_WORKGROUPS) : NO_ROW;
}

// The row of this invocation in a row pass (its workgroups are all row workgroups).
uint row_of_invocation() {
    return row_at(gl_WorkGroupID.x, gl_LocalInvocationID.x);
}

// The entries of fixed row j: the first and the count.
uint fixed_first_entry(uint j) {
    return j < SPRING_ROWS + DISTANCE_ROWS ? 2u * j : 2u * (SPRING_ROWS + DISTANCE_ROWS) + 4u * (j - SPRING_ROWS - DISTANCE_ROWS);
}

uint fixed_arity(uint j) {
    return j < SPRING_ROWS + DISTANCE_ROWS ? 2u : 4u;
}

// Entries of the transpose: the node offsets' end is the entry count.
uint entry_count() {
    return transpose[pc.node_count];
}

uint entry_node(uint e) {
    return transpose[pc.node_count + 1u + 2u * entry_count() + e];
}

// Object o's entries: [first, end).
uvec2 object_entries(uint o) {
    uint at = pc.node_count + 1u + 3u * entry_count() + o;
    return uvec2(transpose[at], transpose[at + 1u]);
}

// SUM += the sum over node i's entries of grad * VALUE, VALUE an expression of the entry's
// row `row`: lane LANE's share of it, every N_LANES-th entry (common/lanes.glsl adds the
// lanes'). The one loop over a node's entries of the rows' transpose.
#define TRANSPOSE_SUM(SUM, I, LANE, N_LANES, VALUE)                                         \
    {                                                                                       \
        uint transpose_end = transpose[(I) + 1u];                                           \
        for (uint t = transpose[I] + (LANE); t < transpose_end; t += (N_LANES)) {           \
            uint item = pc.node_count + 1u + 2u * t;                                        \
            uint row = transpose[item + 1u];                                                \
            SUM += grads[transpose[item]].xyz * (VALUE);                                    \
        }                                                                                   \
    }

// sum over node i's rows of grad * p[row] (its share of J^T p), p the plane `plane`: lane
// `lane`'s share of it, every `lanes`-th entry (common/lanes.glsl adds the lanes').
vec3 transpose_sum(uint i, uint plane, uint lane, uint lanes) {
    vec3 sum = vec3(0.0);
    TRANSPOSE_SUM(sum, i, lane, lanes, vector_at(plane, row))
    return sum;
}

WORKGROUP_SUM_PAIR(minres_workgroup_sum, float)

shared bool s_last;

// Row workgroup `w`'s partial of the pass's dot product from each invocation's `value`;
// true in the last row workgroup to finish, whose invocations then hold the total in
// `value`: the partials added in one fixed order (strided, then the workgroup sum), so the total
// does not depend on which workgroup is last. Every invocation of a row workgroup calls it.
bool reduce_last_at(inout float value, uint w) {
    float unused = 0.0;
    minres_workgroup_sum(value, unused);
    if (gl_LocalInvocationID.x == 0u) {
        sums[w] = value;
        memoryBarrierBuffer();
        s_last = atomicAdd(sums_u[PARTIALS], 1u) == PARTIALS - 1u;
    }
    barrier();
    if (!s_last) {
        return false;
    }
    memoryBarrierBuffer();
    float total = 0.0;
    for (uint p = gl_LocalInvocationID.x; p < PARTIALS; p += gl_WorkGroupSize.x) {
        total += sums[p];
    }
    minres_workgroup_sum(total, unused);
    value = total;
    if (gl_LocalInvocationID.x == 0u) {
        sums_u[PARTIALS] = 0u;
    }
    return true;
}

// reduce_last_at in a row pass (its workgroups are all row workgroups).
bool reduce_last(inout float value) {
    return reduce_last_at(value, gl_WorkGroupID.x);
}

// The recurrence after an iteration (the CPU's Recurrence and its pending Update): the
// Lanczos scalars and the QR factorisation's rotation, whether the solve goes on, and the
// update of the search directions and the solution the next row pass makes.
struct Recurrence {
    float beta;
    float old_beta;
    float dbar;
    float epsilon;
    float phibar;
    float cs;
    float sn;
    float alpha;
    bool going;
    bool pending;
    float old_epsilon;
    float delta;
    float over_gamma;
    float phi;
};

Recurrence load_state(uint k) {
    vec4 a = state[4u * k];
    vec4 b = state[4u * k + 1u];
    vec4 c = state[4u * k + 2u];
    vec4 d = state[4u * k + 3u];
    return Recurrence(a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w, c.x != 0.0, c.y != 0.0, d.x, d.y, d.z, d.w);
}

void store_state(uint k, Recurrence r) {
    state[4u * k] = vec4(r.beta, r.old_beta, r.dbar, r.epsilon);
    state[4u * k + 1u] = vec4(r.phibar, r.cs, r.sn, r.alpha);
    state[4u * k + 2u] = vec4(r.going ? 1.0 : 0.0, r.pending ? 1.0 : 0.0, 0.0, 0.0);
    state[4u * k + 3u] = vec4(r.old_epsilon, r.delta, r.over_gamma, r.phi);
}

// The next rotation from the iteration's alpha and next beta (Recurrence::advance): false
// where the factorisation breaks down.
bool advance(inout Recurrence r, float alpha, float beta) {
    r.old_beta = r.beta;
    r.beta = beta;
    r.old_epsilon = r.epsilon;
    r.delta = r.cs * r.dbar + r.sn * alpha;
    float gbar = r.sn * r.dbar - r.cs * alpha;
    r.epsilon = r.sn * beta;
    r.dbar = -r.cs * beta;
    float gamma = length(vec2(gbar, beta));
    if (!(gamma > 0.0) || isinf(gamma)) {
        return false;
    }
    r.cs = gbar / gamma;
    r.sn = beta / gamma;
    r.phi = r.cs * r.phibar;
    r.phibar *= r.sn;
    r.over_gamma = 1.0 / gamma;
    return true;
}

// The recurrence's start from the first Lanczos vector's norm squared (Recurrence::new); it
// goes on only where that is positive and finite.
Recurrence recurrence_start(float norm) {
    bool live = norm > 0.0 && !isinf(norm);
    float beta = live ? sqrt(norm) : 0.0;
    return Recurrence(beta, 0.0, 0.0, 0.0, beta, -1.0, 0.0, 0.0, live, false, 0.0, 0.0, 0.0, 0.0);
}

// The recurrence after iteration k's `r` and its next Lanczos vector's norm squared: the
// rotation and its pending update; the solve stops where the factorisation breaks down or
// the norm is 0 (the update still pending then).
Recurrence recurrence_next(Recurrence r, float norm) {
    float beta = sqrt(max(norm, 0.0));
    r.pending = advance(r, r.alpha, beta);
    r.going = r.pending && beta != 0.0;
    return r;
}

// Row j's next Lanczos vector after iteration `r` (its alpha known), r2' = av - alpha / beta
// r2, and its preconditioned y = M^-1 r2' (returned in `y`).
// `precise`: every pass that calls it gets the same bits (no contraction into a fused
// multiply-add at one call site and not another).
float next_vector(Recurrence r, uint j, out float y) {
    precise float next = vector_at(P_AV, j) - (r.alpha / r.beta) * vector_at(P_R2, j);
    precise float preconditioned = next * vector_at(P_INVERSE, j);
    y = preconditioned;
    return next;
}

// Row workgroup `w`'s part of iteration k's start (k >= 1; `minres_nodes`' row workgroups,
// `minres_next` for the finish): the norm r2' . y of the next Lanczos vector after
// iteration k - 1, from which the last workgroup advances the recurrence into state k. It
// only reads the vectors: `minres_product` of iteration k writes them
// (lanczos_advance). A stopped solve passes its recurrence on, stopped.
void lanczos_norm(uint k, uint w) {
    Recurrence r = load_state(k - 1u);
    if (!r.going) {
        if (w == 0u && gl_LocalInvocationID.x == 0u) {
            r.pending = false;
            store_state(k, r);
        }
        return;
    }
    uint j = row_at(w, gl_LocalInvocationID.x);
    float norm = 0.0;
    if (j != NO_ROW) {
        float y;
        float next = next_vector(r, j, y);
        norm = next * y;
    }
    if (reduce_last_at(norm, w) && gl_LocalInvocationID.x == 0u) {
        store_state(k, recurrence_next(r, norm));
    }
}

// Row j's Lanczos vectors after iteration `r`: r1 = r2, r2 = r2', y = M^-1 r2', the values
// lanczos_norm summed.
void lanczos_advance(Recurrence r, uint j) {
    float y;
    float next = next_vector(r, j, y);
    set_vector(P_R1, j, vector_at(P_R2, j));
    set_vector(P_R2, j, next);
    set_vector(P_Y, j, y);
}

// Row j's part of the update r holds: w_new = (v - old_epsilon w1 - delta w) / gamma,
// w1 = w, w = w_new, x += phi w_new.
void apply_update(Recurrence r, uint j) {
    float w1 = vector_at(P_W1, j);
    float w = vector_at(P_W, j);
    float next = (vector_at(P_V, j) - r.old_epsilon * w1 - r.delta * w) * r.over_gamma;
    set_vector(P_W1, j, w);
    set_vector(P_W, j, next);
    set_vector(P_X, j, vector_at(P_X, j) + r.phi * next);
}

#endif
