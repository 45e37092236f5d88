//! Backend `cpu-ref`: the oracle. Double precision, one thread, deterministic, and written to
//! read like physics.md: every stage is a plain loop over springs, tets or nodes.

use glam::DVec3;

use super::{check_state, diverged, Bad};
use crate::backend::{
    flatten, restore_coarse, unflatten, Backend, Carried, ContactSample, Reactions, State,
    VolumeSample, COARSE_KEY,
};
use crate::collider;
use crate::contact::{deepest, Contact};
use crate::error::Result;
use crate::model::Model;
use crate::params::{ContactMode, Method, SimParams};
use crate::physics::{
    compliant_multiplier, elastic_start, implicit_accumulate, integrate_node, tet_volume, Solve,
};
use crate::problem::Problem;
use crate::schedule::family::{ConstraintFamily, Family};
use crate::schedule::{Dispatch, GroupAt, PassKind, Schedule};

mod anderson;
mod blocks;
mod elastic;
mod inversion;
mod minres;
mod reactions;
mod springs;
mod step_forces;
mod surfaces;

pub use step_forces::Forces;
use step_forces::StepForces;

/// The reference solver (`cpu-ref`).
#[derive(Debug, Clone)]
pub struct ReferenceBackend {
    /// The model, parameters, sweeps, materials and global constraints it executes.
    problem: Problem,
    x: Vec<DVec3>,
    v: Vec<DVec3>,
    frame: u32,
    /// Time steps taken since creation (the colliders' clock; [`Self::set_state`] keeps it).
    steps: u64,
    /// The last step's nodes pushed by a collider and its body contacts.
    last_contacts: (u32, Vec<(Contact, f64)>),
    /// Per sweep and group, each node's `(a_scale, apply_weight)` from its degree within the
    /// group.
    group_factors: Vec<Vec<Vec<(f64, f64)>>>,
    /// Per spring, its implicit multiplier at the end of the last step: the next step's
    /// start with `warm_start` (zeros otherwise, and after [`Self::set_state`]).
    spring_warm: Vec<f64>,
    /// Per node, the elastic force at the end of the last step (finite elements: the next
    /// step's start; zeros otherwise, and after [`Self::set_state`]).
    elastic_warm: Vec<DVec3>,
    /// The finite elements' coarse level, kept from step to step (built every
    /// [`crate::physics::COARSE_REBUILD_STEPS`]; `RefCell`: the step's solve builds it
    /// through `&self`).
    coarse: std::cell::RefCell<crate::physics::CoarseSpace>,
    /// The step it runs.
    schedule: Schedule,
    /// One time step's dispatches ([`Schedule::step`]).
    dispatches: Vec<Dispatch>,
    /// Per sweep, its constraint family's data.
    families: Vec<Family<f64>>,
    /// The forces the supports exerted in the last step.
    reactions: Reactions,
    /// Per node, the clamp that holds it ([`crate::collider::clamp_of_nodes`]).
    clamp_of: Vec<Option<u32>>,
}

impl ReferenceBackend {
    /// A solver at the model's initial positions and velocities. Fails on invalid parameters.
    pub fn new(model: &Model, params: &SimParams) -> Result<Self> {
        Ok(Self::from_problem(&Problem::new(model, params)?))
    }

    /// A solver for a prepared problem, at its model's initial positions and velocities.
    pub fn from_problem(problem: &Problem) -> Self {
        let (model, params) = (&problem.model, &problem.params);
        let n = model.node_count();
        let group_factors = problem
            .sweeps
            .iter()
            .map(|sweep| {
                (0..sweep.groups.len())
                    .map(|g| {
                        sweep
                            .groups
                            .group_degree(g, n)
                            .iter()
                            .map(|&d| params.combine.node_factors(d))
                            .collect()
                    })
                    .collect()
            })
            .collect();
        let schedule = Schedule::of(problem, false);
        let dispatches = schedule.step();
        ReferenceBackend {
            problem: problem.clone(),
            x: model.positions.clone(),
            v: model.velocities.clone(),
            frame: 0,
            steps: 0,
            last_contacts: (0, Vec::new()),
            group_factors,
            spring_warm: vec![0.0; model.springs.len()],
            elastic_warm: match params.method {
                Method::NeoHookean => vec![DVec3::ZERO; n],
                _ => Vec::new(),
            },
            coarse: Default::default(),
            schedule,
            dispatches,
            families: Family::of_sweeps(problem),
            reactions: Reactions::none(model.colliders.len(), model.clamps.len()),
            clamp_of: crate::collider::clamp_of_nodes(&model.clamps, model.node_count()),
        }
    }

    /// Replaces positions and velocities (e.g. to start from a moving or deformed state).
    pub fn set_state(&mut self, state: &State) -> Result<()> {
        check_state(self.problem.model.node_count(), state)?;
        self.x.clone_from(&state.positions);
        self.v.clone_from(&state.velocities);
        self.spring_warm.fill(0.0);
        self.elastic_warm.fill(DVec3::ZERO);
        Ok(())
    }

    /// Steps 1 and 2 of a time step at the current state: the schedule's dispatches
    /// ([`Schedule::step`]) run in order, each as a plain loop ([`Self::run`]), up to the
    /// floor's last solve, which begins `integrate`. With the default solver that is gravity,
    /// explicit springs (spring-centric, `spring_scatter`, or node-centric, `spring_gather`,
    /// as the schedule says: the same sums here) or, for warm-started implicit springs, the last step's multipliers as forces,
    /// then `iterations` times the sweeps ([`Model::constraint_sweeps`]: implicit springs,
    /// then the method's constraints), each group after group (one group for Jacobi and
    /// Chebyshev, the colour groups for Gauss-Seidel; Chebyshev extrapolating each
    /// iteration's forces) and each group followed by the floor's solve, then the global
    /// volume constraints (when solved) and the floor again.
    pub fn forces(&self) -> Forces {
        self.forces_of(Solve::Full)
    }

    /// [`Self::forces`] of one of the step's solves: the full one, or split contact's
    /// velocity solve ([`Solve::Velocity`]: hard constraints asked for no change of their
    /// value, contacts for no deeper penetration).
    pub fn forces_of(&self, solve: Solve) -> Forces {
        let mut step = StepForces::new(self, solve);
        for dispatch in self.dispatches.iter().filter(|d| d.solve == solve) {
            let kind = self.schedule.stages[dispatch.stage].kind;
            if matches!(kind, PassKind::Integrate | PassKind::SplitVelocity) {
                break;
            }
            self.run(dispatch, &mut step);
        }
        self.contact_solve(&mut step);
        let n = self.problem.model.node_count();
        let constraints = (0..n)
            .map(|i| {
                step.total[i]
                    - step.gravity[i]
                    - step.springs[i]
                    - DVec3::Y * step.floor[i]
                    - step.contacts[i].force
            })
            .collect();
        Forces {
            gravity: step.gravity,
            springs: step.springs,
            constraints,
            floor: step.floor,
            contacts: step.contacts,
            bodies: step.bodies,
            spring_multipliers: step.spring_lambda,
            volume_multipliers: step.volume_lambda,
        }
    }

    /// One dispatch of the schedule on the step's forces so far.
    fn run(&self, dispatch: &Dispatch, step: &mut StepForces) {
        let kind = self.schedule.stages[dispatch.stage].kind;
        let iteration = dispatch.iteration.unwrap_or(0);
        match (kind, dispatch.group) {
            (PassKind::SpringScatter, _) => step.set_springs(self.spring_forces_scatter()),
            (PassKind::SpringGather, _) => step.set_springs(self.spring_forces_gather()),
            (PassKind::SpringWarmStart, _) => step.set_springs(self.warm_start_forces()),
            (PassKind::GlobalVolumePrepare, _) => step.global = self.global_prepare(),
            (PassKind::ContactFind, _) => {
                if let Some(bodies) = &self.problem.bodies {
                    let (model, dt) = (&self.problem.model, self.problem.params.dt);
                    let found = bodies.find(model, &self.x, &self.v, dt);
                    step.bodies = found.into_iter().map(|c| (c, 0.0)).collect();
                }
            }
            (PassKind::ContactSolve, _) => self.contact_iteration(step),
            // The GPU's clamp drive, broad phase and application of the contact sums: here
            // `step` drives the clamps, `contact_find` hashes and `contact_solve` applies.
            (
                PassKind::ClampDrive
                | PassKind::ContactCount
                | PassKind::ContactScan
                | PassKind::ContactFill
                | PassKind::ContactApply,
                _,
            ) => {}
            (PassKind::SpringConstraint | PassKind::Distance | PassKind::Volume, Some(at)) => {
                step.sum = self.solve_group(at, step)
            }
            (PassKind::Elastic, Some(at)) => {
                step.sum = self.elastic_group(at, iteration, step);
            }
            (PassKind::InversionFloor, Some(at)) => step.sum = self.inversion_group(at, step),
            (PassKind::ConstraintApply, Some(at)) => self.apply_group(at, iteration, step),
            (PassKind::GlobalVolumeSum, _) => self.global_multipliers(step),
            (PassKind::GlobalVolume, _) => {
                if let Some(global) = &self.problem.global {
                    for (object, (_, grad, lambda)) in global.objects.iter().zip(&step.global) {
                        let nodes = &global.nodes[object.node_first as usize..];
                        for (&i, g) in nodes.iter().zip(grad) {
                            step.total[i as usize] += *g * -lambda;
                        }
                    }
                }
                self.contact_solve(step);
            }
            // MINRES's passes run as one here, after the iterations, before the inversion
            // sweeps.
            (PassKind::MinresRows, _) => self.minres_solve(step),
            // Anderson's halves run as one here.
            (PassKind::AndersonSum, _) => {}
            (PassKind::AndersonMix, _) => {
                self.anderson(iteration, step);
                self.contact_solve(step);
            }
            // The GPU's frame measure of contact: `volume()` takes it from the last step.
            (PassKind::ContactMeasure, _) => {}
            // Integration ends the step (`step`); the frame's check and volume are the
            // GPU's readbacks (this backend checks each node as it integrates it).
            _ => {}
        }
    }

    /// The constraints of group `at` against the step's forces: the per-node sums of their
    /// forces ([`Self::sweep`]).
    fn solve_group(&self, at: GroupAt, step: &mut StepForces) -> Vec<DVec3> {
        let sweep = &self.problem.sweeps[at.sweep];
        let a_scale: Vec<f64> = self.group_factors[at.sweep][at.group]
            .iter()
            .map(|f| f.0)
            .collect();
        let members = sweep.groups.group(at.group);
        let (total, solve) = (&step.total, step.solve);
        let (springs, volumes) = (&mut step.spring_lambda, &mut step.volume_lambda);
        if let Some(blocks) = &sweep.blocks {
            let factors = &self.group_factors[at.sweep][at.group];
            return match &self.families[at.sweep] {
                Family::Springs(f) => {
                    self.sweep_blocks(members, blocks, f, solve, total, factors, springs)
                }
                Family::Distances(f) => {
                    self.sweep_blocks(members, blocks, f, solve, total, factors, springs)
                }
                Family::Volumes(f) => {
                    self.sweep_blocks(members, blocks, f, solve, total, factors, volumes)
                }
                // Validation refuses blocks for the finite elements.
                Family::Elastic(_) => vec![DVec3::ZERO; self.problem.model.node_count()],
            };
        }
        match &self.families[at.sweep] {
            Family::Springs(f) => self.sweep(members, f, solve, total, &a_scale, springs),
            Family::Distances(f) => self.sweep(members, f, solve, total, &a_scale, springs),
            Family::Volumes(f) => self.sweep(members, f, solve, total, &a_scale, volumes),
            // Solved by `elastic_group` (its own pass).
            Family::Elastic(_) => vec![DVec3::ZERO; self.problem.model.node_count()],
        }
    }

    /// Group `at`'s sums applied to the forces (`omega` times the combine mode's weight),
    /// Chebyshev's extrapolation of `iteration` when it is on, then the floor's solve.
    fn apply_group(&self, at: GroupAt, iteration: u32, step: &mut StepForces) {
        let factors = &self.group_factors[at.sweep][at.group];
        let chebyshev = !self.schedule.chebyshev.is_empty();
        let current = chebyshev.then(|| (step.total.clone(), step.floor.clone()));
        for (i, f) in step.total.iter_mut().enumerate() {
            *f += step.sum[i] * (factors[i].1 * self.problem.params.omega);
        }
        if let Some((t, f)) = current {
            let w = self.schedule.chebyshev_weight(iteration);
            if w != 1.0 {
                let before = step.before_total.iter().zip(&step.before_floor);
                let now = step.total.iter_mut().zip(step.floor.iter_mut());
                for ((total, floor), (bt, bf)) in now.zip(before) {
                    *total = (*total - *bt) * w + *bt;
                    *floor = (*floor - *bf) * w + *bf;
                }
            }
            (step.before_total, step.before_floor) = (t, f);
        }
        self.contact_solve(step);
    }

    /// One Jacobi sweep of the constraints `members` of `family` against the force `f`
    /// ([`ConstraintFamily::evaluate`] gives each one's value, gradients, softness and
    /// damping); returns the per-node sums of `-delta grad C`, `delta` the
    /// compliant multiplier's increment ([`Self::lambda`]). A compliant constraint
    /// (softness > 0) carries its multiplier so far in `lambda[e]`, which grows by
    /// `omega delta`; a hard one neither reads nor changes it, and is asked for no change of
    /// its value in split contact's velocity solve (`solve`).
    #[allow(clippy::too_many_arguments)]
    fn sweep<const K: usize, F: ConstraintFamily<f64, K>>(
        &self,
        members: &[u32],
        family: &F,
        solve: Solve,
        f: &[DVec3],
        a_scale: &[f64],
        lambda: &mut [f64],
    ) -> Vec<DVec3> {
        let elements = F::elements(&self.problem.model);
        let mut sum = vec![DVec3::ZERO; self.problem.model.node_count()];
        for &e in members {
            let e = e as usize;
            let ids = elements[e].map(|i| i as usize);
            let (c, grad, softness, damping) = family.evaluate(e, ids.map(|i| self.x[i]));
            let (c, so_far) = match softness > 0.0 {
                true => (c, softness * lambda[e]),
                false => (solve.hard(c), 0.0),
            };
            let forces = ids.map(|i| f[i]);
            if let Some(delta) =
                self.lambda(c, &grad, ids, forces, a_scale, so_far, softness, damping)
            {
                if softness > 0.0 {
                    lambda[e] += self.problem.params.omega * delta;
                }
                for k in 0..K {
                    sum[ids[k]] -= grad[k] * delta;
                }
            }
        }
        sum
    }

    /// The multiplier (increment) of one constraint with value `c` and gradients `grad` on
    /// the nodes `ids` against their forces `f` ([`compliant_multiplier`]; softness 0:
    /// hard), `so_far` = softness times the multiplier found so far (subtracted from `B`).
    #[allow(clippy::too_many_arguments)]
    fn lambda<const K: usize>(
        &self,
        c: f64,
        grad: &[DVec3; K],
        ids: [usize; K],
        f: [DVec3; K],
        a_scale: &[f64],
        so_far: f64,
        softness: f64,
        damping: f64,
    ) -> Option<f64> {
        let p = &self.problem.params;
        let (mut a, mut b) = (0.0, 0.0);
        for k in 0..K {
            let i = ids[k];
            let w = self.problem.model.inv_mass[i];
            implicit_accumulate(
                &mut a, &mut b, grad[k], w, a_scale[i], self.v[i], f[k], p.dt,
            );
        }
        compliant_multiplier(
            c,
            a,
            b - so_far,
            p.dt,
            softness,
            damping,
            p.constraint_epsilon,
        )
    }

    /// One time step (physics.md steps 1-3). Returns the first node that is non-finite or
    /// faster than the speed limit, if any.
    fn step(&mut self) -> Option<(usize, Bad)> {
        let limit = self.problem.speed_limit;
        let (model, dt) = (&self.problem.model, self.problem.params.dt);
        let (x, v) = (&self.x, &mut self.v);
        collider::drive(
            &model.clamps,
            &model.positions,
            self.steps,
            dt,
            |i| x[i],
            |i, u| v[i] = u,
        );
        let mut forces = self.forces();
        let velocity = (self.problem.params.contact == ContactMode::Split).then(|| {
            let split = self.forces_of(Solve::Velocity);
            (split.total(), split)
        });
        let pushed = forces
            .contacts
            .iter()
            .filter(|c| c.touching.is_some())
            .count();
        self.last_contacts = (pushed as u32, std::mem::take(&mut forces.bodies));
        let f = forces.total();
        if self.problem.params.warm_start {
            std::mem::swap(&mut self.spring_warm, &mut forces.spring_multipliers);
        }
        if !self.elastic_warm.is_empty() {
            let gravity = self.problem.params.gravity;
            let mass = &self.problem.model.mass;
            self.elastic_warm = (f.iter().zip(mass))
                .map(|(&f, &m)| elastic_start(f, m, gravity))
                .collect();
        }
        let p = &self.problem.params;
        let at = collider::at_step(&self.problem.model.colliders, self.steps, p.dt);
        let mut bad = None;
        let nodes = self
            .x
            .iter_mut()
            .zip(self.v.iter_mut())
            .zip(f.iter().zip(&self.problem.model.inv_mass));
        for (i, ((x, v), (&f, &w))) in nodes.enumerate() {
            let (x0, v0) = (*x, *v);
            (*x, *v) = integrate_node(x0, v0, f, w, p.dt, forces.floor[i], p.friction);
            if forces.contacts[i].touching.is_some() {
                *v = collider::friction_of(&at, &forces.contacts[i], x0, *v, p.dt);
                *x = x0 + *v * p.dt;
            }
            // Split contact: the positions are the full solve's, the velocities the
            // velocity solve's (with its own contacts' friction).
            if let Some((f_v, split)) = &velocity {
                *v = integrate_node(x0, v0, f_v[i], w, p.dt, split.floor[i], p.friction).1;
                if split.contacts[i].touching.is_some() {
                    *v = collider::friction_of(&at, &split.contacts[i], x0, *v, p.dt);
                }
            }
            if bad.is_none() {
                if !(x.is_finite() && v.is_finite()) {
                    bad = Some((i, Bad::NonFinite));
                } else if v.length() > limit {
                    bad = Some((i, Bad::TooFast(v.length())));
                }
            }
        }
        self.reactions = self.reactions_of(&forces);
        self.steps += 1;
        bad
    }
}

impl Backend for ReferenceBackend {
    fn name(&self) -> &'static str {
        "cpu-ref"
    }

    fn step_frame(&mut self) -> Result<()> {
        for substep in 0..self.problem.params.substeps {
            if let Some((node, bad)) = self.step() {
                return Err(diverged(
                    self.frame,
                    substep,
                    self.problem.params.method,
                    node as u32,
                    bad,
                    self.problem.speed_limit,
                    &self.problem.likely_cause,
                ));
            }
        }
        self.frame += 1;
        Ok(())
    }

    fn reactions(&mut self) -> Result<Option<Reactions>> {
        Ok(Some(self.reactions.clone()))
    }

    fn volume(&mut self) -> Result<VolumeSample> {
        let mut volume = 0.0;
        let mut inverted = 0;
        let mut local_error = 0.0;
        for (tet, &rest) in self
            .problem
            .model
            .tets
            .iter()
            .zip(&self.problem.model.rest_volume)
        {
            let v = tet_volume(tet.map(|i| self.x[i as usize]));
            volume += v;
            inverted += u32::from(v <= 0.0);
            local_error += (v - rest).abs();
        }
        let problem = &self.problem;
        let contact = problem.measures_contact().then(|| {
            let (pushed, bodies) = &self.last_contacts;
            let (model, x) = (&problem.model, &self.x);
            let dt = problem.params.dt;
            ContactSample {
                collider_nodes: *pushed,
                body_contacts: bodies.iter().filter(|(_, l)| *l < 0.0).count() as u32,
                deepest_m: deepest(&model.colliders, self.steps, dt, bodies, |i| x[i], x.len()),
            }
        });
        Ok(VolumeSample {
            volume,
            inverted,
            local_error,
            contact,
        })
    }

    fn likely_cause(&self) -> &str {
        &self.problem.likely_cause
    }

    fn state(&mut self) -> Result<State> {
        Ok(State {
            positions: self.x.clone(),
            velocities: self.v.clone(),
        })
    }

    fn set_state(&mut self, state: &State) -> Result<()> {
        ReferenceBackend::set_state(self, state)
    }

    /// The frame and step counters, the warm-started springs' multipliers and the finite
    /// elements' forces and coarse level (each where the run has them).
    fn carried(&mut self) -> Result<Carried> {
        let mut arrays = Vec::new();
        if !self.spring_warm.is_empty() {
            arrays.push(("spring_multipliers".to_string(), self.spring_warm.clone()));
        }
        if !self.elastic_warm.is_empty() {
            arrays.push(("elastic_forces".to_string(), flatten(&self.elastic_warm)));
        }
        let coarse = self.coarse.borrow();
        if coarse.is_built() {
            arrays.push((COARSE_KEY.to_string(), coarse.to_values()));
        }
        Ok(Carried {
            frames: self.frame,
            steps: self.steps,
            arrays,
        })
    }

    fn restore(&mut self, state: &State, carried: &Carried) -> Result<()> {
        ReferenceBackend::set_state(self, state)?;
        if !self.spring_warm.is_empty() {
            let values = carried.array("spring_multipliers", self.spring_warm.len())?;
            self.spring_warm.copy_from_slice(values);
        }
        if !self.elastic_warm.is_empty() {
            let values = carried.array("elastic_forces", 3 * self.elastic_warm.len())?;
            self.elastic_warm = unflatten(values);
        }
        let aggregates = (self.families.iter())
            .find_map(|f| match f {
                Family::Elastic(nodes) => Some(nodes.aggregates.len()),
                _ => None,
            })
            .unwrap_or(0);
        *self.coarse.borrow_mut() = restore_coarse(carried, aggregates)?;
        (self.frame, self.steps) = (carried.frames, carried.steps);
        Ok(())
    }
}
