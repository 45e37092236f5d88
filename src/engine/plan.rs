//! What the `vulkan` backend builds for a model and its parameters, decided in one place:
//! the buffers (with sizes), the passes (with their bindings, repetition and
//! specialisation) and the host copies of a frame. [`super::VulkanBackend`] creates exactly
//! these buffers and pipelines and records exactly these passes, and checks every created
//! buffer's size against the plan, so `tetrasim plan` (which prints this without a GPU)
//! cannot drift from the engine.
//!
//! What a scene does not use is not built: no degrees without constraint iterations
//! (`distance`, `volume` or implicit springs), atomic constraint sums only for Jacobi and the
//! gather path's buffers (group members, contributions, node-slot CSR) only for
//! Gauss-Seidel, no spring force pass with implicit springs (but the `spring_warm_start`
//! pass when they are warm-started), no node-spring adjacency without `mss-node`, the
//! gather path of explicit springs or warm-started implicit springs, no volume compliances
//! without `volume`, no floor test in `integrate` without a floor
//! (specialisation constant 1), and no `volume_sum` pass or partials copy in the frame
//! without per-frame metrics. The `check` pass (divergence) and its 16-byte status copy are
//! always there, and so are the rest volumes (the local volume error needs them).

use std::fmt::Write as _;

use super::pass_kind::PassKind;
use crate::gpu::layout::binding;
use crate::model::{ConstraintKind, Sweep};
use crate::params::{chebyshev_weights, Method, SimParams, Solver, SpringKind};

/// A GPU buffer of the simulation.
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
        }
    }

    /// Descriptor binding number in the shaders.
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
        }
    }
}

/// How a pass uses a bound buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Only reads it.
    Read,
    /// Reads and writes it (a barrier follows the pass).
    ReadWrite,
    /// Only writes it (a barrier follows the pass).
    Write,
}

/// How often a pass runs in a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Repeat {
    /// Once per time step.
    Substep,
    /// `iterations` times per time step and, within an iteration, once per constraint group:
    /// a pass of one sweep ([`PassPlan::sweep`]) for each of that sweep's groups, followed
    /// each time by the passes of no sweep (consecutive such passes repeat together).
    Iteration,
    /// Once per iteration, after its constraint groups (the global volume constraints).
    IterationEnd,
    /// Once per frame, after the last time step.
    Frame,
}

/// One planned buffer.
#[derive(Debug, Clone, PartialEq)]
pub struct BufferPlan {
    /// Which buffer.
    pub id: BufferId,
    /// Device-local size [bytes] (at least 4, as [`crate::gpu::Buffer`] allocates).
    pub bytes: u64,
    /// Size of its host-visible copy written every frame [bytes], 0 when there is none.
    pub readback_bytes: u64,
}

/// Which compiled variant of a pass's shader runs (build.rs, `// @variant`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// The shader has no variants.
    Plain,
    /// `#ext` or `#cas`, whichever float-atomic path the device uses.
    Atomics,
    /// A named variant, e.g. `gather`.
    Named(&'static str),
}

/// One planned compute pass.
#[derive(Debug, Clone, PartialEq)]
pub struct PassPlan {
    /// Which pass (its name in the timing report and its shader).
    pub kind: PassKind,
    /// Which of the shader's variants.
    pub variant: Variant,
    /// Specialisation constants from id 1 on (id 0 is the workgroup size).
    pub constants: Vec<u32>,
    /// Invocations (one per node, spring or tet; for a constraint pass of the gather path,
    /// all constraints, of which each dispatch covers one group's).
    pub elements: u32,
    /// Whether each dispatch covers only the current group's constraints.
    pub per_group: bool,
    /// The sweep ([`EnginePlan::sweeps`]) whose constraints the pass solves, for the
    /// constraint passes; `None` for the others (an [`Repeat::Iteration`] pass of no sweep
    /// follows every group of every sweep).
    pub sweep: Option<usize>,
    /// Bound buffers and how the pass uses them.
    pub bindings: Vec<(BufferId, Access)>,
    /// How often it runs.
    pub repeat: Repeat,
}

impl PassPlan {
    /// Name with its variant and specialisation, e.g. `constraint_apply#gather[floor]`.
    pub fn label(&self) -> String {
        let variant = match self.variant {
            Variant::Named(v) => format!("#{v}"),
            _ => String::new(),
        };
        let floor = match (self.kind.has_floor_constant(), self.constants.first()) {
            (true, Some(1)) => "[floor]",
            (true, Some(_)) => "[no floor]",
            _ => "",
        };
        format!("{}{variant}{floor}", self.name())
    }

    /// The pass's name (the shader's file stem), as timings and records print it.
    pub fn name(&self) -> &'static str {
        self.kind.name()
    }

    /// The shader module's key in [`crate::shaders::SHADERS`] for a device on `atomics`.
    pub fn shader_key(&self, atomics: &str) -> String {
        let shader = self.kind.shader();
        match self.variant {
            Variant::Plain => shader.to_string(),
            Variant::Atomics => format!("{shader}#{atomics}"),
            Variant::Named(v) => format!("{shader}#{v}"),
        }
    }
}

/// Element counts of a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlanCounts {
    /// Nodes.
    pub nodes: u32,
    /// Springs.
    pub springs: u32,
    /// Tetrahedra.
    pub tets: u32,
}

impl PlanCounts {
    /// The counts of `model` (an error when one exceeds the engine's u32 indices).
    pub fn of(model: &crate::model::Model) -> crate::Result<Self> {
        let count = |what: &str, n: usize| {
            u32::try_from(n).map_err(|_| {
                crate::Error::Mesh(format!("{n} {what} exceed the GPU engine's u32 indices"))
            })
        };
        Ok(PlanCounts {
            nodes: count("nodes", model.node_count())?,
            springs: count("springs", model.springs.len())?,
            tets: count("tets", model.tets.len())?,
        })
    }
}

/// Peak memory bandwidth of some GPUs [bytes/s], from the vendors' data sheets, for the
/// memory-bound estimate `tetrasim plan` prints.
pub const PEAK_BANDWIDTH: [(&str, f64); 4] = [
    ("NVIDIA H100 SXM5 80GB", 3.35e12),
    ("NVIDIA A100 SXM4 80GB", 2.039e12),
    ("NVIDIA GeForce RTX 4090", 1.008e12),
    ("NVIDIA GeForce RTX 3060", 360e9),
];

/// Sizes of the global volume constraints ([`crate::model::GlobalVolume`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GlobalCounts {
    /// Objects (one constraint and one workgroup each).
    pub objects: u32,
    /// Surface nodes of all objects.
    pub nodes: u32,
    /// Boundary faces of all objects.
    pub faces: u32,
}

impl GlobalCounts {
    /// The sizes of `global`.
    pub fn of(global: &crate::model::GlobalVolume) -> Self {
        GlobalCounts {
            objects: global.objects.len() as u32,
            nodes: global.nodes.len() as u32,
            faces: global.faces.len() as u32,
        }
    }
}

/// One constraint sweep of an iteration ([`Model::constraint_sweeps`](crate::model::Model::constraint_sweeps)):
/// its kind and the sizes of its groups.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SweepPlan {
    /// What the constraints are.
    pub kind: ConstraintKind,
    /// Constraints per group, solved one group after another.
    pub groups: Vec<u32>,
}

impl SweepPlan {
    /// The kind and group sizes of `sweep`.
    pub fn of(sweep: &Sweep) -> Self {
        SweepPlan {
            kind: sweep.kind,
            groups: sweep.groups.sizes(),
        }
    }

    /// The pass that solves it.
    pub fn pass(&self) -> PassKind {
        match self.kind {
            ConstraintKind::Spring => PassKind::SpringConstraint,
            ConstraintKind::Distance => PassKind::Distance,
            ConstraintKind::Volume => PassKind::Volume,
        }
    }

    /// Nodes per constraint (contribution slots per constraint on the gather path).
    pub fn corners(&self) -> u64 {
        match self.kind {
            ConstraintKind::Volume => 4,
            ConstraintKind::Spring | ConstraintKind::Distance => 2,
        }
    }

    /// Constraints of all its groups.
    pub fn constraints(&self) -> u64 {
        self.groups.iter().map(|&g| u64::from(g)).sum()
    }
}

/// Where one sweep's data starts in the buffers that hold every sweep one after another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SweepOffsets {
    /// Its first group, counted over all sweeps (degrees, slot rows).
    pub group: u32,
    /// Its first position in the group members.
    pub member: u32,
    /// Its first slot in the contributions.
    pub slot: u32,
}

/// Everything the engine builds and does per frame.
#[derive(Debug, Clone, PartialEq)]
pub struct EnginePlan {
    /// Method.
    pub method: Method,
    /// Explicit spring forces or implicit spring constraints.
    pub springs: SpringKind,
    /// Whether implicit springs are warm-started (`warm_start`): the `spring_warm_start`
    /// pass applies the stored multipliers as forces before the first iteration, which
    /// `spring_constraint` then takes as the multipliers so far in iteration 0.
    pub warm_start: bool,
    /// Element counts.
    pub counts: PlanCounts,
    /// Time steps per frame.
    pub substeps: u32,
    /// Constraint iterations per time step.
    pub iterations: u32,
    /// The constraint sweeps of an iteration, in order (implicit springs, then the method's
    /// constraints; empty without constraint iterations).
    pub sweeps: Vec<SweepPlan>,
    /// Constraints per group of every sweep, sweep after sweep, solved one group after
    /// another in each iteration (one group per sweep for Jacobi; empty without constraint
    /// iterations). A group's index here numbers its degrees and slot rows.
    pub groups: Vec<u32>,
    /// Whether constraint forces are gathered per node (no float atomics: Gauss-Seidel).
    pub gather: bool,
    /// The global volume constraints' sizes, when solved.
    pub global: Option<GlobalCounts>,
    /// The Chebyshev weight of each iteration (solver `chebyshev`; empty otherwise).
    pub chebyshev: Vec<f32>,
    /// Invocations per workgroup.
    pub workgroup_size: u32,
    /// Whether the frame measures the volume (`volume_sum` + partials copy).
    pub metrics: bool,
    /// Buffers, in creation order.
    pub buffers: Vec<BufferPlan>,
    /// Passes in execution order: the time step's (repeated `substeps` times), then the
    /// frame's.
    pub passes: Vec<PassPlan>,
}

/// Size a [`crate::gpu::Buffer`] of `bytes` really has.
fn alloc(bytes: u64) -> u64 {
    bytes.max(4)
}

impl EnginePlan {
    /// The plan for `model` under `params` (computing its constraint groups and global
    /// volume constraints), with `workgroup_size` invocations per group and per-frame volume
    /// `metrics` or not.
    pub fn for_model(
        model: &crate::model::Model,
        params: &SimParams,
        workgroup_size: u32,
        metrics: bool,
    ) -> crate::Result<Self> {
        let sweeps: Vec<SweepPlan> = model
            .constraint_sweeps(params)
            .iter()
            .map(SweepPlan::of)
            .collect();
        let global = params
            .solves_global_volume()
            .then(|| GlobalCounts::of(&crate::model::GlobalVolume::new(model)));
        Ok(EnginePlan::new(
            PlanCounts::of(model)?,
            params,
            workgroup_size,
            metrics,
            &sweeps,
            global,
        ))
    }

    /// The plan for a model of `counts` under `params`, with `workgroup_size` invocations per
    /// group, per-frame volume `metrics` or not, the constraint `sweeps` of an iteration
    /// ([`crate::model::Model::constraint_sweeps`] under `params`) and the `global` volume
    /// constraints' sizes when `params.global_volume` asks for them.
    pub fn new(
        counts: PlanCounts,
        params: &SimParams,
        workgroup_size: u32,
        metrics: bool,
        sweeps: &[SweepPlan],
        global: Option<GlobalCounts>,
    ) -> Self {
        use Access::{Read, ReadWrite, Write};
        use BufferId::*;
        let (n, s, t) = (
            u64::from(counts.nodes),
            u64::from(counts.springs),
            u64::from(counts.tets),
        );
        let method = params.method;
        let sweeps = sweeps.to_vec();
        let constrained = !sweeps.is_empty();
        let gather = constrained && params.solver == Solver::GaussSeidel;
        let chebyshev: Vec<f32> = match constrained && params.solver == Solver::Chebyshev {
            true => chebyshev_weights(params.rho, params.iterations)
                .into_iter()
                .map(|w| w as f32)
                .collect(),
            false => Vec::new(),
        };
        let groups: Vec<u32> = sweeps.iter().flat_map(|w| w.groups.clone()).collect();
        let k = groups.len().max(1) as u64;
        // Constraints and their slots (corners), of every sweep.
        let constraints: u64 = sweeps.iter().map(SweepPlan::constraints).sum();
        let slots: u64 = sweeps.iter().map(|w| w.corners() * w.constraints()).sum();
        let workgroups = u64::from(counts.tets.div_ceil(workgroup_size.max(1)));
        let mut buffers = vec![
            (Positions, 16 * n, 0),
            (Velocities, 16 * n, 0),
            (Forces, 16 * n, 0),
            (Springs, 16 * s, 0),
            (SpringDamping, 4 * s, 0),
            (Tets, 16 * t, 0),
        ];
        // Rest volumes: the volume constraints' and the local volume error's.
        buffers.push((RestVolumes, 4 * t, 0));
        if method == Method::Volume {
            buffers.push((VolumeCompliance, 4 * t, 0));
        }
        if constrained {
            buffers.push((Degrees, 4 * k * n, 0));
            match gather {
                true => {
                    buffers.push((GroupMembers, 4 * constraints, 0));
                    buffers.push((Contributions, 16 * slots, 0));
                    buffers.push((NodeSlotOffsets, 4 * (k * n + 1), 0));
                    buffers.push((NodeSlotItems, 4 * slots, 0));
                }
                false => buffers.push((ConstraintSum, 16 * n, 0)),
            }
            if !chebyshev.is_empty() {
                buffers.push((ChebyshevBefore, 16 * n, 0));
            }
            // The compliant constraints' multipliers so far in the step, one float per
            // constraint of a sweep that tracks them. Volume sweeps always get theirs: the
            // plan sees counts and parameters, not the per-tet compliances (a material's
            // young's modulus or an object's own material may make any tet compliant), and
            // 4 bytes per tet are what the compliances already take; hard tets never touch
            // their entry.
            for kind in [ConstraintKind::Spring, ConstraintKind::Volume] {
                if sweeps.iter().any(|w| w.kind == kind) {
                    buffers.push(match kind {
                        ConstraintKind::Spring => (SpringMultipliers, 4 * s, 0),
                        _ => (VolumeMultipliers, 4 * t, 0),
                    });
                }
            }
        }
        let global = global.filter(|_| params.solves_global_volume());
        if let Some(g) = global {
            let (objects, nodes, faces) =
                (u64::from(g.objects), u64::from(g.nodes), u64::from(g.faces));
            buffers.push((GlobalObjects, 32 * objects, 0));
            buffers.push((SurfaceNodes, 4 * nodes, 0));
            buffers.push((SurfaceFaces, 16 * faces, 0));
            buffers.push((NodeFaceOffsets, 4 * (nodes + 1), 0));
            buffers.push((NodeFaceItems, 4 * 3 * faces, 0));
            buffers.push((SurfaceGradients, 16 * nodes, 0));
            buffers.push((GlobalState, 16 * objects, 0));
        }
        // Explicit spring forces are gathered per node for mss-node, and on the gather path
        // so that nothing in its step uses float atomics; implicit springs have no force
        // pass (F starts as m g, which `integrate` and the initial upload leave).
        let spring_forces = params.springs == SpringKind::Explicit;
        let spring_gather = spring_forces && (method == Method::MssNode || gather);
        // Warm-started implicit springs apply their stored multipliers as forces, gathered
        // per node (no atomics), before the first iteration.
        let warm_start = params.springs == SpringKind::Implicit
            && params.warm_start
            && sweeps.iter().any(|w| w.kind == ConstraintKind::Spring);
        if spring_gather || warm_start {
            buffers.push((NodeSpringOffsets, 4 * (n + 1), 0));
            buffers.push((NodeSpringItems, 4 * 2 * s, 0));
        }
        // The partials stay for on-demand measurements; they are copied per frame only
        // with metrics.
        let partial_bytes = 16 * workgroups;
        buffers.push((
            Partials,
            partial_bytes,
            if metrics { alloc(partial_bytes) } else { 0 },
        ));
        buffers.push((Status, 16, 16));
        let buffers = buffers
            .into_iter()
            .map(|(id, bytes, readback_bytes)| BufferPlan {
                id,
                bytes: alloc(bytes),
                readback_bytes,
            })
            .collect();

        let pass = |kind, variant, elements, bindings: Vec<_>, repeat| PassPlan {
            kind,
            variant,
            constants: Vec::new(),
            elements,
            per_group: false,
            sweep: None,
            bindings,
            repeat,
        };
        let mut passes = Vec::new();
        if spring_forces {
            passes.push(match spring_gather {
                true => pass(
                    PassKind::SpringGather,
                    Variant::Plain,
                    counts.nodes,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Springs, Read),
                        (SpringDamping, Read),
                        (NodeSpringOffsets, Read),
                        (NodeSpringItems, Read),
                        (Forces, ReadWrite),
                    ],
                    Repeat::Substep,
                ),
                false => pass(
                    PassKind::SpringScatter,
                    Variant::Atomics,
                    counts.springs,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Springs, Read),
                        (SpringDamping, Read),
                        (Forces, ReadWrite),
                    ],
                    Repeat::Substep,
                ),
            });
        }
        if warm_start {
            passes.push(pass(
                PassKind::SpringWarmStart,
                Variant::Plain,
                counts.nodes,
                vec![
                    (Positions, Read),
                    (Springs, Read),
                    (SpringMultipliers, Read),
                    (NodeSpringOffsets, Read),
                    (NodeSpringItems, Read),
                    (Forces, ReadWrite),
                ],
                Repeat::Substep,
            ));
        }
        if let Some(g) = global {
            passes.push(pass(
                PassKind::GlobalVolumePrepare,
                Variant::Plain,
                g.objects * workgroup_size,
                vec![
                    (Positions, Read),
                    (GlobalObjects, Read),
                    (SurfaceNodes, Read),
                    (SurfaceFaces, Read),
                    (NodeFaceOffsets, Read),
                    (NodeFaceItems, Read),
                    (SurfaceGradients, Write),
                    (GlobalState, Write),
                ],
                Repeat::Substep,
            ));
        }
        if constrained {
            let (variant, output) = match gather {
                true => (
                    Variant::Named("gather"),
                    vec![(GroupMembers, Read), (Contributions, Write)],
                ),
                false => (Variant::Atomics, vec![(ConstraintSum, ReadWrite)]),
            };
            for (index, sweep) in sweeps.iter().enumerate() {
                let (elements, element_data) = match sweep.kind {
                    ConstraintKind::Volume => (
                        counts.tets,
                        vec![
                            (Tets, Read),
                            (RestVolumes, Read),
                            (VolumeCompliance, Read),
                            (VolumeMultipliers, ReadWrite),
                        ],
                    ),
                    ConstraintKind::Spring => (
                        counts.springs,
                        vec![
                            (Springs, Read),
                            (SpringDamping, Read),
                            (SpringMultipliers, ReadWrite),
                        ],
                    ),
                    ConstraintKind::Distance => (counts.springs, vec![(Springs, Read)]),
                };
                let mut bindings = vec![(Positions, Read), (Velocities, Read), (Forces, Read)];
                bindings.extend(element_data);
                bindings.push((Degrees, Read));
                bindings.extend(output.iter().copied());
                let mut solve = pass(sweep.pass(), variant, elements, bindings, Repeat::Iteration);
                solve.per_group = gather;
                solve.sweep = Some(index);
                passes.push(solve);
            }
            let (variant, input) = match gather {
                true => (
                    Variant::Named("gather"),
                    vec![
                        (Contributions, Read),
                        (NodeSlotOffsets, Read),
                        (NodeSlotItems, Read),
                    ],
                ),
                false if !chebyshev.is_empty() => (
                    Variant::Named("chebyshev"),
                    vec![(ConstraintSum, ReadWrite), (ChebyshevBefore, ReadWrite)],
                ),
                false => (Variant::Named("sums"), vec![(ConstraintSum, ReadWrite)]),
            };
            let mut apply = pass(
                PassKind::ConstraintApply,
                variant,
                counts.nodes,
                vec![
                    (Positions, Read),
                    (Velocities, Read),
                    (Forces, ReadWrite),
                    (Degrees, Read),
                ],
                Repeat::Iteration,
            );
            apply.bindings.extend(input);
            apply.constants = vec![u32::from(params.floor)];
            passes.push(apply);
            if let Some(g) = global {
                let mut global_pass = pass(
                    PassKind::GlobalVolume,
                    Variant::Plain,
                    g.objects * workgroup_size,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Forces, ReadWrite),
                        (GlobalObjects, Read),
                        (SurfaceNodes, Read),
                        (SurfaceGradients, Read),
                        (GlobalState, Read),
                    ],
                    Repeat::IterationEnd,
                );
                global_pass.constants = vec![u32::from(params.floor)];
                passes.push(global_pass);
            }
        }
        let mut integrate = pass(
            PassKind::Integrate,
            Variant::Plain,
            counts.nodes,
            vec![
                (Positions, ReadWrite),
                (Velocities, ReadWrite),
                (Forces, ReadWrite),
            ],
            Repeat::Substep,
        );
        integrate.constants = vec![u32::from(params.floor)];
        passes.push(integrate);
        passes.push(pass(
            PassKind::Check,
            Variant::Plain,
            counts.nodes,
            vec![(Positions, Read), (Velocities, Read), (Status, ReadWrite)],
            Repeat::Frame,
        ));
        if metrics {
            passes.push(volume_sum_pass(counts));
        }
        EnginePlan {
            method,
            springs: params.springs,
            warm_start,
            counts,
            substeps: params.substeps,
            iterations: params.iterations,
            sweeps,
            groups,
            gather,
            global,
            chebyshev,
            workgroup_size,
            metrics,
            buffers,
            passes,
        }
    }

    /// Whether buffer `id` is built.
    pub fn has(&self, id: BufferId) -> bool {
        self.buffers.iter().any(|b| b.id == id)
    }

    /// The plan of buffer `id`, if it is built.
    pub fn buffer(&self, id: BufferId) -> Option<&BufferPlan> {
        self.buffers.iter().find(|b| b.id == id)
    }

    /// Whether pass `name` is part of the frame.
    pub fn has_pass(&self, name: &str) -> bool {
        PassKind::from_name(name).is_some_and(|k| self.runs(k))
    }

    /// Whether `pass` is part of the frame.
    pub fn runs(&self, pass: PassKind) -> bool {
        self.passes.iter().any(|p| p.kind == pass)
    }

    /// How many times `pass` runs in a frame.
    pub fn runs_per_frame(&self, pass: &PassPlan) -> u32 {
        match pass.repeat {
            Repeat::Substep => self.substeps,
            Repeat::Iteration => self.substeps * self.iterations * self.groups_of(pass),
            Repeat::IterationEnd => self.substeps * self.iterations,
            Repeat::Frame => 1,
        }
    }

    /// Constraint groups solved one after another per iteration, over all sweeps (at
    /// least 1).
    pub fn group_count(&self) -> u32 {
        self.groups.len().max(1) as u32
    }

    /// The groups a per-iteration pass runs for in one iteration: its sweep's, or every
    /// sweep's for a pass of no sweep (at least 1).
    fn groups_of(&self, pass: &PassPlan) -> u32 {
        match pass.sweep.and_then(|s| self.sweeps.get(s)) {
            Some(sweep) => sweep.groups.len().max(1) as u32,
            None => self.group_count(),
        }
    }

    /// Where sweep `index`'s groups, members and slots start in the buffers that hold every
    /// sweep one after another (degrees, group members, contributions, node-slot CSR).
    pub fn sweep_offsets(&self, index: usize) -> SweepOffsets {
        let mut at = SweepOffsets::default();
        for sweep in &self.sweeps[..index.min(self.sweeps.len())] {
            at.group += sweep.groups.len() as u32;
            at.member += sweep.constraints() as u32;
            at.slot += (sweep.corners() * sweep.constraints()) as u32;
        }
        at
    }

    /// Dispatches of one frame (the timestamp count).
    pub fn dispatches_per_frame(&self) -> u32 {
        self.passes.iter().map(|p| self.runs_per_frame(p)).sum()
    }

    /// Labels of every pass in execution order: one time step's (the iteration group
    /// written `N x (a, b)`), then the frame's.
    pub fn pass_list(&self) -> Vec<String> {
        let mut out = self.step_list();
        out.extend(
            self.passes
                .iter()
                .filter(|p| p.repeat == Repeat::Frame)
                .map(PassPlan::label),
        );
        out
    }

    /// Device-local bytes of all buffers.
    pub fn device_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.bytes).sum()
    }

    /// Host-visible bytes copied back every frame.
    pub fn readback_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.readback_bytes).sum()
    }

    /// Bytes `pass` moves per run, estimated as every bound buffer streamed once per read
    /// and once per write (gathers through indices make the real traffic larger). A pass run
    /// once per constraint group streams only its group's share of its sweep's element
    /// buffers and of the buffers that hold every sweep's groups (degrees, members,
    /// contributions, slots).
    pub fn pass_bytes(&self, pass: &PassPlan) -> u64 {
        let all_groups = u64::from(self.group_count());
        let sweep_groups = u64::from(self.groups_of(pass));
        pass.bindings
            .iter()
            .map(|(id, access)| {
                let size = self.buffer(*id).map_or(0, |b| b.bytes);
                let size = match (pass.repeat, id) {
                    (
                        Repeat::Iteration,
                        BufferId::Tets
                        | BufferId::RestVolumes
                        | BufferId::VolumeCompliance
                        | BufferId::VolumeMultipliers
                        | BufferId::Springs
                        | BufferId::SpringMultipliers
                        | BufferId::SpringDamping,
                    ) => size / sweep_groups,
                    (
                        Repeat::Iteration,
                        BufferId::Degrees
                        | BufferId::GroupMembers
                        | BufferId::Contributions
                        | BufferId::NodeSlotOffsets
                        | BufferId::NodeSlotItems,
                    ) => size / all_groups,
                    _ => size,
                };
                match access {
                    Access::Read | Access::Write => size,
                    Access::ReadWrite => 2 * size,
                }
            })
            .sum()
    }

    /// Estimated bytes moved per frame: every pass run plus the host copies.
    pub fn bytes_per_frame(&self) -> u64 {
        let passes: u64 = self
            .passes
            .iter()
            .map(|p| u64::from(self.runs_per_frame(p)) * self.pass_bytes(p))
            .sum();
        passes + 2 * self.readback_bytes()
    }

    /// The plan as text (what `tetrasim plan` prints).
    pub fn render(&self) -> String {
        let mut out = String::new();
        let c = self.counts;
        let springs = match (self.springs, self.warm_start) {
            (SpringKind::Explicit, _) => "",
            (SpringKind::Implicit, false) => " with implicit springs",
            (SpringKind::Implicit, true) => " with warm-started implicit springs",
        };
        let _ = writeln!(
            out,
            "method {}{springs}: {} nodes, {} springs, {} tets; {} substeps x {} iterations, \
             workgroup {}",
            self.method,
            c.nodes,
            c.springs,
            c.tets,
            self.substeps,
            self.iterations,
            self.workgroup_size
        );
        let _ = writeln!(out, "per time step: {}", self.step_list().join(" -> "));
        let frame: Vec<String> = self
            .passes
            .iter()
            .filter(|p| p.repeat == Repeat::Frame)
            .map(PassPlan::label)
            .collect();
        let _ = writeln!(
            out,
            "per frame, after the last step: {} -> copy {} B to the host",
            frame.join(" -> "),
            self.readback_bytes()
        );
        let _ = writeln!(
            out,
            "{:<22} {:>14} {:>10}",
            "buffer", "device bytes", "readback"
        );
        for b in &self.buffers {
            let _ = writeln!(
                out,
                "{:<22} {:>14} {:>10}",
                b.id.name(),
                b.bytes,
                b.readback_bytes
            );
        }
        let _ = writeln!(
            out,
            "total device memory {} B ({:.2} MiB); dispatches per frame {}",
            self.device_bytes(),
            self.device_bytes() as f64 / (1024.0 * 1024.0),
            self.dispatches_per_frame()
        );
        let _ = writeln!(out, "{:<22} {:>6} {:>14}", "pass", "runs", "bytes per run");
        for p in &self.passes {
            let _ = writeln!(
                out,
                "{:<22} {:>6} {:>14}",
                p.label(),
                self.runs_per_frame(p),
                self.pass_bytes(p)
            );
        }
        let _ = writeln!(
            out,
            "estimated bytes moved per frame {} ({:.2} MiB)",
            self.bytes_per_frame(),
            self.bytes_per_frame() as f64 / (1024.0 * 1024.0)
        );
        let _ = writeln!(
            out,
            "memory-bound time per frame at peak bandwidth (bytes / bandwidth; dispatch and \
             latency costs come on top):"
        );
        for (gpu, bandwidth) in PEAK_BANDWIDTH {
            let _ = writeln!(
                out,
                "  {gpu:<28} {:>7.0} GB/s {:>10.1} us",
                bandwidth / 1e9,
                1e6 * self.bytes_per_frame() as f64 / bandwidth
            );
        }
        out
    }

    /// `10 x (a, b)`, `10 x 8 groups x (a, b)` with several constraint groups,
    /// `10 x (8 groups x (a, b), c)` with passes after the groups, and one such part per
    /// sweep, `10 x (8 groups x (s, b), 8 groups x (a, b), c)`: each sweep's pass followed
    /// by the passes of no sweep.
    fn iteration_label(&self, passes: &[&PassPlan], after: &[String]) -> String {
        let shared: Vec<String> = passes
            .iter()
            .filter(|p| p.sweep.is_none())
            .map(|p| p.label())
            .collect();
        let parts: Vec<(usize, String)> = self
            .sweeps
            .iter()
            .enumerate()
            .map(|(index, sweep)| {
                let mut labels: Vec<String> = passes
                    .iter()
                    .filter(|p| p.sweep == Some(index))
                    .map(|p| p.label())
                    .collect();
                labels.extend(shared.iter().cloned());
                let text = match sweep.groups.len() {
                    0 | 1 => labels.join(", "),
                    k => format!("{k} groups x ({})", labels.join(", ")),
                };
                (sweep.groups.len(), text)
            })
            .collect();
        let it = self.iterations;
        match (parts.as_slice(), after.is_empty()) {
            ([(0 | 1, part)], true) => format!("{it} x ({part})"),
            ([(_, part)], true) => format!("{it} x {part}"),
            _ => {
                let mut items: Vec<String> = parts.into_iter().map(|(_, text)| text).collect();
                items.extend(after.iter().cloned());
                format!("{it} x ({})", items.join(", "))
            }
        }
    }

    /// Labels of one time step's passes (the iteration group written `N x (a, b)`).
    fn step_list(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut group: Vec<&PassPlan> = Vec::new();
        let mut after: Vec<String> = Vec::new();
        for p in self.passes.iter().filter(|p| p.repeat != Repeat::Frame) {
            match p.repeat {
                Repeat::Iteration => group.push(p),
                Repeat::IterationEnd => after.push(p.label()),
                _ => {
                    if !group.is_empty() {
                        out.push(self.iteration_label(&group, &after));
                        group.clear();
                        after.clear();
                    }
                    out.push(p.label());
                }
            }
        }
        out
    }
}

/// The `volume_sum` pass (per frame with metrics; on demand otherwise).
pub fn volume_sum_pass(counts: PlanCounts) -> PassPlan {
    PassPlan {
        kind: PassKind::VolumeSum,
        variant: Variant::Plain,
        constants: Vec::new(),
        elements: counts.tets,
        per_group: false,
        sweep: None,
        bindings: vec![
            (BufferId::Positions, Access::Read),
            (BufferId::Tets, Access::Read),
            (BufferId::RestVolumes, Access::Read),
            (BufferId::Partials, Access::Write),
        ],
        repeat: Repeat::Frame,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const COUNTS: PlanCounts = PlanCounts {
        nodes: 10,
        springs: 30,
        tets: 12,
    };

    fn plan(params: &SimParams, sweeps: &[SweepPlan]) -> EnginePlan {
        EnginePlan::new(COUNTS, params, 64, false, sweeps, None)
    }

    #[test]
    fn implicit_springs_sweep_before_the_volumes_and_share_the_gather_buffers() {
        let params = SimParams {
            springs: SpringKind::Implicit,
            global_volume: Some(false),
            ..SimParams::default()
        };
        let sweeps = [
            SweepPlan {
                kind: ConstraintKind::Spring,
                groups: vec![20, 10],
            },
            SweepPlan {
                kind: ConstraintKind::Volume,
                groups: vec![5, 4, 3],
            },
        ];
        let p = plan(&params, &sweeps);
        assert_eq!(
            p.pass_list(),
            [
                "10 x (2 groups x (spring_constraint#gather, constraint_apply#gather[floor]), \
                 3 groups x (volume#gather, constraint_apply#gather[floor]))",
                "integrate[floor]",
                "check",
            ]
        );
        assert!(!p.runs(PassKind::SpringGather) && !p.runs(PassKind::SpringScatter));
        assert!(!p.has(BufferId::NodeSpringOffsets));
        let (n, s, t) = (10, 30, 12);
        for (id, bytes) in [
            (BufferId::Degrees, 4 * 5 * n),
            (BufferId::GroupMembers, 4 * (s + t)),
            (BufferId::Contributions, 16 * (2 * s + 4 * t)),
            (BufferId::NodeSlotOffsets, 4 * (5 * n + 1)),
            (BufferId::NodeSlotItems, 4 * (2 * s + 4 * t)),
            (BufferId::SpringDamping, 4 * s),
            (BufferId::VolumeCompliance, 4 * t),
            (BufferId::SpringMultipliers, 4 * s),
            (BufferId::VolumeMultipliers, 4 * t),
        ] {
            assert_eq!(p.buffer(id).map(|b| b.bytes), Some(bytes), "{id:?}");
        }
        assert_eq!(p.sweep_offsets(0), SweepOffsets::default());
        assert_eq!(
            p.sweep_offsets(1),
            SweepOffsets {
                group: 2,
                member: 30,
                slot: 60
            }
        );
        // Per iteration: 2 spring groups and 3 volume groups, each with its apply.
        assert_eq!(p.dispatches_per_frame(), 10 * 2 * 5 + 2);
    }

    #[test]
    fn implicit_springs_alone_are_a_jacobi_sweep_without_a_force_pass() {
        let params = SimParams {
            method: Method::Mss,
            springs: SpringKind::Implicit,
            solver: Solver::Jacobi,
            ..SimParams::default()
        };
        let sweeps = [SweepPlan {
            kind: ConstraintKind::Spring,
            groups: vec![30],
        }];
        let p = plan(&params, &sweeps);
        assert_eq!(
            p.pass_list(),
            [
                "10 x (spring_constraint, constraint_apply#sums[floor])",
                "integrate[floor]",
                "check"
            ]
        );
        assert_eq!(p.buffer(BufferId::Degrees).map(|b| b.bytes), Some(40));
        assert!(p.has(BufferId::ConstraintSum) && !p.has(BufferId::VolumeCompliance));
        assert_eq!(
            p.buffer(BufferId::SpringMultipliers).map(|b| b.bytes),
            Some(4 * 30)
        );
        assert!(!p.has(BufferId::VolumeMultipliers));
        assert!(p.render().starts_with("method mss with implicit springs:"));
    }

    #[test]
    fn warm_started_implicit_springs_gather_their_stored_forces_before_the_iterations() {
        let params = SimParams {
            method: Method::Mss,
            springs: SpringKind::Implicit,
            warm_start: true,
            solver: Solver::Jacobi,
            ..SimParams::default()
        };
        let sweeps = [SweepPlan {
            kind: ConstraintKind::Spring,
            groups: vec![30],
        }];
        let p = plan(&params, &sweeps);
        assert!(p.warm_start);
        assert_eq!(
            p.pass_list(),
            [
                "spring_warm_start",
                "10 x (spring_constraint, constraint_apply#sums[floor])",
                "integrate[floor]",
                "check"
            ]
        );
        assert_eq!(
            p.buffer(BufferId::NodeSpringOffsets).map(|b| b.bytes),
            Some(4 * 11)
        );
        assert_eq!(
            p.buffer(BufferId::NodeSpringItems).map(|b| b.bytes),
            Some(4 * 60)
        );
        assert!(!p.runs(PassKind::SpringGather) && !p.runs(PassKind::SpringScatter));
        assert_eq!(p.dispatches_per_frame(), 1 + 10 * 2 + 2);
        assert!(p
            .render()
            .starts_with("method mss with warm-started implicit springs:"));
        // Warm start means nothing to explicit springs.
        let explicit = plan(
            &SimParams {
                springs: SpringKind::Explicit,
                ..params
            },
            &[],
        );
        assert!(!explicit.warm_start && !explicit.runs(PassKind::SpringWarmStart));
    }
}
