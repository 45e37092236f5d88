//! Backend `cpu-ref`: the oracle. Double precision, one thread, deterministic, and written to
//! read like physics.md: every stage is a plain loop over springs, tets or nodes.

use glam::DVec3;

use super::{check_state, diverged, Bad};
use crate::backend::{Backend, State, VolumeSample};
use crate::collider::{self, NodeContact};
use crate::contact::Contact;
use crate::error::Result;
use crate::model::{GlobalObject, GlobalVolume, Model};
use crate::params::SimParams;
use crate::physics::{
    compliant_multiplier, face_volume, floor_solve, implicit_accumulate, implicit_multiplier,
    integrate_node, spring_constraint, spring_force, tet_volume,
};
use crate::problem::Problem;
use crate::schedule::family::{ConstraintFamily, Family};
use crate::schedule::{Dispatch, GroupAt, PassKind, Schedule};

/// The forces of steps 1 and 2 of one time step, per node [N]; their sum is the `F` that is
/// integrated.
#[derive(Debug, Clone, PartialEq)]
pub struct Forces {
    /// `m g` along -Y.
    pub gravity: Vec<DVec3>,
    /// Spring forces (zero for methods without springs).
    pub springs: Vec<DVec3>,
    /// Constraint forces of all iterations, combined and relaxed.
    pub constraints: Vec<DVec3>,
    /// The floor's normal force (along +Y, `>= 0`; zero without a floor).
    pub floor: Vec<f64>,
    /// The kinematic colliders' force and contact ([`collider::solve_node`]; none without
    /// colliders).
    pub contacts: Vec<NodeContact>,
    /// Per spring, the multiplier of its implicit spring after the step's iterations (the
    /// force is `-lambda grad C`); zeros with explicit springs.
    pub spring_multipliers: Vec<f64>,
    /// Per tet, the multiplier of its compliant volume constraint after the iterations
    /// (zero for hard ones).
    pub volume_multipliers: Vec<f64>,
}

impl Forces {
    /// The total force on each node.
    pub fn total(&self) -> Vec<DVec3> {
        (0..self.gravity.len())
            .map(|i| {
                self.gravity[i]
                    + self.springs[i]
                    + self.constraints[i]
                    + DVec3::Y * self.floor[i]
                    + self.contacts[i].force
            })
            .collect()
    }
}

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
    /// Per sweep and group, each node's `(a_scale, apply_weight)` from its degree within the
    /// group.
    group_factors: Vec<Vec<Vec<(f64, f64)>>>,
    /// Per spring, its implicit multiplier at the end of the last step: the next step's
    /// start with `warm_start` (zeros otherwise, and after [`Self::set_state`]).
    spring_warm: Vec<f64>,
    /// The step it runs.
    schedule: Schedule,
    /// One time step's dispatches ([`Schedule::step`]).
    dispatches: Vec<Dispatch>,
    /// Per sweep, its constraint family's data.
    families: Vec<Family<f64>>,
}

/// The forces of a time step while its dispatches run.
struct StepForces {
    gravity: Vec<DVec3>,
    /// Explicit spring forces, or the warm start's (zeros without a spring force stage).
    springs: Vec<DVec3>,
    /// The total force so far.
    total: Vec<DVec3>,
    /// The floor's normal force so far.
    floor: Vec<f64>,
    /// The colliders' force and contact so far.
    contacts: Vec<NodeContact>,
    /// Each node's [`collider::clearance`] in this step (empty until the first solve).
    clearance: Vec<f64>,
    /// Each node's attachment to a grab in this step.
    attached: Vec<Option<collider::Attachment>>,
    /// The compliant constraints' multipliers found so far in this step (the warm start's
    /// for the springs).
    spring_lambda: Vec<f64>,
    volume_lambda: Vec<f64>,
    /// Chebyshev: the total and floor forces two iterations back.
    before_total: Vec<DVec3>,
    before_floor: Vec<f64>,
    /// The current group's per-node constraint sums.
    sum: Vec<DVec3>,
    /// Per global volume object: `C_g`, the surface gradients and the multiplier.
    global: Vec<(f64, Vec<DVec3>, f64)>,
    /// The step's body contacts with their multipliers so far (`<= 0`: they push).
    bodies: Vec<(Contact, f64)>,
}

impl StepForces {
    /// Gravity alone, at the start of a step of `backend`.
    fn new(backend: &ReferenceBackend) -> Self {
        let problem = &backend.problem;
        let n = problem.model.node_count();
        let down = DVec3::new(0.0, -problem.params.gravity, 0.0);
        let gravity: Vec<DVec3> = problem.model.mass.iter().map(|&m| down * m).collect();
        let mut step = StepForces {
            springs: vec![DVec3::ZERO; n],
            total: Vec::new(),
            floor: vec![0.0; n],
            contacts: vec![NO_CONTACT; n],
            clearance: Vec::new(),
            attached: Vec::new(),
            spring_lambda: backend.spring_warm.clone(),
            volume_lambda: vec![0.0; problem.model.tets.len()],
            before_total: Vec::new(),
            before_floor: Vec::new(),
            sum: Vec::new(),
            global: Vec::new(),
            bodies: Vec::new(),
            gravity,
        };
        step.set_springs(vec![DVec3::ZERO; n]);
        step
    }

    /// The spring forces: the total becomes gravity plus them (and so do the Chebyshev
    /// forces before the first iteration).
    fn set_springs(&mut self, springs: Vec<DVec3>) {
        self.total = (self.gravity.iter().zip(&springs))
            .map(|(g, s)| *g + *s)
            .collect();
        self.springs = springs;
        self.before_total.clone_from(&self.total);
        self.before_floor.clone_from(&self.floor);
    }
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
            group_factors,
            spring_warm: vec![0.0; model.springs.len()],
            schedule,
            dispatches,
            families: Family::of_sweeps(problem),
        }
    }

    /// Replaces positions and velocities (e.g. to start from a moving or deformed state).
    pub fn set_state(&mut self, state: &State) -> Result<()> {
        check_state(self.problem.model.node_count(), state)?;
        self.x.clone_from(&state.positions);
        self.v.clone_from(&state.velocities);
        self.spring_warm.fill(0.0);
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
        let mut step = StepForces::new(self);
        for dispatch in &self.dispatches {
            if self.schedule.stages[dispatch.stage].kind == PassKind::Integrate {
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
        let total = &step.total;
        let (springs, volumes) = (&mut step.spring_lambda, &mut step.volume_lambda);
        match &self.families[at.sweep] {
            Family::Springs(family) => self.sweep(members, family, total, &a_scale, springs),
            Family::Distances(family) => self.sweep(members, family, total, &a_scale, springs),
            Family::Volumes(family) => self.sweep(members, family, total, &a_scale, volumes),
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

    /// With implicit springs: each spring's warm-start multiplier (zero without
    /// `warm_start`) as the force `-lambda grad C` at the current positions.
    fn warm_start_forces(&self) -> Vec<DVec3> {
        let mut f = vec![DVec3::ZERO; self.problem.model.node_count()];
        for (s, &lambda) in self.spring_warm.iter().enumerate() {
            if lambda != 0.0 {
                let ids = self.problem.model.springs[s].map(|i| i as usize);
                let (_, grad) = spring_constraint(
                    self.x[ids[0]],
                    self.x[ids[1]],
                    self.problem.model.rest_length[s],
                );
                for k in 0..2 {
                    f[ids[k]] -= grad[k] * lambda;
                }
            }
        }
        f
    }

    /// Per object of the global volume constraints: `C_g` and the gradient on each of its
    /// surface nodes (in [`GlobalVolume::nodes`] order from the object's first) at the
    /// step's positions, the multiplier still 0. The reference point of the face volumes is
    /// the object's first surface node.
    fn global_prepare(&self) -> Vec<(f64, Vec<DVec3>, f64)> {
        let Some(global) = &self.problem.global else {
            return Vec::new();
        };
        (global.objects.iter())
            .map(|object| {
                let (c, grad) = self.global_gradients(global, object);
                (c, grad, 0.0)
            })
            .collect()
    }

    /// `C_g` of `object` and its gradient on each of its surface nodes.
    fn global_gradients(&self, global: &GlobalVolume, object: &GlobalObject) -> (f64, Vec<DVec3>) {
        let nodes = &global.nodes[object.node_first as usize..][..object.node_count as usize];
        let faces = &global.faces[object.face_first as usize..][..object.face_count as usize];
        let o = self.x[nodes[0] as usize];
        let mut c = -object.rest_volume;
        let mut face_grad = Vec::with_capacity(faces.len());
        for face in faces {
            let (v, g) = face_volume(face.map(|i| self.x[i as usize]), o);
            c += v;
            face_grad.push(g);
        }
        let first_face = 3 * object.face_first as usize;
        let grad = (0..nodes.len())
            .map(|k| {
                let row = global.node_faces.row(object.node_first as usize + k);
                row.iter()
                    .map(|&e| face_grad[(e as usize - first_face) / 3][e as usize % 3])
                    .sum()
            })
            .collect();
        (c, grad)
    }

    /// Every object's global volume multiplier against the step's forces so far.
    fn global_multipliers(&self, step: &mut StepForces) {
        let Some(global) = &self.problem.global else {
            return;
        };
        let p = &self.problem.params;
        for (object, (c, grad, lambda)) in global.objects.iter().zip(&mut step.global) {
            let nodes = &global.nodes[object.node_first as usize..][..object.node_count as usize];
            let (mut a, mut b) = (0.0, 0.0);
            for (&i, &g) in nodes.iter().zip(grad.iter()) {
                let i = i as usize;
                let w = self.problem.model.inv_mass[i];
                implicit_accumulate(&mut a, &mut b, g, w, 1.0, self.v[i], step.total[i], p.dt);
            }
            *lambda = implicit_multiplier(*c, a, b, p.dt, p.constraint_epsilon).unwrap_or(0.0);
        }
    }

    /// One Jacobi sweep of the step's body contacts against the forces so far
    /// ([`crate::contact::BodyContact::sweep`]), its forces added, then the floor and the
    /// colliders again.
    fn contact_iteration(&self, step: &mut StepForces) {
        let Some(bodies) = &self.problem.bodies else {
            return;
        };
        let (model, params) = (&self.problem.model, &self.problem.params);
        let total = &step.total;
        let forces = bodies.sweep(
            &mut step.bodies,
            model,
            params,
            |i| self.x[i],
            |i| self.v[i],
            |i| total[i],
        );
        for (i, force) in forces {
            step.total[i] += force;
        }
        self.contact_solve(step);
    }

    /// Solves every node's contacts against the step's total force (which includes the
    /// contact forces found so far) and updates both: the floor's, then the colliders' in
    /// their order ([`collider::solve_node`]).
    fn contact_solve(&self, step: &mut StepForces) {
        let (model, dt) = (&self.problem.model, self.problem.params.dt);
        if self.problem.params.floor {
            for (i, (f, n)) in step.total.iter_mut().zip(step.floor.iter_mut()).enumerate() {
                (*f, *n) = floor_solve(*f, *n, self.x[i].y, self.v[i].y, model.inv_mass[i], dt);
            }
        }
        if model.colliders.is_empty() && model.grabs.is_empty() {
            return;
        }
        let at = collider::at_step(&model.colliders, self.steps, dt);
        if step.clearance.is_empty() {
            step.clearance = self
                .x
                .iter()
                .map(|&x| collider::clearance(&at, x))
                .collect();
            let t = self.steps as f64 * dt;
            step.attached = collider::attachments(&model.grabs, &model.positions, t, dt);
        }
        let nodes = step.total.iter_mut().zip(step.contacts.iter_mut());
        for (i, (f, c)) in nodes.enumerate() {
            let (x, v, w, clear) = (self.x[i], self.v[i], model.inv_mass[i], step.clearance[i]);
            (*f, *c) = match step.attached[i] {
                Some(a) => collider::solve_node_attached(&at, Some(a), *f, c.force, x, v, w, dt),
                None => collider::solve_node_clear(&at, clear, *f, c.force, x, v, w, dt),
            };
        }
    }

    /// Spring forces, one spring at a time, added to both ends.
    pub fn spring_forces_scatter(&self) -> Vec<DVec3> {
        let mut f = vec![DVec3::ZERO; self.problem.model.node_count()];
        for (s, &[i, j]) in self.problem.model.springs.iter().enumerate() {
            let (i, j) = (i as usize, j as usize);
            let fi = self.spring(i, j, s);
            f[i] += fi;
            f[j] -= fi;
        }
        f
    }

    /// Spring forces, one node at a time, gathered over its springs (`node_springs`).
    pub fn spring_forces_gather(&self) -> Vec<DVec3> {
        (0..self.problem.model.node_count())
            .map(|i| {
                let mut f = DVec3::ZERO;
                for &s in self.problem.model.node_springs.row(i) {
                    let [a, b] = self.problem.model.springs[s as usize];
                    let other = if a as usize == i { b } else { a };
                    f += self.spring(i, other as usize, s as usize);
                }
                f
            })
            .collect()
    }

    /// Explicit force on node `i` of spring `s`, whose other end is `j`.
    fn spring(&self, i: usize, j: usize, s: usize) -> DVec3 {
        spring_force(
            self.x[i],
            self.x[j],
            self.v[i],
            self.v[j],
            self.problem.model.rest_length[s],
            self.problem.material.spring_stiffness[s],
            self.problem.material.spring_damping[s],
        )
    }

    /// One Jacobi sweep of the constraints `members` of `family` against the force `f`
    /// ([`ConstraintFamily::evaluate`] gives each one's value, gradients, softness and
    /// damping); returns the per-node sums of `-delta grad C`, `delta` the
    /// compliant multiplier's increment ([`Self::lambda`]). A compliant constraint
    /// (softness > 0) carries its multiplier so far in `lambda[e]`, which grows by
    /// `omega delta`; a hard one neither reads nor changes it.
    fn sweep<const K: usize, F: ConstraintFamily<f64, K>>(
        &self,
        members: &[u32],
        family: &F,
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
            let so_far = if softness > 0.0 {
                softness * lambda[e]
            } else {
                0.0
            };
            if let Some(delta) = self.lambda(c, &grad, ids, f, a_scale, so_far, softness, damping) {
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
    /// the nodes `ids` against the force `f` ([`compliant_multiplier`]; softness 0: hard),
    /// `so_far` = softness times the multiplier found so far (subtracted from `B`).
    #[allow(clippy::too_many_arguments)]
    fn lambda<const K: usize>(
        &self,
        c: f64,
        grad: &[DVec3; K],
        ids: [usize; K],
        f: &[DVec3],
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
                &mut a, &mut b, grad[k], w, a_scale[i], self.v[i], f[i], p.dt,
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
        let f = forces.total();
        if self.problem.params.warm_start {
            std::mem::swap(&mut self.spring_warm, &mut forces.spring_multipliers);
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
            let contact = forces.floor[i] > 0.0;
            let x0 = *x;
            (*x, *v) = integrate_node(x0, *v, f, w, p.dt, contact, p.friction);
            if forces.contacts[i].touching.is_some() {
                *v = collider::friction_of(&at, &forces.contacts[i], x0, *v, p.dt);
                *x = x0 + *v * p.dt;
            }
            if bad.is_none() {
                if !(x.is_finite() && v.is_finite()) {
                    bad = Some((i, Bad::NonFinite));
                } else if v.length() > limit {
                    bad = Some((i, Bad::TooFast(v.length())));
                }
            }
        }
        self.steps += 1;
        bad
    }
}

/// No collider contact.
const NO_CONTACT: NodeContact = NodeContact {
    force: DVec3::ZERO,
    touching: None,
};

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
        Ok(VolumeSample {
            volume,
            inverted,
            local_error,
        })
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
}
