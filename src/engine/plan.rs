//! What the `vulkan` backend builds for a model and its parameters, decided in one place:
//! the buffers (with sizes), the passes (with their bindings, repetition and
//! specialisation) and the host copies of a frame. [`super::VulkanBackend`] creates exactly
//! these buffers and pipelines and records exactly these passes, and checks every created
//! buffer's size against the plan, so `tetrasim plan` (which prints this without a GPU)
//! cannot drift from the engine.
//!
//! What a scene does not use is not built: no rest volumes without `volume`, no constraint
//! sums or degrees without `distance`/`volume`, no node-spring adjacency without `mss-node`,
//! no floor test in `integrate` without a floor (specialisation constant 1), and no
//! `volume_sum` pass or partials copy in the frame without per-frame metrics. The `check`
//! pass (divergence) and its 16-byte status copy are always there.

use std::fmt::Write as _;

use crate::gpu::layout::binding;
use crate::params::{Method, SimParams};

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
    /// float per tet (`volume`).
    RestVolumes,
    /// vec4 per node (`distance`, `volume`).
    ConstraintSum,
    /// float per node (`distance`, `volume`).
    Degrees,
    /// N + 1 u32 (`mss-node`).
    NodeSpringOffsets,
    /// 2 S u32 (`mss-node`).
    NodeSpringItems,
    /// 8 bytes per volume_sum workgroup.
    Partials,
    /// 16 bytes: divergence flags, first bad node, speed limit.
    Status,
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
    /// `iterations` times per time step (consecutive such passes repeat as a group).
    Iteration,
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

/// One planned compute pass.
#[derive(Debug, Clone, PartialEq)]
pub struct PassPlan {
    /// Name in the timing report (the shader's file stem).
    pub name: &'static str,
    /// Whether the shader has `ext`/`cas` float-atomic variants.
    pub atomics_variant: bool,
    /// Specialisation constants from id 1 on (id 0 is the workgroup size).
    pub constants: Vec<u32>,
    /// Invocations (one per node, spring or tet).
    pub elements: u32,
    /// Bound buffers and how the pass uses them.
    pub bindings: Vec<(BufferId, Access)>,
    /// How often it runs.
    pub repeat: Repeat,
}

impl PassPlan {
    /// Name with its specialisation, e.g. `integrate[floor]`.
    pub fn label(&self) -> String {
        match (self.name, self.constants.first()) {
            ("integrate" | "constraint_apply", Some(1)) => format!("{}[floor]", self.name),
            ("integrate" | "constraint_apply", Some(_)) => format!("{}[no floor]", self.name),
            _ => self.name.to_string(),
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
    /// The plan for a model of `counts` under `params`, with `workgroup_size` invocations per
    /// group and per-frame volume `metrics` or not.
    pub fn new(counts: PlanCounts, params: &SimParams, workgroup_size: u32, metrics: bool) -> Self {
        use Access::{Read, ReadWrite, Write};
        use BufferId::*;
        let (n, s, t) = (
            u64::from(counts.nodes),
            u64::from(counts.springs),
            u64::from(counts.tets),
        );
        let method = params.method;
        let constrained = matches!(method, Method::Distance | Method::Volume);
        let groups = u64::from(counts.tets.div_ceil(workgroup_size.max(1)));
        let mut buffers = vec![
            (Positions, 16 * n, 0),
            (Velocities, 16 * n, 0),
            (Forces, 16 * n, 0),
            (Springs, 16 * s, 0),
            (Tets, 16 * t, 0),
        ];
        if method == Method::Volume {
            buffers.push((RestVolumes, 4 * t, 0));
        }
        if constrained {
            buffers.push((ConstraintSum, 16 * n, 0));
            buffers.push((Degrees, 4 * n, 0));
        }
        if method == Method::MssNode {
            buffers.push((NodeSpringOffsets, 4 * (n + 1), 0));
            buffers.push((NodeSpringItems, 4 * 2 * s, 0));
        }
        // The partials stay for on-demand measurements; they are copied per frame only
        // with metrics.
        let partial_bytes = 8 * groups;
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

        let pass = |name, atomics_variant, elements, bindings: Vec<_>, repeat| PassPlan {
            name,
            atomics_variant,
            constants: Vec::new(),
            elements,
            bindings,
            repeat,
        };
        let mut passes = vec![match method {
            Method::MssNode => pass(
                "spring_gather",
                false,
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
            _ => pass(
                "spring_scatter",
                true,
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
        if constrained {
            passes.push(match method {
                Method::Volume => pass(
                    "volume",
                    true,
                    counts.tets,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Forces, Read),
                        (Tets, Read),
                        (RestVolumes, Read),
                        (Degrees, Read),
                        (ConstraintSum, ReadWrite),
                    ],
                    Repeat::Iteration,
                ),
                _ => pass(
                    "distance",
                    true,
                    counts.springs,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Forces, Read),
                        (Springs, Read),
                        (Degrees, Read),
                        (ConstraintSum, ReadWrite),
                    ],
                    Repeat::Iteration,
                ),
            });
            let mut apply = pass(
                "constraint_apply",
                false,
                counts.nodes,
                vec![
                    (Positions, Read),
                    (Velocities, Read),
                    (Forces, ReadWrite),
                    (ConstraintSum, ReadWrite),
                    (Degrees, Read),
                ],
                Repeat::Iteration,
            );
            apply.constants = vec![u32::from(params.floor)];
            passes.push(apply);
        }
        let mut integrate = pass(
            "integrate",
            false,
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
            "check",
            false,
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
        self.passes.iter().any(|p| p.name == name)
    }

    /// How many times `pass` runs in a frame.
    pub fn runs_per_frame(&self, pass: &PassPlan) -> u32 {
        match pass.repeat {
            Repeat::Substep => self.substeps,
            Repeat::Iteration => self.substeps * self.iterations,
            Repeat::Frame => 1,
        }
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
    /// and once per write (gathers through indices make the real traffic larger).
    pub fn pass_bytes(&self, pass: &PassPlan) -> u64 {
        pass.bindings
            .iter()
            .map(|(id, access)| {
                let size = self.buffer(*id).map_or(0, |b| b.bytes);
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
        out
    }

    /// Labels of one time step's passes (the iteration group written `N x (a, b)`).
    fn step_list(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut group: Vec<String> = Vec::new();
        for p in self.passes.iter().filter(|p| p.repeat != Repeat::Frame) {
            if p.repeat == Repeat::Iteration {
                group.push(p.label());
                continue;
            }
            if !group.is_empty() {
                out.push(format!("{} x ({})", self.iterations, group.join(", ")));
                group.clear();
            }
            out.push(p.label());
        }
        out
    }
}

/// The `volume_sum` pass (per frame with metrics; on demand otherwise).
pub fn volume_sum_pass(counts: PlanCounts) -> PassPlan {
    PassPlan {
        name: "volume_sum",
        atomics_variant: false,
        constants: Vec::new(),
        elements: counts.tets,
        bindings: vec![
            (BufferId::Positions, Access::Read),
            (BufferId::Tets, Access::Read),
            (BufferId::Partials, Access::Write),
        ],
        repeat: Repeat::Frame,
    }
}
