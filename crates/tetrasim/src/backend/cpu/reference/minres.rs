//! MINRES after the sweeps on `cpu-ref` ([`crate::backend::cpu::minres`], on a team of one):
//! the step's constraint rows at the forces the sweeps left, solved, and their increments
//! applied.

use glam::DVec3;

use super::{ReferenceBackend, StepForces};
use crate::backend::cpu::minres::Minres;
use crate::backend::cpu::team::Team;
use crate::physics::{compliant_residual, implicit_accumulate, Mobility, StepRows};
use crate::schedule::family::{ConstraintFamily, Family};

/// Which multipliers a row's increment adds to.
#[derive(Clone, Copy)]
enum Slot {
    Spring(usize),
    Volume(usize),
    /// Hard constraints and the global volume constraints keep none.
    None,
}

impl ReferenceBackend {
    /// `params.minres` iterations of MINRES on every constraint of the step (each kind
    /// once, then the global volume constraints) at the forces so far, the nodes the floor,
    /// the colliders and the grabs push held; the increments added to the forces and the
    /// compliant multipliers, then the floor and colliders solved again.
    pub(super) fn minres_solve(&self, step: &mut StepForces) {
        let iterations = self.problem.params.minres;
        if iterations == 0 {
            return;
        }
        let mut rows = StepRows::new();
        let mut slots = Vec::new();
        // Each kind once, in the sweeps' order (implicit springs first), as every backend
        // orders its rows (crate::schedule::MinresRowKinds).
        let mut done = Vec::new();
        for family in &self.families {
            let kind = std::mem::discriminant(family);
            if done.contains(&kind) {
                continue;
            }
            done.push(kind);
            match family {
                Family::Springs(f) => self.rows_of(f, step, &mut rows, &mut slots),
                Family::Distances(f) => self.rows_of(f, step, &mut rows, &mut slots),
                Family::Volumes(f) => self.rows_of(f, step, &mut rows, &mut slots),
                // Validation refuses MINRES for the finite elements.
                Family::Elastic(_) => {}
            }
        }
        self.global_rows(step, &mut rows, &mut slots);
        let mut minres = Minres::default();
        minres.solve(&Team::default(), &rows, &self.mobility(step), iterations);
        let delta = minres.increments();
        for (i, total) in step.total.iter_mut().enumerate() {
            *total -= minres.node_force(i);
        }
        for (&d, slot) in delta.iter().zip(&slots) {
            match *slot {
                Slot::Spring(e) => step.spring_lambda[e] += d,
                Slot::Volume(e) => step.volume_lambda[e] += d,
                Slot::None => {}
            }
        }
        self.contact_solve(step);
    }

    /// Each node's mobility ([`Mobility::held_by`] the floor, colliders and grabs).
    fn mobility(&self, step: &StepForces) -> Vec<Mobility> {
        let model = &self.problem.model;
        (0..model.node_count())
            .map(|i| {
                let grabbed = step.attached.get(i).is_some_and(|a| a.is_some());
                let (floor, collider) = (step.floor[i] > 0.0, step.contacts[i].force);
                Mobility::held_by(model.inv_mass[i], floor, collider, grabbed)
            })
            .collect()
    }

    /// The rows of every constraint of `family` at the step's forces so far.
    fn rows_of<const K: usize, F: ConstraintFamily<f64, K>>(
        &self,
        family: &F,
        step: &StepForces,
        rows: &mut StepRows,
        slots: &mut Vec<Slot>,
    ) {
        let elements = F::elements(&self.problem.model);
        for (e, nodes) in elements.iter().enumerate() {
            let ids = nodes.map(|i| i as usize);
            let (c, grad, softness, damping) = family.evaluate(e, ids.map(|i| self.x[i]));
            let (c, so_far, slot) = match (softness > 0.0, F::KIND) {
                (false, _) => (step.solve.hard(c), 0.0, Slot::None),
                (true, crate::model::ConstraintKind::Volume) => {
                    (c, softness * step.volume_lambda[e], Slot::Volume(e))
                }
                (true, _) => (c, softness * step.spring_lambda[e], Slot::Spring(e)),
            };
            let b = self.numerator_sum(ids.iter().copied().zip(grad), step) - so_far;
            let residual = compliant_residual(c, b, self.problem.params.dt, softness, damping);
            rows.push(nodes, &grad, softness, residual);
            slots.push(slot);
        }
    }

    /// The rows of the global volume constraints (hard) at the step's forces so far.
    fn global_rows(&self, step: &StepForces, rows: &mut StepRows, slots: &mut Vec<Slot>) {
        let Some(global) = &self.problem.global else {
            return;
        };
        for (object, (c, grad, _)) in global.objects.iter().zip(&step.global) {
            let nodes = &global.nodes[object.node_first as usize..][..object.node_count as usize];
            let entries = nodes.iter().map(|&i| i as usize).zip(grad.iter().copied());
            let b = self.numerator_sum(entries, step);
            let c = step.solve.hard(*c);
            let residual = compliant_residual(c, b, self.problem.params.dt, 0.0, 0.0);
            rows.push(nodes, grad, 0.0, residual);
            slots.push(Slot::None);
        }
    }

    /// `sum_k grad_k . (v_k / dt + w_k F_k)` of a row's entries at the step's forces.
    fn numerator_sum(
        &self,
        entries: impl Iterator<Item = (usize, DVec3)>,
        step: &StepForces,
    ) -> f64 {
        let (mut a, mut b) = (0.0, 0.0);
        for (i, g) in entries {
            let w = self.problem.model.inv_mass[i];
            implicit_accumulate(
                &mut a,
                &mut b,
                g,
                w,
                1.0,
                self.v[i],
                step.total[i],
                self.problem.params.dt,
            );
        }
        b
    }
}
