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
//! Gauss-Seidel and Chebyshev, no spring force pass with implicit springs (but the `spring_warm_start`
//! pass when they are warm-started), no node-spring adjacency without `mss-node`, the
//! gather path of explicit springs or warm-started implicit springs, no volume compliances
//! without `volume`, no floor test in `integrate` without a floor
//! (specialisation constant 1), no collider buffers (contacts, collider data, grids, poses)
//! nor collider solve (the `colliders` variants, their count a specialisation constant)
//! without kinematic colliders, and no `volume_sum` pass or partials copy in the frame
//! without per-frame metrics. The `check` pass (divergence) and its 16-byte status copy are
//! always there (32 bytes, with the `contact_measure` pass, when per-frame metrics measure
//! contact: colliders or body contact; grabs alone get the words without the pass), and so
//! are the rest volumes (the local volume error needs them).

mod anderson;
#[cfg(test)]
mod binding_tests;
mod buffer;
mod cost;
mod counts;
mod elastic;
mod minres;
mod pass;
mod pass_of;
mod queries;
mod report;
#[cfg(test)]
mod report_tests;
#[cfg(test)]
mod tests;
mod workgroups;

pub use anderson::anderson_chunks;
use anderson::{mixed_multipliers, ANDERSON_TERMS};
pub use buffer::BufferPlan;
pub use cost::{profile as gpu_profile, GpuProfile, GPU_PROFILES};
pub use counts::{
    grabbed_nodes, BodyCounts, GlobalCounts, PlanCounts, SweepOffsets, PEAK_BANDWIDTH,
};
pub use elastic::{
    coarse_factor_workgroup, elastic_workgroup, ElasticCounts, ELASTIC_PLANES, ELASTIC_STATE_WORDS,
};
pub use minres::{MinresCounts, MINRES_PLANES, MINRES_STATE_BYTES};
pub use pass::{volume_sum_pass, PassPlan, Variant};
pub use workgroups::for_elements as workgroup_for_elements;

use crate::gpu::MemoryNeeds;
use crate::model::ConstraintKind;
use crate::params::{Method, SimParams, SpringKind};
pub use crate::schedule::{Access, BufferId, Repeat, SweepPlan};
use crate::schedule::{PassKind, Schedule};

/// Everything the engine builds and does per frame.
#[derive(Debug, Clone, PartialEq)]
pub struct EnginePlan {
    /// Method.
    pub method: Method,
    /// Explicit spring forces or implicit spring constraints.
    pub springs: SpringKind,
    /// Element counts.
    pub counts: PlanCounts,
    /// The step every backend runs: its stages, sweeps, iterations and substeps.
    pub schedule: Schedule,
    /// The global volume constraints' sizes, when solved.
    pub global: Option<GlobalCounts>,
    /// Body contact's sizes, when the model has it.
    pub body: Option<BodyCounts>,
    /// Invocations per workgroup.
    pub workgroup_size: u32,
    /// Whether the frame measures the volume (`volume_sum` + partials copy).
    pub metrics: bool,
    /// Buffers, in creation order.
    pub buffers: Vec<BufferPlan>,
    /// One pass per stage of the schedule, in its order: the time step's (repeated
    /// `substeps` times), then the frame's.
    pub passes: Vec<PassPlan>,
    /// The finite elements' sizes, when the plan runs them ([`Self::with_elastic`]).
    pub elastic: Option<ElasticCounts>,
}

/// Invocations per workgroup of the global volume passes (at most; a smaller plan-wide size
/// wins): chunks of 256 surface nodes spread one object over many multiprocessors.
pub const GLOBAL_WORKGROUP: u32 = 256;

/// Workgroups a pass's dispatch should have at least for every multiprocessor of a large
/// GPU to get one (an H100 or H200 has 132), when [`EnginePlan::size_workgroups`] sizes them.
pub const MIN_WORKGROUPS: u32 = 128;

/// The smallest workgroup [`EnginePlan::size_workgroups`] picks (two subgroups of 32).
pub const MIN_WORKGROUP_SIZE: u32 = 64;

/// Size a [`crate::gpu::Buffer`] of `bytes` really has.
fn alloc(bytes: u64) -> u64 {
    bytes.max(4)
}

impl EnginePlan {
    /// The plan of a prepared problem (its constraint groups and global volume constraints),
    /// with `workgroup_size` invocations per group and per-frame volume `metrics` or not.
    pub fn of_problem(
        problem: &crate::problem::Problem,
        workgroup_size: u32,
        metrics: bool,
    ) -> crate::Result<Self> {
        problem.params.check_workgroup_blocks()?;
        let sweeps: Vec<SweepPlan> = problem.sweeps.iter().map(SweepPlan::of).collect();
        let compliant = problem
            .material
            .volume_compliance
            .iter()
            .filter(|&&a| a > 0.0);
        let plan = EnginePlan::with_bodies(
            PlanCounts {
                compliant_tets: compliant.count() as u32,
                ..PlanCounts::of(&problem.model)?
            },
            &problem.params,
            workgroup_size,
            metrics,
            &sweeps,
            problem.global.as_ref().map(GlobalCounts::of),
            problem.bodies.as_ref().map(BodyCounts::of),
        );
        Ok(match plan.runs(PassKind::Elastic) {
            true => {
                let data = super::elastic::ElasticData::prepare(problem);
                plan.with_elastic(data.counts)
            }
            false => plan,
        })
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
        Self::with_bodies(
            counts,
            params,
            workgroup_size,
            metrics,
            sweeps,
            global,
            None,
        )
    }

    /// [`Self::new`] with body contact's sizes when the model has it.
    pub fn with_bodies(
        counts: PlanCounts,
        params: &SimParams,
        workgroup_size: u32,
        metrics: bool,
        sweeps: &[SweepPlan],
        global: Option<GlobalCounts>,
        body: Option<BodyCounts>,
    ) -> Self {
        let global = global.filter(|_| params.solves_global_volume());
        let mut schedule = Schedule::new(params, sweeps.to_vec(), global.is_some(), metrics);
        schedule.anderson_volumes &= counts.compliant_tets > 0;
        let schedule = schedule
            .with_body_contact(body.is_some())
            .with_colliders(counts.colliders, counts.grabbed > 0)
            .with_clamps(counts.clamped)
            .with_contact_measure(metrics)
            .with_reactions(metrics);
        let status = match measures_contact(counts, metrics, body.is_some()) {
            true => CONTACT_STATUS_BYTES,
            false => STATUS_BYTES,
        };
        let mut buffers = buffers(
            counts,
            params,
            &schedule,
            global,
            workgroup_size,
            metrics,
            status,
        );
        if counts.clamped > 0 {
            let poses = CLAMP_POSE_BYTES * u64::from(counts.clamps * schedule.substeps);
            for (id, bytes, upload_bytes) in [
                (BufferId::ClampNodes, 32 * u64::from(counts.clamped), 0),
                (BufferId::ClampPoses, poses * u64::from(POSE_SLOTS), poses),
            ] {
                buffers.push(BufferPlan {
                    id,
                    bytes: alloc(bytes),
                    readback_bytes: 0,
                    upload_bytes,
                });
            }
        }
        if let Some(b) = body {
            buffers.extend(body_buffers(counts, b));
        }
        let passes = (schedule.stages.iter())
            .map(|stage| {
                let mut pass =
                    PassPlan::of(stage, &schedule, counts, global, workgroup_size, params);
                if let Some(b) = body {
                    pass.body_contact(b, counts, workgroup_size);
                }
                pass
            })
            .collect();
        EnginePlan {
            method: params.method,
            springs: params.springs,
            counts,
            schedule,
            global,
            body,
            workgroup_size,
            metrics,
            buffers,
            passes,
            elastic: None,
        }
    }
}

/// Body contact's buffers for a model of `counts` with `body`'s sizes (section "Contact
/// between bodies" of docs/GPU.md).
fn body_buffers(counts: PlanCounts, body: BodyCounts) -> Vec<BufferPlan> {
    use BufferId::*;
    let n = u64::from(counts.nodes);
    let (s, t) = (u64::from(body.nodes), u64::from(body.triangles));
    let h = u64::from(body.buckets);
    [
        (BodySurface, 16 * (s + t)),
        (ContactHash, 4 * (2 * h + 1 + u64::from(body.capacity))),
        (Contacts, CONTACT_BYTES * s),
        (ContactSums, 16 * n),
    ]
    .into_iter()
    .map(|(id, bytes)| device_only(id, bytes))
    .collect()
}

/// Buffer `id` of `bytes` on the device alone (no readback, no per-frame upload).
fn device_only(id: BufferId, bytes: u64) -> BufferPlan {
    BufferPlan {
        id,
        bytes: alloc(bytes),
        readback_bytes: 0,
        upload_bytes: 0,
    }
}

/// Bytes of the divergence status (check.comp).
pub const STATUS_BYTES: u64 = 16;

/// Bytes of the status when the frame measures contact ([`EnginePlan::measures_contact`]):
/// the divergence status, then the frame's contact words (contact_measure.comp): the nodes
/// a collider pushed in the last step, the pushing body contacts, the deepest penetration
/// [m] (f32 bits) and a pad word.
pub const CONTACT_STATUS_BYTES: u64 = 32;

/// Whether a frame of a model of `counts` (with body contact when `bodies`) measures
/// contact: with per-frame `metrics`, when it has kinematic colliders, grabs or body contact
/// ([`crate::problem::Problem::measures_contact`]).
pub fn measures_contact(counts: PlanCounts, metrics: bool, bodies: bool) -> bool {
    metrics && (counts.colliders > 0 || counts.grabbed > 0 || bodies)
}

/// Bytes of one surface node's body contact record (`BodyContactRecord`,
/// glsl/physics/bodies.glsl).
pub const CONTACT_BYTES: u64 = 48;

/// The buffers of a plan in creation order: every array a stage of `schedule` touches, the
/// rest volumes (the local volume error needs them) and the status of `status_bytes`
/// (divergence, and contact when measured), with their sizes for a model of `counts`.
fn buffers(
    counts: PlanCounts,
    params: &SimParams,
    schedule: &Schedule,
    global: Option<GlobalCounts>,
    workgroup_size: u32,
    metrics: bool,
    status_bytes: u64,
) -> Vec<BufferPlan> {
    use BufferId::*;
    let (n, s, t) = (
        u64::from(counts.nodes),
        u64::from(counts.springs),
        u64::from(counts.tets),
    );
    let sweeps = &schedule.sweeps;
    let k = u64::from(schedule.group_count());
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
    if params.method == Method::Volume {
        buffers.push((VolumeCompliance, 4 * t, 0));
    }
    if !sweeps.is_empty() {
        buffers.push((Degrees, 4 * k * n, 0));
        match schedule.gather {
            true => {
                buffers.push((GroupMembers, 4 * constraints, 0));
                buffers.push((Contributions, 16 * slots, 0));
                buffers.push((NodeSlotOffsets, 4 * (k * n + 1), 0));
                buffers.push((NodeSlotItems, 4 * slots, 0));
            }
            false => buffers.push((ConstraintSum, 16 * n, 0)),
        }
        if !schedule.chebyshev.is_empty() {
            buffers.push((ChebyshevBefore, 16 * n, 0));
        }
        // Block Gauss-Seidel: the blocked sweeps' rows and nodes one after another, and a
        // uvec4 per member of every sweep (read from the sweep's `member_first`).
        let shapes = sweeps.iter().filter_map(|w| w.blocks);
        let (rows, block_nodes) = shapes.fold((0, 0), |(r, k), b| {
            (r + u64::from(b.blocks), k + u64::from(b.nodes))
        });
        if rows > 0 {
            buffers.push((BlockRows, 16 * rows, 0));
            buffers.push((BlockNodes, 4 * block_nodes, 0));
            buffers.push((BlockCorners, 16 * constraints, 0));
        }
        // The compliant constraints' multipliers so far in the step, one float per
        // constraint of a sweep that tracks them. Volume sweeps always get theirs: the
        // plan sees counts and parameters, not the per-tet compliances (a material's
        // young's modulus or an object's own material may make any tet compliant), and
        // 4 bytes per tet are what the compliances already take; hard tets never touch
        // their entry.
        // Anderson's passes bind both multiplier arrays, also where no sweep uses one.
        for kind in [ConstraintKind::Spring, ConstraintKind::Volume] {
            if schedule.anderson > 0 || sweeps.iter().any(|w| w.kind == kind) {
                buffers.push(match kind {
                    ConstraintKind::Spring => (SpringMultipliers, 4 * s, 0),
                    _ => (VolumeMultipliers, 4 * t, 0),
                });
            }
        }
    }
    if let Some(g) = global {
        let (objects, nodes, faces) =
            (u64::from(g.objects), u64::from(g.nodes), u64::from(g.faces));
        buffers.push((GlobalObjects, 32 * objects, 0));
        buffers.push((SurfaceNodes, 4 * nodes, 0));
        buffers.push((SurfaceFaces, 16 * faces, 0));
        buffers.push((NodeFaceOffsets, 4 * (nodes + 1), 0));
        buffers.push((NodeFaceItems, 4 * 3 * faces, 0));
        buffers.push((SurfaceGradients, 16 * nodes, 0));
        let chunks = u64::from(g.chunks(workgroup_size.min(GLOBAL_WORKGROUP)));
        buffers.push((GlobalState, 16 * objects * chunks, 0));
    }
    if schedule.split {
        buffers.push((SplitVelocities, 16 * n, 0));
    }
    let minres = workgroup_size.min(GLOBAL_WORKGROUP);
    if let Some(m) = MinresCounts::of(schedule, counts, global, minres) {
        let sized = m.buffers(counts.nodes, schedule.minres);
        buffers.extend(sized.into_iter().map(|(id, bytes)| (id, bytes, 0)));
    }
    if schedule.anderson > 0 {
        let planes = 3 + 2 * u64::from(schedule.anderson);
        buffers.push((AndersonHistory, 16 * planes * n, 0));
        let chunks = u64::from(anderson_chunks(counts.nodes, workgroup_size));
        buffers.push((AndersonSums, 4 * ANDERSON_TERMS * chunks, 0));
        let (springs, tets) = mixed_multipliers(schedule, counts);
        let mixed = u64::from(springs + tets).max(1);
        let columns = 1 + u64::from(schedule.anderson);
        buffers.push((AndersonMultipliers, 4 * columns * mixed, 0));
    }
    if schedule
        .stages
        .iter()
        .any(|stage| stage.touches(NodeSpringItems))
    {
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
    buffers.push((Status, status_bytes, status_bytes));
    // Forces out: each node's holding inputs, its clamp, and the workgroups' sums, copied
    // to the host every frame.
    // Without them `integrate` binds a placeholder of the inputs (it never writes them).
    if schedule.runs(PassKind::Reactions) {
        let sums = reaction_partials(counts, schedule.colliders, workgroup_size);
        buffers.push((ReactionInputs, 32 * n, 0));
        buffers.push((NodeClamps, 4 * n, 0));
        buffers.push((ReactionPartials, 16 * sums, alloc(16 * sums)));
    } else {
        buffers.push((ReactionInputs, 0, 0));
    }
    let mut buffers: Vec<BufferPlan> = buffers
        .into_iter()
        .map(|(id, bytes, readback_bytes)| BufferPlan {
            id,
            bytes: alloc(bytes),
            readback_bytes,
            upload_bytes: 0,
        })
        .collect();
    if counts.colliders > 0 || counts.grabbed > 0 {
        let (c, values) = (u64::from(counts.colliders), u64::from(counts.grid_values));
        let poses = POSE_BYTES * c * u64::from(schedule.substeps);
        let grabbed = u64::from(counts.grabbed);
        let targets = 16 * grabbed * u64::from(schedule.substeps);
        let grab_nodes = if grabbed > 0 { 4 * n } else { 0 };
        for (id, bytes, upload_bytes) in [
            (ColliderContacts, 16 * n, 0),
            (Colliders, 64 * c, 0),
            (ColliderGrids, 4 * values, 0),
            (ColliderPoses, poses * u64::from(POSE_SLOTS), poses),
            (GrabNodes, grab_nodes, 0),
            (GrabTargets, targets * u64::from(POSE_SLOTS), targets),
        ] {
            buffers.push(BufferPlan {
                id,
                bytes: alloc(bytes),
                readback_bytes: 0,
                upload_bytes,
            });
        }
    }
    buffers
}

/// The vec4 sums `reactions` leaves for the host on a model of `counts` with `colliders`
/// colliders: the pins' (with the floor's), each collider's and each clamp's, per workgroup
/// of the plan's `workgroup_size` (at most [`GLOBAL_WORKGROUP`]).
pub fn reaction_partials(counts: PlanCounts, colliders: u32, workgroup_size: u32) -> u64 {
    let groups = counts
        .nodes
        .div_ceil(workgroup_size.clamp(1, GLOBAL_WORKGROUP));
    u64::from(groups) * u64::from(1 + colliders + counts.clamps)
}

/// Bytes of one collider's pose over one step ([`crate::gpu::layout::GpuColliderPose`]).
pub const POSE_BYTES: u64 = 64;

/// Bytes of one clamp's pose at one step's end ([`crate::gpu::layout::GpuClampPose`]).
pub const CLAMP_POSE_BYTES: u64 = 32;

/// Frame slots the collider poses buffer has rows for (host-visible, each slot's written
/// before its submit): as many as frames may be in flight.
pub const POSE_SLOTS: u32 = super::MAX_FRAMES_IN_FLIGHT;
