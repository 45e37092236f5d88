//! The step written down once: which stages a step has, in which order, and what each
//! touches. A new pass is a [`PassKind`] entry (pass_kind.rs) and its stage in
//! [`Schedule::new`], its shader, and its arm in each CPU backend.

use super::{Access, BufferId, Domain, PassKind, Repeat, Schedule, Stage, SweepPlan};
use crate::model::ConstraintKind;
use crate::params::{chebyshev_weights, ContactMode, Method, SimParams, Solver, SpringKind};

/// A stage of no sweep.
pub(super) fn stage(
    kind: PassKind,
    repeat: Repeat,
    domain: Domain,
    bindings: Vec<(BufferId, Access)>,
) -> Stage {
    Stage {
        kind,
        repeat,
        domain,
        sweep: None,
        bindings,
    }
}

impl Schedule {
    /// The schedule under `params` for the constraint `sweeps` of an iteration
    /// ([`crate::model::Model::constraint_sweeps`] under `params`), with the global volume
    /// stages when `global` (the model has global volume constraints and `params` solve
    /// them) and the per-frame volume stage when `metrics`.
    pub fn new(params: &SimParams, sweeps: Vec<SweepPlan>, global: bool, metrics: bool) -> Self {
        use Access::{Read, ReadWrite, Write};
        use BufferId::*;
        let method = params.method;
        let constrained = !sweeps.is_empty();
        // Only Jacobi sums forces with float atomics; the others gather per node, in order.
        let gather = constrained && params.solver != Solver::Jacobi;
        let chebyshev = match constrained && params.solver == Solver::Chebyshev {
            true => chebyshev_weights(params.rho, params.iterations),
            false => Vec::new(),
        };
        let global = global && params.solves_global_volume();
        let mut stages = Vec::new();
        // Explicit spring forces are gathered per node for mss-node, and on the gather path
        // so that nothing in its step uses float atomics; implicit springs have no force
        // stage (F starts as m g, which `integrate` and the initial state leave).
        if params.springs == SpringKind::Explicit && params.has_springs() {
            let gather_springs = method == Method::MssNode || gather;
            let mut bindings = vec![
                (Positions, Read),
                (Velocities, Read),
                (Springs, Read),
                (SpringDamping, Read),
            ];
            let (kind, domain) = match gather_springs {
                true => {
                    bindings.extend([(NodeSpringOffsets, Read), (NodeSpringItems, Read)]);
                    (PassKind::SpringGather, Domain::Nodes)
                }
                false => (PassKind::SpringScatter, Domain::Springs),
            };
            bindings.push((Forces, ReadWrite));
            stages.push(stage(kind, Repeat::Substep, domain, bindings));
        }
        // Warm-started implicit springs apply their stored multipliers as forces, gathered
        // per node (no atomics), before the first iteration.
        let warm_start = params.springs == SpringKind::Implicit
            && params.warm_start
            && sweeps.iter().any(|w| w.kind == ConstraintKind::Spring);
        if warm_start {
            stages.push(stage(
                PassKind::SpringWarmStart,
                Repeat::Substep,
                Domain::Nodes,
                vec![
                    (Positions, Read),
                    (Springs, Read),
                    (SpringMultipliers, Read),
                    (NodeSpringOffsets, Read),
                    (NodeSpringItems, Read),
                    (Forces, ReadWrite),
                ],
            ));
        }
        if global {
            stages.push(stage(
                PassKind::GlobalVolumePrepare,
                Repeat::Substep,
                Domain::Surface,
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
            ));
        }
        if constrained {
            let output = match gather {
                true => vec![(GroupMembers, Read), (Contributions, Write)],
                false => vec![(ConstraintSum, ReadWrite)],
            };
            for (index, sweep) in sweeps.iter().enumerate() {
                if sweep.kind == ConstraintKind::Elastic {
                    stages.extend(super::elastic::stages(index));
                    continue;
                }
                let (domain, element_data) = sweep.kind.data();
                let mut bindings = vec![(Positions, Read), (Velocities, Read), (Forces, Read)];
                bindings.extend(element_data);
                bindings.push((Degrees, Read));
                bindings.extend(output.iter().copied());
                if sweep.blocks.is_some() {
                    bindings.extend([(BlockRows, Read), (BlockNodes, Read), (BlockCorners, Read)]);
                }
                stages.push(Stage {
                    sweep: Some(index),
                    ..stage(
                        sweep.pass(),
                        Repeat::Iteration,
                        if gather { Domain::Group } else { domain },
                        bindings,
                    )
                })
            }
            let mut bindings = vec![
                (Positions, Read),
                (Velocities, Read),
                (Forces, ReadWrite),
                (Degrees, Read),
            ];
            bindings.extend(match gather {
                true => vec![
                    (Contributions, Read),
                    (NodeSlotOffsets, Read),
                    (NodeSlotItems, Read),
                ],
                false => vec![(ConstraintSum, ReadWrite)],
            });
            if !chebyshev.is_empty() {
                bindings.push((ChebyshevBefore, ReadWrite));
            }
            stages.push(stage(
                PassKind::ConstraintApply,
                Repeat::Iteration,
                Domain::Nodes,
                bindings,
            ));
            if global {
                stages.push(stage(
                    PassKind::GlobalVolumeSum,
                    Repeat::IterationEnd,
                    Domain::Surface,
                    vec![
                        (Velocities, Read),
                        (Forces, Read),
                        (GlobalObjects, Read),
                        (SurfaceNodes, Read),
                        (SurfaceGradients, Read),
                        (GlobalState, ReadWrite),
                    ],
                ));
                stages.push(stage(
                    PassKind::GlobalVolume,
                    Repeat::IterationEnd,
                    Domain::Surface,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Forces, ReadWrite),
                        (GlobalObjects, Read),
                        (SurfaceNodes, Read),
                        (SurfaceGradients, Read),
                        (GlobalState, Read),
                    ],
                ));
            }
            if params.anderson > 0 {
                stages.push(stage(
                    PassKind::AndersonSum,
                    Repeat::IterationEnd,
                    Domain::Nodes,
                    vec![
                        (Forces, Read),
                        (SpringMultipliers, Read),
                        (VolumeMultipliers, Read),
                        (AndersonHistory, ReadWrite),
                        (AndersonSums, Write),
                        (AndersonMultipliers, ReadWrite),
                    ],
                ));
                stages.push(stage(
                    PassKind::AndersonMix,
                    Repeat::IterationEnd,
                    Domain::Nodes,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Forces, ReadWrite),
                        (SpringMultipliers, ReadWrite),
                        (VolumeMultipliers, ReadWrite),
                        (AndersonHistory, ReadWrite),
                        (AndersonSums, Read),
                        (AndersonMultipliers, Read),
                    ],
                ));
            }
        }
        let minres = match constrained {
            true => params.minres,
            false => 0,
        };
        stages.extend(super::minres::stages(minres, &sweeps, global));
        let volumes = sweeps.iter().position(|w| w.kind == ConstraintKind::Volume);
        let inversion_sweeps = match volumes {
            Some(volumes) if params.inversion_sweeps > 0 => {
                let mut bindings = vec![
                    (Positions, Read),
                    (Velocities, Read),
                    (Forces, Read),
                    (Tets, Read),
                    (RestVolumes, Read),
                    (Degrees, Read),
                ];
                bindings.extend(match gather {
                    true => vec![(GroupMembers, Read), (Contributions, Write)],
                    false => vec![(ConstraintSum, ReadWrite)],
                });
                if sweeps[volumes].blocks.is_some() {
                    bindings.extend([(BlockRows, Read), (BlockNodes, Read), (BlockCorners, Read)]);
                }
                stages.push(Stage {
                    sweep: Some(volumes),
                    ..stage(
                        PassKind::InversionFloor,
                        Repeat::Restore,
                        if gather { Domain::Group } else { Domain::Tets },
                        bindings,
                    )
                });
                params.inversion_sweeps
            }
            _ => 0,
        };
        let split = params.contact == ContactMode::Split;
        if split {
            stages.push(stage(
                PassKind::SplitVelocity,
                Repeat::Substep,
                Domain::Nodes,
                vec![
                    (Positions, Read),
                    (Velocities, Read),
                    (Forces, ReadWrite),
                    (SplitVelocities, Write),
                ],
            ));
        }
        // `integrate` leaves the forces out's inputs (only with the `reactions` stage, its
        // specialisation constant says; the buffer is a placeholder without).
        let mut bindings = vec![
            (Positions, ReadWrite),
            (Velocities, ReadWrite),
            (Forces, ReadWrite),
            (ReactionInputs, Write),
        ];
        if split {
            bindings.push((SplitVelocities, Read));
        }
        stages.push(stage(
            PassKind::Integrate,
            Repeat::Substep,
            Domain::Nodes,
            bindings,
        ));
        stages.push(stage(
            PassKind::Check,
            Repeat::Frame,
            Domain::Nodes,
            vec![(Positions, Read), (Velocities, Read), (Status, ReadWrite)],
        ));
        if metrics {
            stages.push(super::volume_sum());
        }
        Schedule {
            stages,
            sweeps,
            substeps: params.substeps,
            iterations: params.iterations,
            gather,
            warm_start,
            chebyshev,
            anderson: if constrained { params.anderson } else { 0 },
            anderson_volumes: constrained && params.anderson > 0,
            minres,
            inversion_sweeps,
            inversion_floor: params.inversion_floor,
            block_sweeps: params.block_sweeps,
            spring_block_sweeps: params.spring_sweeps(),
            floor: params.floor,
            colliders: 0,
            grabs: false,
            split,
        }
    }
}
