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
//! (specialisation constant 1), and no `volume_sum` pass or partials copy in the frame
//! without per-frame metrics. The `check` pass (divergence) and its 16-byte status copy are
//! always there, and so are the rest volumes (the local volume error needs them).

mod buffer;
mod cost;
mod counts;
mod pass;
mod queries;
mod report;
#[cfg(test)]
mod tests;
mod workgroups;

pub use buffer::{Access, BufferId, BufferPlan};
pub use cost::{profile as gpu_profile, GpuProfile, GPU_PROFILES};
pub use counts::{GlobalCounts, PlanCounts, SweepOffsets, SweepPlan, PEAK_BANDWIDTH};
pub use pass::{volume_sum_pass, PassPlan, Repeat, Variant};
pub use workgroups::for_elements as workgroup_for_elements;

use super::pass_kind::PassKind;
use crate::model::ConstraintKind;
use crate::params::{chebyshev_weights, Method, SimParams, Solver, SpringKind};

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
    /// Whether constraint forces are gathered per node (no float atomics: every solver but
    /// Jacobi).
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
        let sweeps: Vec<SweepPlan> = problem.sweeps.iter().map(SweepPlan::of).collect();
        Ok(EnginePlan::new(
            PlanCounts::of(&problem.model)?,
            &problem.params,
            workgroup_size,
            metrics,
            &sweeps,
            problem.global.as_ref().map(GlobalCounts::of),
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
        // Only the paper's Jacobi sums constraint forces with float atomics; Gauss-Seidel and
        // Chebyshev gather them per node in a fixed order (bit-identical reruns).
        let gather = constrained && params.solver != Solver::Jacobi;
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
        // The global passes reduce in shared memory per chunk of an object's surface.
        let global_workgroup = workgroup_size.min(GLOBAL_WORKGROUP);
        let global_constants =
            |g: GlobalCounts| vec![u32::from(params.floor), g.chunks(global_workgroup)];
        let global_elements =
            |g: GlobalCounts| g.objects * g.chunks(global_workgroup) * global_workgroup;
        if let Some(g) = global {
            let (objects, nodes, faces) =
                (u64::from(g.objects), u64::from(g.nodes), u64::from(g.faces));
            buffers.push((GlobalObjects, 32 * objects, 0));
            buffers.push((SurfaceNodes, 4 * nodes, 0));
            buffers.push((SurfaceFaces, 16 * faces, 0));
            buffers.push((NodeFaceOffsets, 4 * (nodes + 1), 0));
            buffers.push((NodeFaceItems, 4 * 3 * faces, 0));
            buffers.push((SurfaceGradients, 16 * nodes, 0));
            let chunks = u64::from(g.chunks(global_workgroup));
            buffers.push((GlobalState, 16 * objects * chunks, 0));
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
            workgroup_size,
            elements,
            per_group: false,
            sweep: None,
            bindings,
            repeat,
        };
        // A global volume pass: one workgroup per chunk of every object, its chunk count and
        // the floor as constants.
        let global_pass = |kind, g: GlobalCounts, bindings: Vec<_>, repeat| PassPlan {
            constants: global_constants(g),
            workgroup_size: global_workgroup,
            ..pass(kind, Variant::Plain, global_elements(g), bindings, repeat)
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
            passes.push(global_pass(
                PassKind::GlobalVolumePrepare,
                g,
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
            let gathered = vec![
                (Contributions, Read),
                (NodeSlotOffsets, Read),
                (NodeSlotItems, Read),
            ];
            let (variant, input) = match gather {
                true if !chebyshev.is_empty() => (
                    Variant::Named("gather_chebyshev"),
                    [gathered, vec![(ChebyshevBefore, ReadWrite)]].concat(),
                ),
                true => (Variant::Named("gather"), gathered),
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
                passes.push(global_pass(
                    PassKind::GlobalVolumeSum,
                    g,
                    vec![
                        (Velocities, Read),
                        (Forces, Read),
                        (GlobalObjects, Read),
                        (SurfaceNodes, Read),
                        (SurfaceGradients, Read),
                        (GlobalState, ReadWrite),
                    ],
                    Repeat::IterationEnd,
                ));
                passes.push(global_pass(
                    PassKind::GlobalVolume,
                    g,
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
                ));
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
            passes.push(volume_sum_pass(counts, workgroup_size));
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
}
