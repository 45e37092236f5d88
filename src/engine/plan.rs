//! What the `vulkan` backend builds for a model and its parameters, decided in one place:
//! the buffers (with sizes), the passes (with their bindings, repetition and
//! specialisation) and the host copies of a frame. [`super::VulkanBackend`] creates exactly
//! these buffers and pipelines and records exactly these passes, and checks every created
//! buffer's size against the plan, so `tetrasim plan` (which prints this without a GPU)
//! cannot drift from the engine.
//!
//! What a scene does not use is not built: no degrees without `distance`/`volume`, atomic
//! constraint sums only for Jacobi and the gather path's buffers (group members,
//! contributions, node-slot CSR) only for Gauss-Seidel, no node-spring adjacency without
//! `mss-node` or the gather path, no floor test in `integrate` without a floor
//! (specialisation constant 1), and no `volume_sum` pass or partials copy in the frame
//! without per-frame metrics. The `check` pass (divergence) and its 16-byte status copy are
//! always there, and so are the rest volumes (the local volume error needs them).

use std::fmt::Write as _;

use super::pass_kind::PassKind;
use crate::gpu::layout::binding;
use crate::params::{chebyshev_weights, Method, SimParams, Solver};

/// A GPU buffer of the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BufferId {
    /// vec4 per node: position, inverse mass.
    Positions,
    /// vec4 per node: velocity, mass.
    Velocities,
    /// vec4 per node: the step's force.
    Forces,
    /// 16 bytes per spring.
    Springs,
    /// uvec4 per tet.
    Tets,
    /// float per tet: rest volume (volume constraints, local volume error).
    RestVolumes,
    /// vec4 per node (`distance`, `volume` with Jacobi: the atomic sums).
    ConstraintSum,
    /// float per group and node (`distance`, `volume`).
    Degrees,
    /// N + 1 u32 (`mss-node`, gather path).
    NodeSpringOffsets,
    /// 2 S u32 (`mss-node`, gather path).
    NodeSpringItems,
    /// 16 bytes per volume_sum workgroup.
    Partials,
    /// 16 bytes: divergence flags, first bad node, speed limit.
    Status,
    /// u32 per constraint, in group order (gather path).
    GroupMembers,
    /// vec4 per constraint corner, in group order (gather path).
    Contributions,
    /// `groups * N + 1` u32 (gather path).
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
            BufferId::Tets => "tets",
            BufferId::RestVolumes => "rest volumes",
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
            BufferId::Tets => binding::TETS,
            BufferId::RestVolumes => binding::REST_VOLUMES,
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
    /// `iterations` times per time step and, within an iteration, once per constraint group
    /// (consecutive such passes repeat together).
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

/// Everything the engine builds and does per frame.
#[derive(Debug, Clone, PartialEq)]
pub struct EnginePlan {
    /// Method.
    pub method: Method,
    /// Element counts.
    pub counts: PlanCounts,
    /// Time steps per frame.
    pub substeps: u32,
    /// Constraint iterations per time step.
    pub iterations: u32,
    /// Constraints per group, solved one group after another in each iteration (one group
    /// for Jacobi; empty for the springs-only methods).
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
        let groups = model.constraint_groups(params.method, params.solver, params.groups);
        let global = params
            .solves_global_volume()
            .then(|| GlobalCounts::of(&crate::model::GlobalVolume::new(model)));
        Ok(EnginePlan::new(
            PlanCounts::of(model)?,
            params,
            workgroup_size,
            metrics,
            &groups.map(|g| g.sizes()).unwrap_or_default(),
            global,
        ))
    }

    /// The plan for a model of `counts` under `params`, with `workgroup_size` invocations per
    /// group, per-frame volume `metrics` or not, the constraints split into groups of
    /// `groups` constraints each ([`crate::model::Model::constraint_groups`]; ignored by
    /// the springs-only methods) and the `global` volume constraints' sizes when
    /// `params.global_volume` asks for them.
    pub fn new(
        counts: PlanCounts,
        params: &SimParams,
        workgroup_size: u32,
        metrics: bool,
        groups: &[u32],
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
        let constrained = matches!(method, Method::Distance | Method::Volume);
        let gather = constrained && params.solver == Solver::GaussSeidel;
        let chebyshev: Vec<f32> = match constrained && params.solver == Solver::Chebyshev {
            true => chebyshev_weights(params.rho, params.iterations)
                .into_iter()
                .map(|w| w as f32)
                .collect(),
            false => Vec::new(),
        };
        let groups = if constrained {
            groups.to_vec()
        } else {
            Vec::new()
        };
        let k = groups.len().max(1) as u64;
        // Constraints and the slots (corners) of each.
        let (constraints, corners) = match method {
            Method::Volume => (t, 4),
            _ => (s, 2),
        };
        let workgroups = u64::from(counts.tets.div_ceil(workgroup_size.max(1)));
        let mut buffers = vec![
            (Positions, 16 * n, 0),
            (Velocities, 16 * n, 0),
            (Forces, 16 * n, 0),
            (Springs, 16 * s, 0),
            (Tets, 16 * t, 0),
        ];
        // Rest volumes: the volume constraints' and the local volume error's.
        buffers.push((RestVolumes, 4 * t, 0));
        if constrained {
            buffers.push((Degrees, 4 * k * n, 0));
            match gather {
                true => {
                    buffers.push((GroupMembers, 4 * constraints, 0));
                    buffers.push((Contributions, 16 * corners * constraints, 0));
                    buffers.push((NodeSlotOffsets, 4 * (k * n + 1), 0));
                    buffers.push((NodeSlotItems, 4 * corners * constraints, 0));
                }
                false => buffers.push((ConstraintSum, 16 * n, 0)),
            }
            if !chebyshev.is_empty() {
                buffers.push((ChebyshevBefore, 16 * n, 0));
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
        // Spring forces are gathered per node for mss-node, and on the gather path so
        // that nothing in its step uses float atomics.
        let spring_gather = method == Method::MssNode || gather;
        if spring_gather {
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
            bindings,
            repeat,
        };
        let mut passes = vec![match spring_gather {
            true => pass(
                PassKind::SpringGather,
                Variant::Plain,
                counts.nodes,
                vec![
                    (Positions, Read),
                    (Velocities, Read),
                    (Springs, Read),
                    (NodeSpringOffsets, Read),
                    (NodeSpringItems, Read),
                    (Forces, Write),
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
                    (Forces, ReadWrite),
                ],
                Repeat::Substep,
            ),
        }];
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
            let mut solve = match method {
                Method::Volume => pass(
                    PassKind::Volume,
                    variant,
                    counts.tets,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Forces, Read),
                        (Tets, Read),
                        (RestVolumes, Read),
                        (Degrees, Read),
                    ],
                    Repeat::Iteration,
                ),
                _ => pass(
                    PassKind::Distance,
                    variant,
                    counts.springs,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Forces, Read),
                        (Springs, Read),
                        (Degrees, Read),
                    ],
                    Repeat::Iteration,
                ),
            };
            solve.bindings.extend(output);
            solve.per_group = gather;
            passes.push(solve);
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
            counts,
            substeps: params.substeps,
            iterations: params.iterations,
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
            Repeat::Iteration => self.substeps * self.iterations * self.group_count(),
            Repeat::IterationEnd => self.substeps * self.iterations,
            Repeat::Frame => 1,
        }
    }

    /// Constraint groups solved one after another per iteration (at least 1).
    pub fn group_count(&self) -> u32 {
        self.groups.len().max(1) as u32
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
    /// once per constraint group streams only its group's share of the per-constraint
    /// buffers (and of the per-group degrees and slot offsets).
    pub fn pass_bytes(&self, pass: &PassPlan) -> u64 {
        let groups = u64::from(self.group_count());
        pass.bindings
            .iter()
            .map(|(id, access)| {
                let size = self.buffer(*id).map_or(0, |b| b.bytes);
                let size = match (pass.repeat, id) {
                    (
                        Repeat::Iteration,
                        BufferId::Tets
                        | BufferId::RestVolumes
                        | BufferId::Springs
                        | BufferId::Degrees
                        | BufferId::GroupMembers
                        | BufferId::Contributions
                        | BufferId::NodeSlotOffsets
                        | BufferId::NodeSlotItems,
                    ) => size / groups,
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
        let _ = writeln!(
            out,
            "method {}: {} nodes, {} springs, {} tets; {} substeps x {} iterations, workgroup {}",
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

    /// `10 x (a, b)`, `10 x 8 groups x (a, b)` with several constraint groups, and
    /// `10 x (8 groups x (a, b), c)` with passes after the groups.
    fn iteration_label(&self, passes: &[String], after: &[String]) -> String {
        let grouped = match self.groups.len() {
            0 | 1 => passes.join(", "),
            k => format!("{k} groups x ({})", passes.join(", ")),
        };
        match (after.is_empty(), self.groups.len()) {
            (true, 0 | 1) => format!("{} x ({grouped})", self.iterations),
            (true, _) => format!("{} x {grouped}", self.iterations),
            (false, _) => format!("{} x ({grouped}, {})", self.iterations, after.join(", ")),
        }
    }

    /// Labels of one time step's passes (the iteration group written `N x (a, b)`).
    fn step_list(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut group: Vec<String> = Vec::new();
        let mut after: Vec<String> = Vec::new();
        for p in self.passes.iter().filter(|p| p.repeat != Repeat::Frame) {
            match p.repeat {
                Repeat::Iteration => group.push(p.label()),
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
        bindings: vec![
            (BufferId::Positions, Access::Read),
            (BufferId::Tets, Access::Read),
            (BufferId::RestVolumes, Access::Read),
            (BufferId::Partials, Access::Write),
        ],
        repeat: Repeat::Frame,
    }
}
