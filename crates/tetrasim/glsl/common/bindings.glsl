// Descriptor bindings (set 0) and the push-constant block shared by every pass.
// The host side is src/gpu/layout.rs (`binding::*` from src/gpu/bindings.rs, `PushConstants`,
// `GpuSpring`, `VolumePartial`); a test there checks the bindings and offsets in the
// compiled SPIR-V.
#ifndef COMMON_BINDINGS_GLSL
#define COMMON_BINDINGS_GLSL

// The descriptor bindings B_POSITIONS, B_VELOCITIES, ... are not defined here: build.rs
// compiles every shader with one macro B_<NAME> per entry of src/gpu/bindings.rs, the list
// the host's binding numbers come from too (what each buffer holds is documented there).
#if !defined(B_POSITIONS) || !defined(B_VOLUME_MULTIPLIERS)
#error "the B_* binding macros are missing: compile through build.rs"
#endif

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
    vec3 gravity;    // gravity's acceleration [m/s^2] (offset 16: a vec3's alignment)
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
    uint collider_first; // the substep's first entry in ColliderPoses (colliders)
    uint step_row;    // frame slot * substeps + substep: the step's row of ClampPoses
    uint grab_first;  // step_row * grabbed nodes: the step's first entry in GrabTargets
    uint phase;       // PHASE_FULL, or PHASE_VELOCITY in split contact's velocity solve
                      // (physics/solve.glsl)
    uint block_first; // the sweep's first row in BlockRows (block Gauss-Seidel)
} pc;

// Index of node i's per-group data (degrees, slot rows) in the current group.
uint group_node(uint i) {
    return pc.group * pc.node_count + i;
}

// Workgroup size along X, chosen by the host from the device limits.
layout(local_size_x_id = 0) in;

#endif
