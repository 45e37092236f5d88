//! The time step, declared once. A [`Schedule`] is the list of a frame's stages (passes) in
//! execution order, each with how often it runs ([`Repeat`]), which elements it covers
//! ([`Domain`]), the constraint sweep it solves and the arrays it reads and writes
//! ([`BufferId`], [`Access`]); [`Schedule::step`] unrolls one time step into its
//! dispatches (iterations x sweeps x groups). Every backend follows it:
//!
//! - the Vulkan engine records one dispatch per [`Dispatch`], a barrier on the arrays the
//!   stage writes after each ([`Stage::writes`]), and builds one pipeline per [`Stage`];
//! - `cpu-ref` runs each dispatch as a plain loop (backend/cpu/reference.rs, one `match`
//!   arm per [`PassKind`]);
//! - `cpu` runs the same dispatches, the constraint iterations on its thread team with a
//!   barrier wait after each dispatch.
//!
//! What a scene does not need is not scheduled: no constraint stages without constraint
//! iterations, no spring force stage with implicit springs (but `spring_warm_start` when they
//! are warm-started), no global volume stages unless the parameters solve them, no
//! `volume_sum` without per-frame metrics, no `contact_measure` without them or without
//! colliders or body contact. Which variant of a stage a backend runs
//! (per-node gather or atomics) follows from [`Schedule::gather`].
//!
//! A new pass is a [`PassKind`] (pass_kind.rs) and its stage in [`Schedule::new`]
//! (stages.rs), its shader, and its arm in each CPU backend's executor.

mod buffer;
mod elastic;
pub mod family;
mod minres;
mod pass_kind;
mod scene;
mod stages;
#[cfg(test)]
mod tests;
mod walk;

pub use buffer::{Access, BufferId};
pub use minres::MinresRowKinds;
pub use pass_kind::PassKind;
pub use scene::volume_sum;
pub use walk::{Dispatch, GroupAt};

use crate::model::{ConstraintKind, Sweep};
use crate::problem::Problem;

/// How often a stage runs in a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Repeat {
    /// Once per time step.
    Substep,
    /// `iterations` times per time step and, within an iteration, once per constraint group:
    /// a stage of one sweep ([`Stage::sweep`]) for each of that sweep's groups, followed
    /// each time by the stages of no sweep (consecutive such stages repeat together).
    Iteration,
    /// As [`Repeat::Iteration`], in the first iteration only (the finite elements' coarse
    /// level, built at a step's first linearisation).
    FirstIteration,
    /// As [`Repeat::Iteration`], in the last iteration only (the finite elements' rigid-part
    /// correction).
    LastIteration,
    /// Once per iteration, after its constraint groups (the global volume constraints).
    IterationEnd,
    /// After the iterations, [`Schedule::inversion_sweeps`] times: once per group of the
    /// stage's sweep, each followed by the [`Repeat::Iteration`] stages of no sweep (the
    /// inversion floor, then `constraint_apply`), then the global volume stages when the
    /// step has them.
    Restore,
    /// Once per time step after the iterations, before the inversion sweeps (MINRES's
    /// passes around its iterations; their dispatches carry the iteration count as their
    /// iteration).
    AfterIterations,
    /// [`Schedule::minres`] times per time step, after the [`Repeat::AfterIterations`]
    /// stages before it (MINRES's iterations; their dispatches carry its iteration).
    Minres,
    /// Once per frame, after the last time step.
    Frame,
}

/// The elements one run of a stage covers (one invocation, or one loop body, each).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Domain {
    /// Every node.
    Nodes,
    /// Every spring.
    Springs,
    /// Every tet.
    Tets,
    /// The constraints of the current group of the stage's sweep ([`GroupAt`]).
    Group,
    /// The surface nodes and faces of every object (global volume constraints).
    Surface,
    /// MINRES's rows: every constraint of the step (one invocation each), then one
    /// workgroup per global volume constraint.
    Rows,
    /// The finite elements' workgroup passes: per aggregate of the coarse level, per block
    /// of its matrix, per object, or one workgroup (the engine plan sizes each).
    Coarse,
}

/// One stage of the step: a pass, when it runs, what it covers, what it touches.
#[derive(Debug, Clone, PartialEq)]
pub struct Stage {
    /// Which pass (its name in timings and records, its shader, its CPU arm).
    pub kind: PassKind,
    /// How often it runs.
    pub repeat: Repeat,
    /// The elements of one run.
    pub domain: Domain,
    /// The sweep ([`Schedule::sweeps`]) whose constraints it solves, for the constraint
    /// stages; `None` for the others (a [`Repeat::Iteration`] stage of no sweep follows
    /// every group of every sweep).
    pub sweep: Option<usize>,
    /// The arrays it reads and writes.
    pub bindings: Vec<(BufferId, Access)>,
}

impl Repeat {
    /// Whether a stage of this repetition belongs to the iterations' block (runs in some
    /// or every iteration, group by group).
    pub fn in_iterations(self) -> bool {
        matches!(
            self,
            Repeat::Iteration | Repeat::FirstIteration | Repeat::LastIteration
        )
    }

    /// Whether a stage of this repetition runs in iteration `iteration` of `iterations`.
    pub fn runs_in(self, iteration: u32, iterations: u32) -> bool {
        match self {
            Repeat::FirstIteration => iteration == 0,
            Repeat::LastIteration => iteration + 1 == iterations,
            _ => true,
        }
    }

    /// Of `iterations`, how many iterations a stage of this repetition runs in.
    pub fn iterations_of(self, iterations: u32) -> u32 {
        match self {
            Repeat::FirstIteration | Repeat::LastIteration => iterations.min(1),
            _ => iterations,
        }
    }
}

impl Stage {
    /// The arrays it writes: the barrier after it covers these.
    pub fn writes(&self) -> impl Iterator<Item = BufferId> + '_ {
        (self.bindings.iter())
            .filter(|(_, access)| *access != Access::Read)
            .map(|(id, _)| *id)
    }

    /// Whether it reads or writes `id`.
    pub fn touches(&self, id: BufferId) -> bool {
        self.bindings.iter().any(|(b, _)| *b == id)
    }
}

/// One constraint sweep of an iteration ([`crate::model::Model::constraint_sweeps`]): its
/// kind and the sizes of its groups.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SweepPlan {
    /// What the constraints are.
    pub kind: ConstraintKind,
    /// Constraints per group, solved one group after another.
    pub groups: Vec<u32>,
    /// Block Gauss-Seidel's blocks of its one group, when it sweeps in blocks.
    pub blocks: Option<BlockShape>,
}

/// The shape of a sweep's blocks (block Gauss-Seidel; [`crate::model::ConstraintBlocks`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockShape {
    /// Number of blocks (one workgroup each on the GPU).
    pub blocks: u32,
    /// The blocks' nodes, counted per block (a node in two blocks counts twice).
    pub nodes: u32,
    /// The most constraints in one block (the GPU's workgroup size, one invocation each).
    pub largest: u32,
    /// The most colours in one block (barriers per sweep of a block).
    pub colours: u32,
}

impl SweepPlan {
    /// The kind and group sizes of `sweep`.
    pub fn of(sweep: &Sweep) -> Self {
        SweepPlan {
            kind: sweep.kind,
            groups: sweep.groups.sizes(),
            blocks: sweep.blocks.as_ref().map(|b| BlockShape {
                blocks: b.len() as u32,
                nodes: b.nodes.items.len() as u32,
                largest: b.largest(),
                colours: b.most_colours(),
            }),
        }
    }

    /// The pass that solves it.
    pub fn pass(&self) -> PassKind {
        self.kind.pass()
    }

    /// Nodes per constraint (contribution slots per constraint on the gather path).
    pub fn corners(&self) -> u64 {
        self.kind.arity() as u64
    }

    /// Constraints of all its groups.
    pub fn constraints(&self) -> u64 {
        self.groups.iter().map(|&g| u64::from(g)).sum()
    }
}

/// A frame's stages in execution order and what unrolls them.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    /// Stages in execution order: the time step's (repeated `substeps` times), then the
    /// frame's.
    pub stages: Vec<Stage>,
    /// The constraint sweeps of an iteration, in order (implicit springs, then the method's
    /// constraints; empty without constraint iterations).
    pub sweeps: Vec<SweepPlan>,
    /// Time steps per frame.
    pub substeps: u32,
    /// Constraint iterations per time step.
    pub iterations: u32,
    /// Whether constraint forces are gathered per node in a fixed order (every solver but
    /// Jacobi, whose forces the Vulkan engine sums with float atomics).
    pub gather: bool,
    /// Whether implicit springs are warm-started: `spring_warm_start` applies the stored
    /// multipliers as forces before the first iteration, which `spring_constraint` then
    /// takes as the multipliers so far in iteration 0.
    pub warm_start: bool,
    /// The Chebyshev weight of each iteration (solver `chebyshev`; empty otherwise).
    pub chebyshev: Vec<f64>,
    /// Anderson acceleration's memory (0: off; `anderson_sum` and `anderson_mix` end every
    /// iteration).
    pub anderson: u32,
    /// Whether Anderson acceleration mixes the volume constraints' multipliers: some are
    /// compliant (a hard constraint never reads its multiplier). The springs' are mixed
    /// whenever they are constraints (implicit springs are compliant).
    pub anderson_volumes: bool,
    /// MINRES iterations after the constraint iterations (0: none; `minres_*`).
    pub minres: u32,
    /// Inversion sweeps after the iterations (0: none; `inversion_floor` runs per group of
    /// the volume sweep, [`Repeat::Restore`]).
    pub inversion_sweeps: u32,
    /// The fraction of the rest volume the inversion sweeps restore.
    pub inversion_floor: f64,
    /// Sweeps of each block per iteration (block Gauss-Seidel; 1 otherwise).
    pub block_sweeps: u32,
    /// The same for the implicit springs' blocks ([`crate::SimParams::spring_sweeps`]).
    pub spring_block_sweeps: u32,
    /// Whether the step has a floor.
    pub floor: bool,
    /// Kinematic colliders, solved with the floor (0: none).
    pub colliders: u32,
    /// Whether grabs hold nodes (their attachments are solved with the colliders).
    pub grabs: bool,
    /// Split contact (`contact = "split"`): each step solves twice from the same state,
    /// first the velocity solve, ended by `split_velocity`, then the full solve
    /// ([`Schedule::step`]).
    pub split: bool,
}

/// The position of the first of `stages` that runs after `kind` (declaration order).
fn before(stages: &[Stage], kind: PassKind) -> usize {
    (stages.iter())
        .position(|s| s.kind > kind)
        .unwrap_or(stages.len())
}

impl Schedule {
    /// Sweeps of each block per iteration in a pass of `kind` (block Gauss-Seidel): the
    /// step's `block_sweeps` for a constraint pass (`spring_block_sweeps` for the implicit
    /// springs'), 1 for the inversion floor's.
    pub fn block_sweeps_of(&self, kind: PassKind) -> u32 {
        match kind {
            PassKind::InversionFloor => 1,
            PassKind::SpringConstraint => self.spring_block_sweeps,
            _ => self.block_sweeps,
        }
    }

    /// The schedule of a prepared problem, with the per-frame volume stage when `metrics`.
    pub fn of(problem: &Problem, metrics: bool) -> Self {
        let sweeps = problem.sweeps.iter().map(SweepPlan::of).collect();
        let mut schedule =
            Schedule::new(&problem.params, sweeps, problem.global.is_some(), metrics);
        schedule.anderson_volumes &= problem.material.has_compliant_volumes();
        schedule
            .with_body_contact(problem.bodies.is_some())
            .with_colliders(
                problem.model.colliders.len() as u32,
                !problem.model.grabs.is_empty(),
            )
            .with_clamps(
                (problem.model.clamps.iter())
                    .map(|c| c.nodes.len() as u32)
                    .sum(),
            )
            .with_contact_measure(metrics)
            .with_reactions(metrics)
    }

    /// The same schedule with the body contact stages when `on` ([`crate::contact`]): once
    /// per step before the iterations the broad phase (`contact_count`, `contact_scan`,
    /// `contact_fill`: a hash of the surface triangles built by counting sort; the GPU's
    /// own, no-ops on the CPU backends, whose `contact_find` hashes) and `contact_find`;
    /// after each iteration's other constraints (once per step for springs-only methods)
    /// `contact_solve` and `contact_apply` (the GPU's application of the solve's per-node
    /// sums, a no-op on the CPU backends, whose `contact_solve` applies).
    pub fn with_body_contact(mut self, on: bool) -> Self {
        if !on {
            return self;
        }
        use Access::{Read, ReadWrite, Write};
        use BufferId::*;
        let substep = |kind, bindings| Stage {
            kind,
            repeat: Repeat::Substep,
            domain: Domain::Surface,
            sweep: None,
            bindings,
        };
        let predicted = [(Positions, Read), (Velocities, Read), (BodySurface, Read)];
        let broad = vec![
            substep(
                PassKind::ContactCount,
                [
                    &predicted[..],
                    &[(ContactHash, ReadWrite), (Status, ReadWrite)],
                ]
                .concat(),
            ),
            substep(
                PassKind::ContactScan,
                vec![
                    (BodySurface, Read),
                    (ContactHash, ReadWrite),
                    (ContactSums, Write),
                    (Status, ReadWrite),
                ],
            ),
            substep(
                PassKind::ContactFill,
                [&predicted[..], &[(ContactHash, ReadWrite)]].concat(),
            ),
            substep(
                PassKind::ContactFind,
                [
                    &predicted[..],
                    &[
                        (Springs, Read),
                        (NodeSpringOffsets, Read),
                        (NodeSpringItems, Read),
                        (ContactHash, Read),
                        (Contacts, Write),
                        (ContactSums, ReadWrite),
                    ],
                ]
                .concat(),
            ),
        ];
        let at = before(&self.stages, PassKind::ContactCount);
        self.stages.splice(at..at, broad);
        let repeat = match self.sweeps.is_empty() {
            true => Repeat::Substep,
            false => Repeat::IterationEnd,
        };
        let solve = vec![
            Stage {
                repeat,
                ..substep(
                    PassKind::ContactSolve,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (Forces, Read),
                        (Contacts, ReadWrite),
                        (ContactSums, ReadWrite),
                    ],
                )
            },
            Stage {
                repeat,
                domain: Domain::Nodes,
                ..substep(
                    PassKind::ContactApply,
                    vec![
                        (Positions, Read),
                        (Velocities, Read),
                        (ContactSums, ReadWrite),
                        (Forces, ReadWrite),
                    ],
                )
            },
        ];
        let at = before(&self.stages, PassKind::ContactSolve);
        self.stages.splice(at..at, solve);
        self
    }

    /// How many of a step's solves run stage `kind`: 2 for the stages before
    /// `split_velocity` with split contact ([`Schedule::step`]), else 1.
    pub fn solves_running(&self, kind: PassKind) -> u32 {
        match self.split && kind < PassKind::SplitVelocity {
            true => 2,
            false => 1,
        }
    }

    /// Whether `kind` runs in the frame.
    pub fn runs(&self, kind: PassKind) -> bool {
        self.stages.iter().any(|s| s.kind == kind)
    }

    /// Constraint groups solved one after another per iteration, over all sweeps (at
    /// least 1).
    pub fn group_count(&self) -> u32 {
        (self.sweeps.iter().map(|s| s.groups.len()).sum::<usize>()).max(1) as u32
    }

    /// The groups the [`Repeat::Restore`] stages run for in one step (each followed by the
    /// stages of no sweep): their sweep's groups, `inversion_sweeps` times.
    pub fn restore_groups(&self) -> u32 {
        (self.stages.iter())
            .filter(|s| s.repeat == Repeat::Restore)
            .filter_map(|s| s.sweep.and_then(|w| self.sweeps.get(w)))
            .map(|w| w.groups.len().max(1) as u32 * self.inversion_sweeps)
            .sum()
    }

    /// How many times the [`Repeat::IterationEnd`] stage `kind` runs per step: once per
    /// iteration, and the global volume stages once more after each inversion sweep and
    /// after MINRES when it closes the step ([`Self::closes_minres`]).
    pub fn iteration_ends(&self, kind: PassKind) -> u32 {
        let restores = self.stages.iter().any(|s| s.repeat == Repeat::Restore);
        if !kind.is_global_volume() {
            return self.iterations;
        }
        let after_restores = if restores { self.inversion_sweeps } else { 0 };
        self.iterations + after_restores + u32::from(self.closes_minres())
    }

    /// Whether the global volume constraints run once more after MINRES: when the step
    /// solves both and no inversion sweep follows (those end with them already). MINRES
    /// solves the global rows with the others, only as far as its iterations go; this
    /// projection restores the total exactly, as every iteration of the sweeps does
    /// (docs/PHYSICS.md, "MINRES after the sweeps").
    pub fn closes_minres(&self) -> bool {
        let runs = |kind| self.stages.iter().any(|s| s.kind == kind);
        runs(PassKind::MinresForces)
            && runs(PassKind::GlobalVolume)
            && !self.stages.iter().any(|s| s.repeat == Repeat::Restore)
    }

    /// The Chebyshev weight of `iteration` (1 without Chebyshev).
    pub fn chebyshev_weight(&self, iteration: u32) -> f64 {
        self.chebyshev
            .get(iteration as usize)
            .copied()
            .unwrap_or(1.0)
    }
}
