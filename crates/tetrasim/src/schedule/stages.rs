//! Which stages a step has, in which order, and what each touches: the one place the step
//! is written down.

use super::{Access, BufferId, Domain, PassKind, Repeat, Schedule, Stage, SweepPlan};
use crate::model::ConstraintKind;
use crate::params::{chebyshev_weights, Method, SimParams, Solver, SpringKind};

/// A stage of no sweep.
fn stage(
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
        // Only the paper's Jacobi sums constraint forces with float atomics; Gauss-Seidel and
        // Chebyshev gather them per node in a fixed order (bit-identical reruns).
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
        if params.springs == SpringKind::Explicit {
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
                let (domain, element_data) = sweep.kind.data();
                let mut bindings = vec![(Positions, Read), (Velocities, Read), (Forces, Read)];
                bindings.extend(element_data);
                bindings.push((Degrees, Read));
                bindings.extend(output.iter().copied());
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
        }
        stages.push(stage(
            PassKind::Integrate,
            Repeat::Substep,
            Domain::Nodes,
            vec![
                (Positions, ReadWrite),
                (Velocities, ReadWrite),
                (Forces, ReadWrite),
            ],
        ));
        stages.push(stage(
            PassKind::Check,
            Repeat::Frame,
            Domain::Nodes,
            vec![(Positions, Read), (Velocities, Read), (Status, ReadWrite)],
        ));
        if metrics {
            stages.push(volume_sum());
        }
        Schedule {
            stages,
            sweeps,
            substeps: params.substeps,
            iterations: params.iterations,
            gather,
            warm_start,
            chebyshev,
            floor: params.floor,
        }
    }
}

/// The `volume_sum` stage (per frame with metrics; on demand otherwise).
pub fn volume_sum() -> Stage {
    use Access::{Read, Write};
    use BufferId::*;
    stage(
        PassKind::VolumeSum,
        Repeat::Frame,
        Domain::Tets,
        vec![
            (Positions, Read),
            (Tets, Read),
            (RestVolumes, Read),
            (Partials, Write),
        ],
    )
}
