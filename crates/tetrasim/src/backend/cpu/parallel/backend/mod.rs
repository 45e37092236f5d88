//! The `cpu` backend itself: its state in flat single-precision arrays, the step (forces,
//! constraint sweeps, floor, integration) and the [`Backend`] interface. The sweeps' data
//! and group solve are the parent module's.

use super::collide;
use super::iterations::{self, Inputs, Outputs};

mod integrate;
mod iterate;
mod minres;
mod reactions;
use super::*;
use crate::backend::cpu::shared::SharedSlice;
use crate::backend::cpu::team::Team;
use crate::backend::cpu::team_choice::TeamChoice;
use crate::backend::{flatten, restore_coarse, unflatten, Carried, ContactSample, COARSE_KEY};
use crate::collider::{Clamp, Collider, Grab};
use crate::contact::{deepest, Contact};
use glam::DVec3;
use std::sync::Arc;

/// The fast CPU solver (`cpu`).
#[derive(Debug, Clone)]
pub struct ParallelBackend {
    method: Method,
    /// Whether the springs act as explicit forces (else they are solved in the sweeps).
    explicit_springs: bool,
    substeps: u32,
    /// MINRES iterations after the constraint iterations (0: off).
    minres: u32,
    /// MINRES's rows, kept from step to step.
    minres_rows: minres::MinresRows,
    floor: bool,
    k: Coefficients,
    mass: Vec<f32>,
    inv_mass: Vec<f32>,
    springs: Vec<[u32; 2]>,
    rest_length: Vec<f32>,
    /// Per spring: stiffness [N/m] and damping [N s/m] ([`crate::model::ElementMaterial`]).
    spring_stiffness: Vec<f32>,
    spring_damping: Vec<f32>,
    tets: Vec<[u32; 4]>,
    rest_volume: Vec<f32>,
    /// node -> `2 * spring + end` (end 0 is `springs[s][0]`).
    node_spring_ends: Csr,
    /// The constraint sweeps of an iteration, in order (empty for explicit springs-only
    /// methods).
    sweeps: Vec<Sweep>,
    /// The global volume constraints, when solved.
    global: Option<Global>,
    /// The Chebyshev semi-iteration (solver `chebyshev`).
    chebyshev: Option<Chebyshev>,
    /// Anderson acceleration's arrays (`anderson > 0` with constraint iterations).
    anderson: Option<super::anderson::Anderson>,
    /// The threads that run the step, and how many of them run the constraint iterations
    /// (chosen by timing the first frames).
    team: TeamChoice,
    /// The floor's normal force on each node in the current step [N] (`>= 0`).
    floor_force: Vec<f32>,
    /// The problem, when runs of it measure contact ([`Problem::measures_contact`]), and the
    /// nodes a collider pushed in the last step.
    measured: Option<Problem>,
    pushed: u32,
    /// Body contact with its problem (for the model and parameters its sweep reads), when
    /// two surfaces can meet, and the step's contacts with their multipliers.
    bodies: Option<Problem>,
    body_contacts: Vec<(Contact, f64)>,
    /// The moving pins and the initial positions they move from (none without them).
    clamps: Option<(Vec<Clamp>, Vec<DVec3>)>,
    /// The kinematic colliders (shared with the problem).
    colliders: Arc<[Collider]>,
    /// Each node's [`collider::clearance`] in the current step (empty without colliders).
    clearance: Vec<f64>,
    /// The grabs, the initial positions they hold from, and each node's attachment in the
    /// current step (all empty without grabs).
    grabs: Vec<Grab>,
    rest: Vec<DVec3>,
    attached: Vec<Option<collider::Attachment>>,
    /// The colliders' force on each node in the current step [N] (zeros without them).
    contact: Vec<Vec3A>,
    /// Time steps taken since creation (the colliders' clock; [`Self::set_state`] keeps
    /// it), and the step in f64 [s].
    steps: u64,
    dt: f64,
    x: Vec<Vec3A>,
    v: Vec<Vec3A>,
    /// Total force of the current step [N].
    f: Vec<Vec3A>,
    /// Split contact: each node's velocity from the step's velocity solve, which the step
    /// keeps instead of the full solve's (empty without split contact).
    split_v: Vec<Vec3A>,
    /// Per explicit spring: force on the spring's end 0 (end 1 gets its negation); for
    /// warm-started implicit springs, the warm start's force.
    spring_out: Vec<Vec3A>,
    /// With warm-started implicit springs: per spring, its multiplier at the end of the
    /// last step (empty otherwise).
    spring_warm: Vec<f32>,
    /// Per spring or distance constraint, in group order: force on the spring's end 0
    /// (end 1 gets its negation).
    pair_out: Vec<Vec3A>,
    /// Per volume constraint, in group order: force on each corner.
    tet_out: Vec<[Vec3A; 4]>,
    /// Finite elements: per node, in group order, its step's force increment.
    node_out: Vec<Vec3A>,
    /// Finite elements: each step starts where the last one's fall takes the nodes.
    elastic_warm: bool,
    /// What the supports did in the last step, for the forces out.
    supports: reactions::Supports,
    /// Finite elements: the conjugate gradients' vectors (empty otherwise).
    newton: super::newton::NewtonVectors,
    frame: u32,
    /// Divergence speed limit [m/s] ([`crate::stability::speed_limit`]).
    speed_limit: f32,
    /// The pass of each stage of the step's schedule.
    stages: Vec<PassKind>,
    /// One time step's dispatches ([`Schedule::step`]).
    dispatches: Vec<Dispatch>,
    /// The likely cause printed on divergence.
    likely: String,
}

impl ParallelBackend {
    /// A solver at the model's initial positions and velocities. Fails on invalid parameters.
    pub fn new(model: &Model, params: &SimParams) -> Result<Self> {
        Ok(Self::from_problem(&Problem::new(model, params)?))
    }

    /// A solver for a prepared problem (rounded to f32), at its model's initial positions
    /// and velocities.
    pub fn from_problem(problem: &Problem) -> Self {
        let (model, params) = (&problem.model, &problem.params);
        let n = model.node_count();
        let ns = &model.node_springs;
        let mut ends = Csr {
            offsets: ns.offsets.clone(),
            items: Vec::with_capacity(ns.items.len()),
        };
        for i in 0..n {
            for &s in ns.row(i) {
                let end = u32::from(model.springs[s as usize][0] as usize != i);
                ends.items.push(2 * s + end);
            }
        }
        let to32 = |v: &[f64]| v.iter().map(|&a| a as f32).collect::<Vec<f32>>();
        let material = &problem.material;
        let sweeps: Vec<Sweep> = (problem.sweeps.iter().cloned())
            .zip(Family::of_sweeps(problem))
            .map(|(sweep, family)| Sweep::new(model, params, sweep, family))
            .collect();
        let has = |kind: ConstraintKind| sweeps.iter().any(|s| s.kind == kind);
        let explicit_springs = params.springs == SpringKind::Explicit;
        let schedule = Schedule::of(problem, false);
        let gravity = params.gravity.as_vec3a();
        ParallelBackend {
            stages: schedule.stages.iter().map(|stage| stage.kind).collect(),
            dispatches: schedule.step(),
            method: params.method,
            explicit_springs,
            substeps: params.substeps,
            minres: params.minres,
            minres_rows: Default::default(),
            floor: params.floor,
            k: Coefficients {
                dt: params.dt as f32,
                iterations: params.iterations,
                omega: params.omega as f32,
                friction: params.friction as f32,
                epsilon: params.constraint_epsilon as f32,
                inversion_floor: params.inversion_floor as f32,
                gravity,
                solve: Solve::Full,
            },
            mass: to32(&model.mass),
            inv_mass: to32(&model.inv_mass),
            springs: model.springs.clone(),
            rest_length: to32(&model.rest_length),
            spring_stiffness: to32(&material.spring_stiffness),
            spring_damping: to32(&material.spring_damping),
            tets: model.tets.clone(),
            rest_volume: to32(&model.rest_volume),
            node_spring_ends: ends,
            global: (problem.global.clone()).map(|data| Global::new(model, data)),
            chebyshev: (params.solver == Solver::Chebyshev).then(|| Chebyshev {
                weights: chebyshev_weights(params.rho, params.iterations)
                    .into_iter()
                    .map(|w| w as f32)
                    .collect(),
                before_f: vec![Vec3A::ZERO; n],
                before_n: vec![0.0; n],
            }),
            anderson: (params.anderson > 0 && !sweeps.is_empty()).then(|| {
                let volumes = schedule.anderson_volumes;
                let constraints = (sweeps.iter())
                    .filter(|s| super::anderson::mixes(s.kind, volumes))
                    .map(|s| s.multipliers.len())
                    .sum();
                super::anderson::Anderson::new(params.anderson, n, constraints, volumes)
            }),
            team: TeamChoice::for_work(n, mean_group_size(&sweeps)),
            floor_force: vec![0.0; n],
            bodies: problem.bodies.is_some().then(|| problem.clone()),
            measured: problem.measures_contact().then(|| problem.clone()),
            pushed: 0,
            body_contacts: Vec::new(),
            clamps: (!model.clamps.is_empty())
                .then(|| (model.clamps.clone(), model.positions.clone())),
            colliders: model.colliders.clone().into(),
            contact: vec![Vec3A::ZERO; n],
            clearance: Vec::new(),
            grabs: model.grabs.clone(),
            rest: match model.grabs.is_empty() {
                true => Vec::new(),
                false => model.positions.clone(),
            },
            attached: Vec::new(),
            steps: 0,
            dt: params.dt,
            x: model
                .positions
                .iter()
                .map(|&p| Vec3A::from_dvec3(p))
                .collect(),
            v: model
                .velocities
                .iter()
                .map(|&v| Vec3A::from_dvec3(v))
                .collect(),
            // F starts as m g, which `integrate` leaves: with implicit springs and no warm
            // start, no stage adds to it before the iterations.
            f: model.mass.iter().map(|&m| gravity * m as f32).collect(),
            split_v: match params.contact {
                ContactMode::Split => vec![Vec3A::ZERO; n],
                ContactMode::Combined => Vec::new(),
            },
            spring_out: if (explicit_springs || params.warm_start)
                && params.method != Method::MssNode
            {
                vec![Vec3A::ZERO; model.springs.len()]
            } else {
                Vec::new()
            },
            spring_warm: if params.warm_start {
                vec![0.0; model.springs.len()]
            } else {
                Vec::new()
            },
            pair_out: if has(ConstraintKind::Spring) || has(ConstraintKind::Distance) {
                vec![Vec3A::ZERO; model.springs.len()]
            } else {
                Vec::new()
            },
            node_out: match has(ConstraintKind::Elastic) {
                true => vec![Vec3A::ZERO; model.node_count()],
                false => Vec::new(),
            },
            elastic_warm: has(ConstraintKind::Elastic),
            supports: reactions::Supports::of(model, params.floor),
            newton: match has(ConstraintKind::Elastic) {
                true => super::newton::NewtonVectors::new(
                    model.node_count(),
                    model.tets.len(),
                    (sweeps.iter())
                        .find_map(|s| match &s.family {
                            Family::Elastic(nodes) => Some(nodes.aggregates.len()),
                            _ => None,
                        })
                        .unwrap_or(0),
                ),
                false => Default::default(),
            },
            tet_out: if has(ConstraintKind::Volume) {
                vec![[Vec3A::ZERO; 4]; model.tets.len()]
            } else {
                Vec::new()
            },
            sweeps,
            frame: 0,
            speed_limit: problem.speed_limit as f32,
            likely: problem.likely_cause.clone(),
        }
    }

    /// The same backend on a team of `sizes[0]` threads choosing among the given thread
    /// counts for its iterations, whatever the work (tests; one size is a fixed team).
    #[cfg(test)]
    pub(super) fn with_team_sizes(mut self, sizes: &[usize]) -> Self {
        self.team = TeamChoice::with_sizes(sizes);
        self
    }

    /// Replaces positions and velocities (rounded to f32).
    pub fn set_state(&mut self, state: &State) -> Result<()> {
        check_state(self.x.len(), state)?;
        self.x = state
            .positions
            .iter()
            .map(|&p| Vec3A::from_dvec3(p))
            .collect();
        self.v = state
            .velocities
            .iter()
            .map(|&p| Vec3A::from_dvec3(p))
            .collect();
        self.spring_warm.fill(0.0);
        if self.elastic_warm {
            let (g, mass) = (self.k.gravity, &self.mass);
            (self.f.iter_mut().zip(mass)).for_each(|(f, &m)| *f = g * m);
        }
        Ok(())
    }

    /// Stage `spring_scatter`, `spring_gather` or `spring_warm_start`: `F = m g + spring
    /// forces`, each spring with its own stiffness and damping (with warm-started implicit
    /// springs, their last multipliers' forces `-lambda grad C`). `mss-node` evaluates
    /// each spring at both ends inside one node-centric gather; every other method
    /// evaluates each spring once and gathers the results.
    fn spring_pass(&mut self) {
        let (x, v, k) = (&self.x, &self.v, self.k);
        let (springs, rest, mass) = (&self.springs, &self.rest_length, &self.mass);
        let (ks, kd) = (&self.spring_stiffness, &self.spring_damping);
        let ends = &self.node_spring_ends;
        let warm = &self.spring_warm;
        if !self.explicit_springs && !warm.is_empty() {
            self.spring_out
                .par_iter_mut()
                .enumerate()
                .with_min_len(CHUNK)
                .for_each(|(s, out)| {
                    let [i, j] = springs[s].map(|a| a as usize);
                    let (_, grad) = spring_constraint(x[i], x[j], rest[s]);
                    *out = grad[0] * -warm[s];
                });
        }
        if self.method == Method::MssNode {
            self.f
                .par_iter_mut()
                .enumerate()
                .with_min_len(CHUNK)
                .for_each(|(i, f)| {
                    let mut sum = k.gravity * mass[i];
                    for &e in ends.row(i) {
                        let s = (e >> 1) as usize;
                        let j = springs[s][1 - (e & 1) as usize] as usize;
                        sum += spring_force(x[i], x[j], v[i], v[j], rest[s], ks[s], kd[s]);
                    }
                    *f = sum;
                });
            return;
        }
        if self.explicit_springs {
            self.spring_out
                .par_iter_mut()
                .enumerate()
                .with_min_len(CHUNK)
                .for_each(|(s, out)| {
                    let [i, j] = springs[s].map(|a| a as usize);
                    *out = spring_force(x[i], x[j], v[i], v[j], rest[s], ks[s], kd[s]);
                });
        }
        let out = &self.spring_out;
        self.f
            .par_iter_mut()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(i, f)| {
                *f = k.gravity * mass[i] + gather::<2, _>(out)(ends.row(i));
            });
    }

    /// One time step (physics.md steps 1-3): the schedule's dispatches in order, those of
    /// the constraint iterations run by `team` (the backend's, taken out for the step).
    fn step(&mut self, team: &Team) -> Option<(usize, Bad)> {
        let colliders = Arc::clone(&self.colliders);
        let at = collider::at_step(&colliders, self.steps, self.dt);
        if !self.grabs.is_empty() {
            let t = self.steps as f64 * self.dt;
            self.attached = collider::attachments(&self.grabs, &self.rest, t, self.dt);
        }
        if !at.is_empty() || !self.grabs.is_empty() {
            let x = &self.x;
            self.clearance = (0..x.len())
                .into_par_iter()
                .with_min_len(CHUNK)
                .map(|i| collider::clearance(&at, x[i].to_dvec3()))
                .collect();
        }
        if let Some((clamps, rest)) = &self.clamps {
            let (x, v) = (&self.x, &mut self.v);
            collider::drive(
                clamps,
                rest,
                self.steps,
                self.dt,
                |i| x[i].to_dvec3(),
                |i, u| v[i] = Vec3A::from_dvec3(u),
            );
        }
        self.steps += 1;
        let mut k = 0;
        while k < self.dispatches.len() {
            let dispatch = self.dispatches[k];
            if dispatch.iteration.is_some() {
                let end = (k..self.dispatches.len())
                    .find(|&e| self.dispatches[e].iteration.is_none())
                    .unwrap_or(self.dispatches.len());
                self.k.solve = dispatch.solve;
                self.iterations(team, k..end, &at);
                k = end;
                continue;
            }
            match self.stages[dispatch.stage] {
                PassKind::SpringScatter | PassKind::SpringGather | PassKind::SpringWarmStart => {
                    self.spring_pass()
                }
                PassKind::ContactFind => {
                    if let Some(problem) = &self.bodies {
                        let bodies = problem.bodies.as_ref().expect("body contact");
                        let x: Vec<DVec3> = self.x.iter().map(|p| p.to_dvec3()).collect();
                        let v: Vec<DVec3> = self.v.iter().map(|p| p.to_dvec3()).collect();
                        let found = bodies.find(&problem.model, &x, &v, self.dt);
                        self.body_contacts = found.into_iter().map(|c| (c, 0.0)).collect();
                    }
                }
                // The GPU's clamp drive (done above) and broad phase (`contact_find` hashes).
                PassKind::ClampDrive
                | PassKind::ContactCount
                | PassKind::ContactScan
                | PassKind::ContactFill => {}
                // The GPU's frame measure of contact (`contact_sample` takes it).
                PassKind::ContactMeasure => {}
                PassKind::GlobalVolumePrepare => {
                    if let Some(global) = &mut self.global {
                        global.prepare(&self.x);
                    }
                }
                PassKind::SplitVelocity => {
                    if let Some(bad) = self.integrate_pass(&at, Solve::Velocity) {
                        return Some(bad);
                    }
                }
                PassKind::Integrate => return self.integrate_pass(&at, Solve::Full),
                _ => {}
            }
            k += 1;
        }
        None
    }

    /// A frame's substeps on `team` (running on its threads).
    fn frame_steps(&mut self, team: &Team) -> Result<()> {
        for substep in 0..self.substeps {
            if let Some((node, bad)) = self.step(team) {
                return Err(diverged(
                    self.frame,
                    substep,
                    self.method,
                    node as u32,
                    bad,
                    f64::from(self.speed_limit),
                    &self.likely,
                ));
            }
        }
        self.frame += 1;
        Ok(())
    }

    /// The volume figures at the current positions.
    fn volume_sample(&self) -> VolumeSample {
        let x = &self.x;
        let (volume, inverted, local_error) = self
            .tets
            .par_iter()
            .zip(self.rest_volume.par_iter())
            .with_min_len(CHUNK)
            .map(|(t, &rest)| {
                let v = tet_volume(t.map(|i| x[i as usize]));
                (
                    f64::from(v),
                    u32::from(v <= 0.0),
                    f64::from((v - rest).abs()),
                )
            })
            .reduce(|| (0.0, 0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2));
        VolumeSample {
            volume,
            inverted,
            local_error,
            contact: self.contact_sample(),
        }
    }

    /// The frame's contact measures, when the problem takes them.
    fn contact_sample(&self) -> Option<ContactSample> {
        let problem = self.measured.as_ref()?;
        let x = &self.x;
        let bodies = &self.body_contacts;
        let colliders = &problem.model.colliders;
        Some(ContactSample {
            collider_nodes: self.pushed,
            body_contacts: bodies.iter().filter(|(_, l)| *l < 0.0).count() as u32,
            deepest_m: deepest(
                colliders,
                self.steps,
                self.dt,
                bodies,
                |i| x[i].to_dvec3(),
                x.len(),
            ),
        })
    }
}

/// The mean number of constraints in a group, over the sweeps' groups (0: no sweeps).
fn mean_group_size(sweeps: &[Sweep]) -> usize {
    let groups: usize = sweeps.iter().map(Sweep::len).sum();
    let constraints: usize = sweeps.iter().map(|s| s.members.items.len()).sum();
    constraints.checked_div(groups).unwrap_or(0)
}

impl Backend for ParallelBackend {
    fn name(&self) -> &'static str {
        "cpu"
    }

    fn step_frame(&mut self) -> Result<()> {
        // Taken out for the frame: the step borrows the rest of `self` mutably.
        let mut choice = std::mem::take(&mut self.team);
        let start = std::time::Instant::now();
        let team = choice.team();
        let result = team.install(|| self.frame_steps(team));
        choice.record(start.elapsed());
        self.team = choice;
        result
    }

    fn volume(&mut self) -> Result<VolumeSample> {
        Ok(self.team.team().install(|| self.volume_sample()))
    }

    fn reactions(&mut self) -> Result<Option<crate::backend::Reactions>> {
        Ok(Some(self.reactions_now()))
    }

    fn likely_cause(&self) -> &str {
        &self.likely
    }

    fn state(&mut self) -> Result<State> {
        Ok(State {
            positions: self.x.iter().map(|p| p.to_dvec3()).collect(),
            velocities: self.v.iter().map(|p| p.to_dvec3()).collect(),
        })
    }

    fn set_state(&mut self, state: &State) -> Result<()> {
        ParallelBackend::set_state(self, state)
    }

    /// The frame and step counters, the step's forces (the finite elements start the next
    /// step from them), the warm-started springs' multipliers and the finite elements'
    /// coarse level.
    fn carried(&mut self) -> Result<Carried> {
        let forces: Vec<DVec3> = self.f.iter().map(|f| f.as_dvec3()).collect();
        let mut arrays = vec![("forces".to_string(), flatten(&forces))];
        if !self.spring_warm.is_empty() {
            let values = self.spring_warm.iter().map(|&l| f64::from(l)).collect();
            arrays.push(("spring_multipliers".to_string(), values));
        }
        if let Some(coarse) = self.newton.coarse() {
            arrays.push((COARSE_KEY.to_string(), coarse.to_values()));
        }
        Ok(Carried {
            frames: self.frame,
            steps: self.steps,
            arrays,
        })
    }

    fn restore(&mut self, state: &State, carried: &Carried) -> Result<()> {
        ParallelBackend::set_state(self, state)?;
        let forces = carried.array("forces", 3 * self.f.len())?;
        self.f = unflatten(forces).iter().map(|f| f.as_vec3a()).collect();
        if !self.spring_warm.is_empty() {
            let values = carried.array("spring_multipliers", self.spring_warm.len())?;
            self.spring_warm = values.iter().map(|&l| l as f32).collect();
        }
        let coarse = restore_coarse(carried, self.newton.aggregates())?;
        self.newton.set_coarse(coarse);
        (self.frame, self.steps) = (carried.frames, carried.steps);
        Ok(())
    }
}
