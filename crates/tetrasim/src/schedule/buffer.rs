//! The data a step reads and writes, named once: every backend keys its arrays by
//! [`BufferId`] (the Vulkan engine its buffers and descriptor bindings), and a [`super::Stage`]
//! lists the ones it reads and writes with their [`Access`].

use crate::gpu::layout::binding;

/// An array of the simulation (a GPU buffer on the Vulkan engine).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BufferId {
    /// vec4 per node: position, inverse mass.
    Positions,
    /// vec4 per node: velocity, mass.
    Velocities,
    /// vec4 per node: the step's force.
    Forces,
    /// 16 bytes per spring: nodes, rest length, stiffness.
    Springs,
    /// float per spring: damping.
    SpringDamping,
    /// uvec4 per tet.
    Tets,
    /// float per tet: rest volume (volume constraints, local volume error).
    RestVolumes,
    /// float per tet: volume compliance (`volume`).
    VolumeCompliance,
    /// float per spring: implicit springs' multipliers so far in the step.
    SpringMultipliers,
    /// float per tet: compliant volume constraints' multipliers so far in the step
    /// (`volume` with constraint iterations).
    VolumeMultipliers,
    /// vec4 per node (`distance`, `volume` with Jacobi: the atomic sums).
    ConstraintSum,
    /// float per group (of every sweep) and node (constraint iterations).
    Degrees,
    /// N + 1 u32 (`mss-node`, gather path of explicit springs, warm-started implicit
    /// springs).
    NodeSpringOffsets,
    /// 2 S u32 (`mss-node`, gather path of explicit springs, warm-started implicit springs).
    NodeSpringItems,
    /// 16 bytes per volume_sum workgroup.
    Partials,
    /// 16 bytes: divergence flags, first bad node, speed limit.
    Status,
    /// u32 per constraint of every sweep, in sweep and group order (gather path).
    GroupMembers,
    /// vec4 per constraint corner, in sweep and group order (gather path).
    Contributions,
    /// `groups * N + 1` u32, groups of every sweep (gather path).
    NodeSlotOffsets,
    /// u32 per constraint corner (gather path).
    NodeSlotItems,
    /// 32 bytes per object (global volume).
    GlobalObjects,
    /// u32 per surface node (global volume).
    SurfaceNodes,
    /// uvec4 per boundary face (global volume).
    SurfaceFaces,
    /// Surface nodes + 1 u32 (global volume).
    NodeFaceOffsets,
    /// 3 u32 per boundary face (global volume).
    NodeFaceItems,
    /// vec4 per surface node (global volume).
    SurfaceGradients,
    /// vec4 per object (global volume).
    GlobalState,
    /// vec4 per node (Chebyshev).
    ChebyshevBefore,
    /// Per surface node, its contact of the step and multiplier (body contact).
    Contacts,
    /// vec4 per node: the colliders' contact force so far in the step (colliders).
    ColliderContacts,
    /// 64 bytes per collider: shape and material (colliders).
    Colliders,
    /// f32 per distance-grid sample of every mesh collider (colliders).
    ColliderGrids,
    /// 64 bytes per frame slot, substep and collider: the step's poses (colliders;
    /// host-visible).
    ColliderPoses,
    /// uvec4 per surface node (node, object), then per surface triangle (nodes, object)
    /// (body contact).
    BodySurface,
    /// u32: per hash bucket its count, per bucket + 1 its offset, then the items (body
    /// contact).
    ContactHash,
    /// vec4 per node: the body contacts' forces of an iteration (float atomics), w the
    /// node's contact count (u32 bits).
    ContactSums,
    /// 32 bytes per clamped node: node, clamp, rest offset from the clamp's centre.
    ClampNodes,
    /// 32 bytes per frame slot, substep and clamp: its pose at the step's end (host-visible).
    ClampPoses,
    /// u32 per node: its row among the grabbed nodes (u32::MAX: none; colliders or grabs).
    GrabNodes,
    /// vec4 per frame slot, substep and grabbed node: its attachment's target and stiffness
    /// (host-visible; colliders or grabs).
    GrabTargets,
    /// vec4 per node: the velocity solve's new velocity (split contact).
    SplitVelocities,
    /// `3 + 2 m` vec4 per node: Anderson acceleration's history (`anderson = m`).
    AndersonHistory,
    /// float per chunk of nodes and Gram term (`anderson`).
    AndersonSums,
    /// `1 + m` floats per spring and tet multiplier (`anderson`).
    AndersonMultipliers,
    /// uvec4 per block: first member, members, first node, nodes | colours << 16 (block
    /// Gauss-Seidel).
    BlockRows,
    /// u32 per block node: its global index, block after block (block Gauss-Seidel).
    BlockNodes,
    /// uvec4 per member of the blocked sweep: its corners' local indices (16 bits each),
    /// its colour (block Gauss-Seidel).
    BlockCorners,
    /// u32: MINRES's rows' transpose, each node's entries (`N + 1` offsets, then an
    /// entry and its row per item), then each entry's node and each global row's first
    /// entry (`minres`).
    MinresTranspose,
    /// vec4 per entry of MINRES's rows: its gradient (`minres`).
    MinresGrads,
    /// float per row of MINRES, per vector of the solve (`minres`).
    MinresVectors,
    /// vec4 per node, twice: MINRES's product `W J^T v`, then its mobility (the held
    /// direction and the inverse mass) (`minres`).
    MinresNodeVectors,
    /// float per workgroup of MINRES's row passes: the partial sums of a dot product, then
    /// a u32 count of the workgroups done (`minres`).
    MinresSums,
    /// 64 bytes per MINRES iteration + 1: the recurrence's scalars (`minres`).
    MinresState,
    /// 64 bytes per tet: the finite elements' shape gradients, rest volume and material
    /// (`neo-hookean`).
    ElasticTets,
    /// N + 1 u32: node -> tet corners offsets (`neo-hookean`).
    NodeTetOffsets,
    /// 4 T u32: node -> tet corners items, `4 tet + corner` (`neo-hookean`).
    NodeTetItems,
    /// `n^2 + n` floats, `n` coarse unknowns: the coarse matrix and its factor
    /// (`neo-hookean`).
    CoarseMatrix,
    /// `n` floats: a coarse right-hand side and its solution (`neo-hookean`).
    CoarseVector,
    /// 6 vec4 per tet: the stiffness at the step's linearisation (`neo-hookean`).
    ElasticLinear,
    /// vec4 per tet corner: products of the tets' stiffness (`neo-hookean`).
    ElasticCorners,
    /// `ELASTIC_PLANES` vec4 per node: the Newton step's node vectors (`neo-hookean`).
    ElasticNodes,
    /// The conjugate gradients' scalars and partial sums (`neo-hookean`).
    ElasticState,
    /// u32: the aggregates' members and each node's aggregate (`neo-hookean`).
    CoarseAggregates,
    /// vec4 per aggregate: its centre and size (`neo-hookean`).
    CoarseModes,
    /// u32: the coarse assembly's items per tet and per block (`neo-hookean`).
    CoarseIndex,
    /// 36 floats per item of the coarse assembly (`neo-hookean`).
    CoarseScratch,
    /// 16 words per object: its nodes and rigid part (`neo-hookean`).
    ElasticObjects,
    /// 2 vec4 per node: what holds it at the frame's last step (forces out).
    ReactionInputs,
    /// vec4 per reaction per `reactions` workgroup (forces out, copied to the host).
    ReactionPartials,
    /// u32 per node: 1 + its clamp (forces out with clamps).
    NodeClamps,
}

impl BufferId {
    /// Debug name of the buffer.
    pub fn name(self) -> &'static str {
        match self {
            BufferId::Positions => "positions",
            BufferId::Velocities => "velocities",
            BufferId::Forces => "forces",
            BufferId::Springs => "springs",
            BufferId::SpringDamping => "spring damping",
            BufferId::Tets => "tets",
            BufferId::RestVolumes => "rest volumes",
            BufferId::VolumeCompliance => "volume compliance",
            BufferId::SpringMultipliers => "spring multipliers",
            BufferId::VolumeMultipliers => "volume multipliers",
            BufferId::ConstraintSum => "constraint sums",
            BufferId::Degrees => "constraint degrees",
            BufferId::NodeSpringOffsets => "node-spring offsets",
            BufferId::NodeSpringItems => "node-spring items",
            BufferId::Partials => "volume partials",
            BufferId::Status => "divergence status",
            BufferId::GroupMembers => "group members",
            BufferId::Contributions => "constraint contributions",
            BufferId::NodeSlotOffsets => "node-slot offsets",
            BufferId::NodeSlotItems => "node-slot items",
            BufferId::GlobalObjects => "global objects",
            BufferId::SurfaceNodes => "surface nodes",
            BufferId::SurfaceFaces => "surface faces",
            BufferId::NodeFaceOffsets => "node-face offsets",
            BufferId::NodeFaceItems => "node-face items",
            BufferId::SurfaceGradients => "surface gradients",
            BufferId::GlobalState => "global state",
            BufferId::ChebyshevBefore => "chebyshev before",
            BufferId::Contacts => "body contacts",
            BufferId::ColliderContacts => "collider contacts",
            BufferId::Colliders => "colliders",
            BufferId::ColliderGrids => "collider grids",
            BufferId::ColliderPoses => "collider poses",
            BufferId::BodySurface => "body contact surface",
            BufferId::ContactHash => "contact hash",
            BufferId::ContactSums => "contact sums",
            BufferId::ClampNodes => "clamp nodes",
            BufferId::ClampPoses => "clamp poses",
            BufferId::GrabNodes => "grab nodes",
            BufferId::GrabTargets => "grab targets",
            BufferId::SplitVelocities => "split velocities",
            BufferId::AndersonHistory => "anderson history",
            BufferId::AndersonSums => "anderson sums",
            BufferId::AndersonMultipliers => "anderson multipliers",
            BufferId::BlockRows => "block rows",
            BufferId::BlockNodes => "block nodes",
            BufferId::BlockCorners => "block corners",
            BufferId::MinresTranspose => "minres transpose",
            BufferId::MinresGrads => "minres gradients",
            BufferId::MinresVectors => "minres vectors",
            BufferId::MinresNodeVectors => "minres node vectors",
            BufferId::MinresSums => "minres sums",
            BufferId::MinresState => "minres state",
            BufferId::ElasticTets => "elastic tets",
            BufferId::NodeTetOffsets => "node-tet offsets",
            BufferId::NodeTetItems => "node-tet items",
            BufferId::CoarseMatrix => "coarse matrix",
            BufferId::CoarseVector => "coarse vector",
            BufferId::ElasticLinear => "elastic linear",
            BufferId::ElasticCorners => "elastic corners",
            BufferId::ElasticNodes => "elastic nodes",
            BufferId::ElasticState => "elastic state",
            BufferId::CoarseAggregates => "coarse aggregates",
            BufferId::CoarseModes => "coarse modes",
            BufferId::CoarseIndex => "coarse index",
            BufferId::CoarseScratch => "coarse scratch",
            BufferId::ElasticObjects => "elastic objects",
            BufferId::ReactionInputs => "reaction inputs",
            BufferId::ReactionPartials => "reaction partials",
            BufferId::NodeClamps => "node clamps",
        }
    }

    /// Descriptor binding number in the shaders (`gpu/bindings.rs`).
    pub fn binding(self) -> u32 {
        match self {
            BufferId::Positions => binding::POSITIONS,
            BufferId::Velocities => binding::VELOCITIES,
            BufferId::Forces => binding::FORCES,
            BufferId::Springs => binding::SPRINGS,
            BufferId::SpringDamping => binding::SPRING_DAMPING,
            BufferId::Tets => binding::TETS,
            BufferId::RestVolumes => binding::REST_VOLUMES,
            BufferId::VolumeCompliance => binding::VOLUME_COMPLIANCE,
            BufferId::SpringMultipliers => binding::SPRING_MULTIPLIERS,
            BufferId::VolumeMultipliers => binding::VOLUME_MULTIPLIERS,
            BufferId::ConstraintSum => binding::CONSTRAINT_SUM,
            BufferId::Degrees => binding::CONSTRAINT_DEGREE,
            BufferId::NodeSpringOffsets => binding::NODE_SPRING_OFFSETS,
            BufferId::NodeSpringItems => binding::NODE_SPRING_ITEMS,
            BufferId::Partials => binding::VOLUME_PARTIALS,
            BufferId::Status => binding::STATUS,
            BufferId::GroupMembers => binding::GROUP_MEMBERS,
            BufferId::Contributions => binding::CONTRIBUTIONS,
            BufferId::NodeSlotOffsets => binding::NODE_SLOT_OFFSETS,
            BufferId::NodeSlotItems => binding::NODE_SLOT_ITEMS,
            BufferId::GlobalObjects => binding::GLOBAL_OBJECTS,
            BufferId::SurfaceNodes => binding::SURFACE_NODES,
            BufferId::SurfaceFaces => binding::SURFACE_FACES,
            BufferId::NodeFaceOffsets => binding::NODE_FACE_OFFSETS,
            BufferId::NodeFaceItems => binding::NODE_FACE_ITEMS,
            BufferId::SurfaceGradients => binding::SURFACE_GRADIENTS,
            BufferId::GlobalState => binding::GLOBAL_STATE,
            BufferId::ChebyshevBefore => binding::CHEBYSHEV_BEFORE,
            BufferId::Contacts => binding::CONTACTS,
            BufferId::ColliderContacts => binding::COLLIDER_CONTACTS,
            BufferId::Colliders => binding::COLLIDERS,
            BufferId::ColliderGrids => binding::COLLIDER_GRIDS,
            BufferId::ColliderPoses => binding::COLLIDER_POSES,
            BufferId::BodySurface => binding::BODY_SURFACE,
            BufferId::ContactHash => binding::CONTACT_HASH,
            BufferId::ContactSums => binding::CONTACT_SUMS,
            BufferId::ClampNodes => binding::CLAMP_NODES,
            BufferId::ClampPoses => binding::CLAMP_POSES,
            BufferId::GrabNodes => binding::GRAB_NODES,
            BufferId::GrabTargets => binding::GRAB_TARGETS,
            BufferId::SplitVelocities => binding::SPLIT_VELOCITIES,
            BufferId::AndersonHistory => binding::ANDERSON_HISTORY,
            BufferId::AndersonSums => binding::ANDERSON_SUMS,
            BufferId::AndersonMultipliers => binding::ANDERSON_MULTIPLIERS,
            BufferId::BlockRows => binding::BLOCK_ROWS,
            BufferId::BlockNodes => binding::BLOCK_NODES,
            BufferId::BlockCorners => binding::BLOCK_CORNERS,
            BufferId::MinresTranspose => binding::MINRES_TRANSPOSE,
            BufferId::MinresGrads => binding::MINRES_GRADS,
            BufferId::MinresVectors => binding::MINRES_VECTORS,
            BufferId::MinresNodeVectors => binding::MINRES_NODE_VECTORS,
            BufferId::MinresSums => binding::MINRES_SUMS,
            BufferId::MinresState => binding::MINRES_STATE,
            BufferId::ElasticTets => binding::ELASTIC_TETS,
            BufferId::NodeTetOffsets => binding::NODE_TET_OFFSETS,
            BufferId::NodeTetItems => binding::NODE_TET_ITEMS,
            BufferId::CoarseMatrix => binding::COARSE_MATRIX,
            BufferId::CoarseVector => binding::COARSE_VECTOR,
            BufferId::ElasticLinear => binding::ELASTIC_LINEAR,
            BufferId::ElasticCorners => binding::ELASTIC_CORNERS,
            BufferId::ElasticNodes => binding::ELASTIC_NODES,
            BufferId::ElasticState => binding::ELASTIC_STATE,
            BufferId::CoarseAggregates => binding::COARSE_AGGREGATES,
            BufferId::CoarseModes => binding::COARSE_MODES,
            BufferId::CoarseIndex => binding::COARSE_INDEX,
            BufferId::CoarseScratch => binding::COARSE_SCRATCH,
            BufferId::ElasticObjects => binding::ELASTIC_OBJECTS,
            BufferId::ReactionInputs => binding::REACTION_INPUTS,
            BufferId::ReactionPartials => binding::REACTION_PARTIALS,
            BufferId::NodeClamps => binding::NODE_CLAMPS,
        }
    }
}

/// How a stage uses an array.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Only reads it.
    Read,
    /// Reads and writes it (a barrier follows the pass).
    ReadWrite,
    /// Only writes it (a barrier follows the pass).
    Write,
}
