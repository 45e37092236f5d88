//! Backend `cpu-ref`: the oracle. Double precision, one thread, deterministic, and written to
//! read like physics.md: every stage is a plain loop over springs, tets or nodes.

use glam::DVec3;

use super::{check_state, diverged, Bad};
use crate::backend::{Backend, State, VolumeSample};
use crate::error::Result;
use crate::model::{ConstraintKind, GlobalObject, GlobalVolume, Model};
use crate::params::{chebyshev_weights, Method, SimParams, Solver, SpringKind};
use crate::physics::{
    compliant_multiplier, distance_constraint, face_volume, floor_solve, implicit_accumulate,
    implicit_multiplier, integrate_node, spring_constraint, spring_force, spring_softness,
    tet_volume, volume_constraint, volume_softness,
};
use crate::problem::Problem;

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
                self.gravity[i] + self.springs[i] + self.constraints[i] + DVec3::Y * self.floor[i]
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
    /// Per sweep and group, each node's `(a_scale, apply_weight)` from its degree within the
    /// group.
    group_factors: Vec<Vec<Vec<(f64, f64)>>>,
    /// Per spring, its implicit multiplier at the end of the last step: the next step's
    /// start with `warm_start` (zeros otherwise, and after [`Self::set_state`]).
    spring_warm: Vec<f64>,
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
        ReferenceBackend {
            problem: problem.clone(),
            x: model.positions.clone(),
            v: model.velocities.clone(),
            frame: 0,
            group_factors,
            spring_warm: vec![0.0; model.springs.len()],
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

    /// Steps 1 and 2 of a time step at the current state: gravity, explicit springs
    /// (spring-centric for every method but `mss-node`, which gathers per node) or, for
    /// warm-started implicit springs, the last step's multipliers as forces, then
    /// `iterations` times the sweeps ([`Model::constraint_sweeps`]: implicit springs, then
    /// the method's constraints), each group after group (one group for Jacobi and
    /// Chebyshev, the colour groups for Gauss-Seidel; Chebyshev extrapolating each
    /// iteration's forces) and each group followed by the floor's solve, then the global
    /// volume constraints (when solved) and the floor again; finally the floor's last solve.
    pub fn forces(&self) -> Forces {
        let n = self.problem.model.node_count();
        let down = DVec3::new(0.0, -self.problem.params.gravity, 0.0);
        let gravity: Vec<DVec3> = self.problem.model.mass.iter().map(|&m| down * m).collect();
        let springs = match (self.problem.params.springs, self.problem.params.method) {
            (SpringKind::Implicit, _) => self.warm_start_forces(),
            (_, Method::MssNode) => self.spring_forces_gather(),
            _ => self.spring_forces_scatter(),
        };
        // The compliant constraints' multipliers found so far in this step (the warm start's
        // for the springs).
        let mut spring_lambda = self.spring_warm.clone();
        let mut volume_lambda = vec![0.0; self.problem.model.tets.len()];
        let mut total: Vec<DVec3> = (0..n).map(|i| gravity[i] + springs[i]).collect();
        let mut floor = vec![0.0; n];
        // Chebyshev: the weights, and the total and floor forces two iterations back.
        let p = &self.problem.params;
        let weights =
            (p.solver == Solver::Chebyshev).then(|| chebyshev_weights(p.rho, p.iterations));
        let (mut before_total, mut before_floor) = (total.clone(), floor.clone());
        for iteration in 0..self.problem.params.iterations as usize {
            for (sweep, sweep_factors) in self.problem.sweeps.iter().zip(&self.group_factors) {
                for (g, factors) in sweep_factors.iter().enumerate() {
                    let a_scale: Vec<f64> = factors.iter().map(|f| f.0).collect();
                    let members = sweep.groups.group(g);
                    let (springs, tets, m) = (
                        &self.problem.model.springs,
                        &self.problem.model.tets,
                        &self.problem.material,
                    );
                    let (rest, rest_volume, dt) = (
                        &self.problem.model.rest_length,
                        &self.problem.model.rest_volume,
                        self.problem.params.dt,
                    );
                    let sum = match sweep.kind {
                        ConstraintKind::Spring => {
                            let lambda = &mut spring_lambda;
                            self.sweep(members, springs, &total, &a_scale, lambda, |s, [a, b]| {
                                let (c, grad) = spring_constraint(a, b, rest[s]);
                                let (k, kd) = (m.spring_stiffness[s], m.spring_damping[s]);
                                (c, grad, spring_softness(k, kd, dt), kd)
                            })
                        }
                        ConstraintKind::Distance => {
                            let lambda = &mut spring_lambda;
                            self.sweep(members, springs, &total, &a_scale, lambda, |s, [a, b]| {
                                let (c, grad) = distance_constraint(a, b, rest[s]);
                                (c, grad, 0.0, 0.0)
                            })
                        }
                        ConstraintKind::Volume => {
                            let lambda = &mut volume_lambda;
                            self.sweep(members, tets, &total, &a_scale, lambda, |t, p| {
                                let (c, grad) = volume_constraint(p, rest_volume[t]);
                                (c, grad, volume_softness(m.volume_compliance[t], dt), 0.0)
                            })
                        }
                    };
                    let current = weights.as_ref().map(|_| (total.clone(), floor.clone()));
                    for i in 0..n {
                        total[i] += sum[i] * (factors[i].1 * self.problem.params.omega);
                    }
                    if let (Some(w), Some((t, f))) = (&weights, current) {
                        let w = w[iteration];
                        if w != 1.0 {
                            for i in 0..n {
                                total[i] = (total[i] - before_total[i]) * w + before_total[i];
                                floor[i] = (floor[i] - before_floor[i]) * w + before_floor[i];
                            }
                        }
                        (before_total, before_floor) = (t, f);
                    }
                    self.floor_solve(&mut total, &mut floor);
                }
            }
            if let Some(global) = &self.problem.global {
                for object in &global.objects {
                    let f = self.global_volume_forces(global, object, &total);
                    for (&i, f) in global.nodes[object.node_first as usize..].iter().zip(f) {
                        total[i as usize] += f;
                    }
                }
                self.floor_solve(&mut total, &mut floor);
            }
        }
        self.floor_solve(&mut total, &mut floor);
        let constraints = (0..n)
            .map(|i| total[i] - gravity[i] - springs[i] - DVec3::Y * floor[i])
            .collect();
        Forces {
            gravity,
            springs,
            constraints,
            floor,
            spring_multipliers: spring_lambda,
            volume_multipliers: volume_lambda,
        }
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

    /// The forces `-lambda grad_k C_g` of `object`'s global volume constraint against the
    /// total force `f`, one per surface node (in [`GlobalVolume::nodes`] order from the
    /// object's first). The reference point of the face volumes is the object's first
    /// surface node.
    fn global_volume_forces(
        &self,
        global: &GlobalVolume,
        object: &GlobalObject,
        f: &[DVec3],
    ) -> Vec<DVec3> {
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
        let grad: Vec<DVec3> = (0..nodes.len())
            .map(|k| {
                let row = global.node_faces.row(object.node_first as usize + k);
                row.iter()
                    .map(|&e| face_grad[(e as usize - first_face) / 3][e as usize % 3])
                    .sum()
            })
            .collect();
        let (mut a, mut b) = (0.0, 0.0);
        for (&i, &g) in nodes.iter().zip(&grad) {
            let i = i as usize;
            let w = self.problem.model.inv_mass[i];
            implicit_accumulate(
                &mut a,
                &mut b,
                g,
                w,
                1.0,
                self.v[i],
                f[i],
                self.problem.params.dt,
            );
        }
        let p = &self.problem.params;
        let lambda = implicit_multiplier(c, a, b, p.dt, p.constraint_epsilon).unwrap_or(0.0);
        grad.iter().map(|&g| g * -lambda).collect()
    }

    /// Solves every node's floor contact against the current total force `total` (which
    /// includes the floor forces `floor` found so far) and updates both.
    fn floor_solve(&self, total: &mut [DVec3], floor: &mut [f64]) {
        if !self.problem.params.floor {
            return;
        }
        for (i, (f, n)) in total.iter_mut().zip(floor.iter_mut()).enumerate() {
            let w = self.problem.model.inv_mass[i];
            (*f, *n) = floor_solve(*f, *n, self.x[i].y, self.v[i].y, w, self.problem.params.dt);
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

    /// One Jacobi sweep of the constraints `members` (indices into `elements`) against the
    /// force `f`: `constraint(e, positions)` gives constraint `e`'s value, gradients,
    /// softness and damping; returns the per-node sums of `-delta grad C`, `delta` the
    /// compliant multiplier's increment ([`Self::lambda`]). A compliant constraint
    /// (softness > 0) carries its multiplier so far in `lambda[e]`, which grows by
    /// `omega delta`; a hard one neither reads nor changes it.
    fn sweep<const K: usize>(
        &self,
        members: &[u32],
        elements: &[[u32; K]],
        f: &[DVec3],
        a_scale: &[f64],
        lambda: &mut [f64],
        constraint: impl Fn(usize, [DVec3; K]) -> (f64, [DVec3; K], f64, f64),
    ) -> Vec<DVec3> {
        let mut sum = vec![DVec3::ZERO; self.problem.model.node_count()];
        for &e in members {
            let e = e as usize;
            let ids = elements[e].map(|i| i as usize);
            let (c, grad, softness, damping) = constraint(e, ids.map(|i| self.x[i]));
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
        let mut forces = self.forces();
        let f = forces.total();
        if self.problem.params.warm_start {
            std::mem::swap(&mut self.spring_warm, &mut forces.spring_multipliers);
        }
        let p = &self.problem.params;
        let mut bad = None;
        let nodes = self
            .x
            .iter_mut()
            .zip(self.v.iter_mut())
            .zip(f.iter().zip(&self.problem.model.inv_mass));
        for (i, ((x, v), (&f, &w))) in nodes.enumerate() {
            let contact = forces.floor[i] > 0.0;
            (*x, *v) = integrate_node(*x, *v, f, w, p.dt, contact, p.friction);
            if bad.is_none() {
                if !(x.is_finite() && v.is_finite()) {
                    bad = Some((i, Bad::NonFinite));
                } else if v.length() > limit {
                    bad = Some((i, Bad::TooFast(v.length())));
                }
            }
        }
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
