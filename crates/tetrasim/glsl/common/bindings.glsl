// Descriptor bindings (set 0) and the push-constant block shared by every pass.
// The host side is src/gpu/layout.rs (`binding::*`, `PushConstants`, `GpuSpring`,
// `VolumePartial`); a test there checks these numbers and offsets in the compiled SPIR-V.
#ifndef COMMON_BINDINGS_GLSL
#define COMMON_BINDINGS_GLSL

// Per node, vec4: xyz = position [m], w = inverse mass [1/kg].
#define B_POSITIONS 0
// Per node, vec4: xyz = velocity [m/s], w = mass [kg].
#define B_VELOCITIES 1
// Per node, vec4: xyz = force F of the current step [N] (float view for atomics),
// w = the floor's normal force [N], already part of F.y (physics/integrate.glsl).
#define B_FORCES 2
// Per node, vec4: xyz = this iteration's summed constraint forces [N].
#define B_CONSTRAINT_SUM 3
// Per spring: GpuSpring.
#define B_SPRINGS 4
// Per tet: uvec4 node indices, positively oriented.
#define B_TETS 5
// Per tet: rest volume [m^3].
#define B_REST_VOLUMES 6
// Per node: its number of constraints of the method's kind d_k (float), for the combine
// mode's factors (physics/implicit.glsl).
#define B_CONSTRAINT_DEGREE 7
// Node -> springs CSR: N + 1 offsets, then the spring indices.
#define B_NODE_SPRING_OFFSETS 8
#define B_NODE_SPRING_ITEMS 9
// Per volume_sum workgroup: VolumePartial.
#define B_VOLUME_PARTIALS 10
// Divergence status (check.comp): flags (1 non-finite, 2 too fast), first bad node
// (u32::MAX when none), speed limit [m/s], unused.
#define B_STATUS 11
// Gather path (Gauss-Seidel by colour groups, no atomics): per constraint, its index, in
// group order (groups are contiguous ranges); per constraint corner, in the same order,
// vec4 -lambda grad_k C; per group and node, the CSR of the node's slots in that group
// (offsets: groups * N + 1; items: indices into the contributions). With several sweeps per
// iteration (implicit springs, then the method's constraints) each buffer holds the sweeps
// one after another: members and contributions from pc.member_first and pc.slot_first, the
// groups (degrees, slot rows) numbered over all sweeps.
#define B_GROUP_MEMBERS 12
#define B_CONTRIBUTIONS 13
#define B_NODE_SLOT_OFFSETS 14
#define B_NODE_SLOT_ITEMS 15
// Global volume constraints: per object a GlobalObject; the surface nodes (node indices,
// object after object); the outward boundary faces (uvec4: three node indices, 0); per
// surface node (its position in SurfaceNodes), the CSR of its face corners (3 face + corner).
#define B_GLOBAL_OBJECTS 16
#define B_SURFACE_NODES 17
#define B_SURFACE_FACES 18
#define B_NODE_FACE_OFFSETS 19
#define B_NODE_FACE_ITEMS 20
// Per surface node, vec4: grad_k C_g of its object at x(t) [m^2], w = its inverse mass
// (written by global_volume_prepare once per step).
#define B_SURFACE_GRADIENTS 21
// Per object, vec4: C_g [m^3], A = sum_k w_k |grad_k C_g|^2, 0, 0 (global_volume_prepare).
#define B_GLOBAL_STATE 22
// Per node, vec4: the force two Chebyshev iterations back (w: its floor force).
#define B_CHEBYSHEV_BEFORE 23
// Per spring: its damping kd_e [N s/m] (its stiffness is Spring.stiffness; the spring force
// and spring_constraint passes read both, the distance pass neither).
#define B_SPRING_DAMPING 24
// Per tet: the compliance alpha_t of its volume constraint [m^3/Pa], 0 = hard (method volume).
#define B_VOLUME_COMPLIANCE 25
// Compliant constraints' multipliers lambda accumulated over the step's iterations so far
// (XPBD-style: B - s lambda; each read and written only by the invocation that solves its
// constraint, treated as 0 in iteration 0, so nothing resets them): per spring (implicit
// springs) and per tet (method volume; hard tets leave theirs unused). With pc.warm_start a
// spring's stored value (the last step's final one) is its multiplier so far in iteration 0.
#define B_SPRING_MULTIPLIERS 26
#define B_VOLUME_MULTIPLIERS 27

// Values of pc.combine (src/gpu/layout.rs, `combine`).
#define COMBINE_SCALED 0u
#define COMBINE_SUM 1u
#define COMBINE_AVERAGE 2u

// One spring: its two nodes, rest length [m] and stiffness k_e [N/m] (16 bytes, one 128-bit
// load; its damping is in SpringDamping).
struct Spring {
    uint a;
    uint b;
    float rest;
    float stiffness;
};

// Partial result of one volume_sum workgroup.
struct VolumePartial {
    float volume;
    uint inverted;
    float local_error; // sum of |V_t - V0_t| [m^3]
    uint pad;
};

// One object's global volume constraint (src/gpu/layout.rs, `GpuGlobalObject`).
struct GlobalObject {
    uint node_first;   // first position in SurfaceNodes
    uint node_count;
    uint face_first;   // first position in SurfaceFaces
    uint face_count;
    float rest_volume; // sum of its tets' rest volumes [m^3]
    uint pad0;
    uint pad1;
    uint pad2;
};

// Derived from SimParams (src/gpu/layout.rs, `PushConstants::from_params`).
layout(push_constant, std430) uniform PushConstants {
    float dt;        // time step [s]
    float omega;     // relaxation of the averaged constraint forces
    uint member_first; // the sweep's first position in Members (gather path)
    uint slot_first;   // the sweep's first slot in Contributions (gather path)
    float gravity;   // gravity magnitude along -Y [m/s^2]
    float friction;  // tangential velocity fraction removed on floor contact
    uint floor_on;   // 1 when the floor y = 0 exists
    uint node_count;
    uint spring_count;
    uint tet_count;
    float epsilon;   // constraints with A <= epsilon are skipped (constraint_epsilon)
    uint combine;    // COMBINE_SCALED, COMBINE_SUM or COMBINE_AVERAGE
    uint group;       // constraint group being solved, counted over every sweep of an
                      // iteration (selects the degrees and slot rows)
    uint group_first; // its first position in its sweep's group-ordered constraints (gather)
    uint group_count; // its constraint count (gather path)
    float chebyshev_weight; // the iteration's Chebyshev weight (solver chebyshev; else 1)
    uint iteration;   // the constraint iteration within the step (0: multipliers start at 0)
    uint warm_start;  // 1: implicit springs' multipliers start at the stored (last step's)
                      // values, applied as forces by spring_warm_start
} pc;

// Index of node i's per-group data (degrees, slot rows) in the current group.
uint group_node(uint i) {
    return pc.group * pc.node_count + i;
}

// Workgroup size along X, chosen by the host from the device limits.
layout(local_size_x_id = 0) in;

#endif
