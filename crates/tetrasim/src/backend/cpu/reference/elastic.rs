//! `cpu-ref`'s finite elements: each step one Newton step on the stable Neo-Hookean energy,
//! its linear system solved by conjugate gradients with a two-level preconditioner
//! (block-Jacobi and rigid modes of aggregates; [`crate::physics::CoarseSpace`]), one
//! iteration per dispatch of the `elastic` pass (docs/PHYSICS.md, "Finite elements").

use glam::DVec3;

use super::step_forces::StepForces;
use super::ReferenceBackend;
use crate::collider;
use crate::physics::{
    correction_length, elastic_linearise, elastic_product, elastic_product_strain,
    elastic_relinearise, end_position, held_increment, held_mass, rebuilds, touching,
    ElasticLinear, RigidPart, Sym3,
};
use crate::schedule::family::{backtrack, ElasticNodes, Family};
use crate::schedule::GroupAt;

/// The conjugate gradients' state within a step: the positions the system is linearised at
/// (where the step's first iteration found the nodes ending), the residual `r`, the
/// preconditioned residual `z`, the search direction `p`, the inverse diagonal blocks and
/// `r . z`.
#[derive(Debug, Clone, Default)]
pub(super) struct NewtonCg {
    at: Vec<DVec3>,
    /// Where inertia and gravity alone would take each node (the step's `y`), and the
    /// displacement the iterations have added to `at` so far.
    y: Vec<DVec3>,
    dx: Vec<DVec3>,
    /// The step's incremental potential at `at + dx` ([`ReferenceBackend::potential`]),
    /// once a step has needed it.
    potential: Option<f64>,
    /// Per tet: its stiffness at `at`.
    linear: Vec<ElasticLinear<DVec3>>,
    r: Vec<DVec3>,
    z: Vec<DVec3>,
    p: Vec<DVec3>,
    inverse: Vec<Sym3<f64>>,
    /// Per node: the stiffening of the contact that holds it at the linearisation (zero:
    /// none; [`ElasticNodes::newton_row`]).
    held: Vec<DVec3>,
    /// Per node: in contact at the latest linearisation (left out of the coarse correction).
    touching: Vec<bool>,
    rz: f64,
    /// Converged, or the direction met non-positive curvature: no further increments.
    done: bool,
    /// The last step went beyond the linearisation's trust: the next iteration begins a
    /// new Newton step where the nodes now end.
    relinearise: bool,
}

impl ReferenceBackend {
    /// Iteration `iteration` of the finite elements' conjugate gradients on group `at` (all
    /// nodes), against the step's forces: the per-node force increments `m/dt^2 alpha p`.
    /// The first iteration linearises the step's equation where the nodes end so far
    /// ([`crate::schedule::family::ElasticNodes::newton_row`]). The last iteration also
    /// removes the rigid part of each free object's elastic forces (what the unconverged
    /// residual leaves; [`RigidPart`]), so that they conserve momentum: whole on a body
    /// nothing holds, as far as it lowers the step's model on one a contact holds
    /// ([`ReferenceBackend::correction_length`]).
    pub(super) fn elastic_group(
        &self,
        at: GroupAt,
        iteration: u32,
        step: &mut StepForces,
    ) -> Vec<DVec3> {
        let mut sum = self.conjugate_gradients(at, iteration, step);
        if iteration + 1 == self.problem.params.iterations {
            if let Family::Elastic(nodes) = &self.families[at.sweep] {
                let moved = |i: usize| held_mass(nodes.mass[i], step.newton.held[i]);
                for object in &nodes.free_objects {
                    let elastic = |i: usize| step.elastic(i) + sum[i];
                    let part =
                        RigidPart::of(object.clone().map(|i| (self.x[i], moved(i), elastic(i))));
                    let held = object.clone().any(|i| step.newton.held[i] != DVec3::ZERO);
                    let length = if held {
                        self.correction_length(nodes, step, object.clone(), &part)
                    } else {
                        1.0
                    };
                    for i in object.clone() {
                        sum[i] -= part.force(self.x[i], moved(i)) * length;
                    }
                }
            }
        }
        sum
    }

    /// The length of the rigid-part correction `part` on `object`, a body a contact holds:
    /// the correction's moves taken as one more direction of the step's Newton system, at
    /// the length that minimises its quadratic model, `r . d / d . A d`, in [0, 1].
    fn correction_length(
        &self,
        nodes: &ElasticNodes<f64>,
        step: &StepForces,
        object: std::ops::Range<usize>,
        part: &RigidPart,
    ) -> f64 {
        let (model, dt) = (&self.problem.model, self.problem.params.dt);
        let (w, tets, cg) = (&model.inv_mass, &model.tets, &step.newton);
        let n = model.node_count();
        let mut d = vec![DVec3::ZERO; n];
        for i in object.clone() {
            let m = held_mass(nodes.mass[i], cg.held[i]);
            d[i] = -part.force(self.x[i], m) * (w[i] * dt * dt);
        }
        let corners: Vec<[DVec3; 4]> = (tets.iter().zip(&nodes.tets).zip(&cg.linear))
            .map(|((tet, t), linear)| elastic_product(t, linear, tet.map(|k| d[k as usize])))
            .collect();
        let (mut gain, mut curvature) = (0.0, 0.0);
        for i in object {
            let corner = |item: usize| corners[item / 4][item % 4];
            let q = nodes.product(i, w[i], dt, d[i], cg.held[i], corner);
            gain += cg.r[i].dot(d[i]);
            curvature += d[i].dot(q);
        }
        correction_length(gain, curvature)
    }

    /// One iteration of the conjugate gradients: the force increments.
    fn conjugate_gradients(
        &self,
        at: GroupAt,
        iteration: u32,
        step: &mut StepForces,
    ) -> Vec<DVec3> {
        let n = self.problem.model.node_count();
        let mut sum = vec![DVec3::ZERO; n];
        let Family::Elastic(nodes) = &self.families[at.sweep] else {
            return sum;
        };
        let (model, dt) = (&self.problem.model, self.problem.params.dt);
        let (w, tets) = (&model.inv_mass, &model.tets);
        let members = self.problem.sweeps[at.sweep].groups.group(at.group);
        if iteration == 0 || step.newton.relinearise {
            // The contacts as the forces so far leave them, and the nodes they hold.
            self.contact_solve(step);
            let phi: Vec<DVec3> = (0..n).map(|i| step.elastic(i)).collect();
            let (total, cg) = (&step.total, &mut step.newton);
            cg.at = (0..n)
                .map(|k| end_position(self.x[k], self.v[k], total[k], w[k], dt))
                .collect();
            cg.y = (0..n)
                .map(|k| cg.at[k] - phi[k] * (w[k] * dt * dt))
                .collect();
            cg.dx = vec![DVec3::ZERO; n];
            cg.potential = None;
            // The step's first linearisation takes every tet's stiffness; a later one keeps
            // those of the tets that barely moved since.
            cg.linear = (tets.iter().zip(&nodes.tets).enumerate())
                .map(|(k, (tet, t))| {
                    let p = tet.map(|k| cg.at[k as usize]);
                    match iteration {
                        0 => elastic_linearise(t, p),
                        _ => elastic_relinearise(t, p, &cg.linear[k]),
                    }
                })
                .collect();
            let rates: Vec<[DVec3; 4]> = (0..tets.len())
                .map(|t| {
                    let (start, end) = (|k| self.x[k], |k| cg.at[k]);
                    nodes.rate_corners(t, tets[t], &cg.linear[t], dt, start, end)
                })
                .collect();
            cg.r = vec![DVec3::ZERO; n];
            cg.inverse = vec![[0.0; 6]; n];
            cg.held = vec![DVec3::ZERO; n];
            cg.touching = vec![false; n];
            let colliders = collider::at_step(&model.colliders, self.steps, dt);
            for &i in members {
                let i = i as usize;
                let floor = self.problem.params.floor.then_some(step.floor[i] > 0.0);
                let pushed = step.contacts[i].force;
                let normal =
                    collider::held_normal(floor, pushed, cg.at[i], nodes.reach[i], &colliders);
                let (end, rate) = (|k| cg.at[k], |item: usize| rates[item / 4][item % 4]);
                (cg.r[i], cg.inverse[i], cg.held[i]) =
                    nodes.newton_row(i, w[i], dt, phi[i], normal, tets, end, rate);
                cg.touching[i] = touching(floor, pushed, cg.held[i]);
            }
            if iteration == 0 && rebuilds(self.steps, self.coarse.borrow().is_built()) {
                // The coarse level, every `COARSE_REBUILD_STEPS` steps.
                let mut coarse = nodes.coarse_space(&cg.at);
                let n = coarse.unknowns();
                let mut columns = vec![0.0; n * n];
                for (a, columns) in columns.chunks_mut(6 * n).enumerate() {
                    let (at, linear, held) = (&cg.at, &cg.linear, &cg.held);
                    nodes.coarse_columns(&coarse, a, tets, at, linear, held, dt, columns);
                }
                coarse.assemble(&columns);
                *self.coarse.borrow_mut() = coarse;
            }
            let coarse = self.coarse.borrow();
            cg.z = nodes.precondition(&coarse, &cg.at, &cg.r, &cg.inverse, &cg.touching);
            cg.p.clone_from(&cg.z);
            cg.rz = dot(&cg.r, &cg.z);
            cg.done = !positive(cg.rz);
            cg.relinearise = false;
        }
        let cg = &mut step.newton;
        if cg.done {
            return sum;
        }
        let (corners, strains): (Vec<[DVec3; 4]>, Vec<f64>) = (tets
            .iter()
            .zip(&nodes.tets)
            .zip(&cg.linear))
        .map(|((tet, t), linear)| elastic_product_strain(t, linear, tet.map(|k| cg.p[k as usize])))
        .unzip();
        let mut q = vec![DVec3::ZERO; n];
        for &i in members {
            let i = i as usize;
            let corner = |item: usize| corners[item / 4][item % 4];
            q[i] = nodes.product(i, w[i], dt, cg.p[i], cg.held[i], corner);
        }
        let curvature = dot(&cg.p, &q);
        if !positive(curvature) {
            cg.done = true;
            return sum;
        }
        // Backtracking: a step that changes some strain beyond the linearisation's trust
        // and raises the incremental potential (a large deformation the linearisation
        // misjudges) is halved until it lowers it or is trusted; such a step is followed by
        // a new Newton step, linearised where the nodes then end, unless the potential fell
        // as the model said and no node the contacts left free ends inside one.
        let strain = strains.into_iter().fold(0.0, f64::max);
        let (at, dx, p) = (&cg.at, &cg.dx, &cg.p);
        let stepped = backtrack(cg.rz / curvature, strain, curvature, cg.potential, |a| {
            let moves: Vec<DVec3> = (0..n).map(|k| dx[k] + p[k] * a).collect();
            let (model, dt) = (&self.problem.model, self.problem.params.dt);
            nodes.potential(
                &model.tets,
                &model.inv_mass,
                dt,
                at,
                &moves,
                &cg.y,
                &cg.held,
            )
        });
        (cg.potential, cg.relinearise) = (stepped.potential, stepped.relinearise);
        let Some(alpha) = stepped.alpha else {
            cg.done = true;
            return sum;
        };
        if stepped.checked && !cg.relinearise {
            let colliders = collider::at_step(&model.colliders, self.steps, dt);
            let floor = self.problem.params.floor;
            cg.relinearise = (0..n).any(|k| {
                let end = cg.at[k] + cg.dx[k] + cg.p[k] * alpha;
                collider::enters_unheld(w[k] > 0.0, cg.held[k], floor, &colliders, end)
            });
        }
        for &i in members {
            let i = i as usize;
            cg.dx[i] += cg.p[i] * alpha;
            let (h, d) = (cg.held[i], cg.p[i] * alpha);
            let pushed = DVec3::Y * step.floor[i] + step.contacts[i].force;
            sum[i] = held_increment(nodes.increment(i, dt, h, cg.p[i], alpha), h, d, pushed);
            cg.r[i] -= q[i] * alpha;
        }
        let coarse = self.coarse.borrow();
        cg.z = nodes.precondition(&coarse, &cg.at, &cg.r, &cg.inverse, &cg.touching);
        let rz = dot(&cg.r, &cg.z);
        let beta = rz / cg.rz;
        for (p, z) in cg.p.iter_mut().zip(&cg.z) {
            *p = *z + *p * beta;
        }
        cg.rz = rz;
        cg.done = !positive(rz);
        sum
    }
}

/// `sum_i a_i . b_i`, in node order.
fn dot(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a.dot(*b)).sum()
}

/// Whether `x` is a positive number (not NaN): the conjugate gradients go on only then.
fn positive(x: f64) -> bool {
    x > 0.0
}
