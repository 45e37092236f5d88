//! MINRES after the sweeps on `cpu` ([`crate::backend::cpu::minres`], on the team, the
//! product in single precision): the step's constraint rows at the forces the team left, solved, and their
//! increments applied to the forces and the compliant multipliers. The floor and colliders
//! are solved again by the passes that follow (the inversion sweeps' or `integrate`).

use glam::{DVec3, Vec3A};

use super::ParallelBackend;
use crate::backend::cpu::minres::Minres;
use crate::backend::cpu::parallel::{ConstraintFamily, Family, Global, Sweep};
use crate::backend::cpu::team::Team;
use crate::physics::{compliant_residual, implicit_accumulate, Mobility, StepRows, Vector};

/// Where a row's increment goes: its sweep and position (compliant constraints), or nowhere.
type Slot = Option<(usize, usize)>;

/// The rows of the last step, where their increments went and the solve's memory, kept so
/// that each step reuses them (the sphere's rows are 200 kB: allocated anew, each step paid
/// for its pages).
#[derive(Debug, Clone, Default)]
pub(super) struct MinresRows {
    rows: StepRows<Vec3A>,
    slots: Vec<Slot>,
    solver: Minres<Vec3A>,
}

impl ParallelBackend {
    /// `self.minres` iterations of MINRES on every constraint of `sweeps` (each kind once)
    /// and the global volume constraints at the forces so far, the nodes the floor,
    /// colliders and grabs push held, solved by `team`.
    pub(super) fn minres_solve(
        &mut self,
        team: &Team,
        sweeps: &mut [Sweep],
        global: Option<&Global>,
    ) {
        let MinresRows {
            mut rows,
            mut slots,
            mut solver,
        } = std::mem::take(&mut self.minres_rows);
        rows.clear();
        slots.clear();
        let mut kinds = Vec::new();
        for (s, sweep) in sweeps.iter().enumerate() {
            if kinds.contains(&sweep.kind) {
                continue;
            }
            kinds.push(sweep.kind);
            match &sweep.family {
                Family::Springs(f) => {
                    self.rows_of(f, s, sweep, &sweep.pair_nodes, &mut rows, &mut slots)
                }
                Family::Distances(f) => {
                    self.rows_of(f, s, sweep, &sweep.pair_nodes, &mut rows, &mut slots)
                }
                Family::Volumes(f) => {
                    self.rows_of(f, s, sweep, &sweep.tet_nodes, &mut rows, &mut slots)
                }
                // Validation refuses MINRES for the finite elements.
                Family::Elastic(_) => {}
            }
        }
        if let Some(global) = global {
            self.global_rows(global, &mut rows, &mut slots);
        }
        solver.solve(team, &rows, &self.mobility(), self.minres);
        let delta = solver.increments();
        for (i, f) in self.f.iter_mut().enumerate() {
            *f -= solver.node_force(i);
        }
        for (&d, slot) in delta.iter().zip(&slots) {
            if let Some((s, p)) = *slot {
                sweeps[s].multipliers[p] += d as f32;
            }
        }
        self.minres_rows = MinresRows {
            rows,
            slots,
            solver,
        };
    }

    /// Each node's mobility ([`Mobility::held_by`] the floor, colliders and grabs).
    fn mobility(&self) -> Vec<Mobility> {
        (0..self.x.len())
            .map(|i| {
                let grabbed = self.attached.get(i).is_some_and(|a| a.is_some());
                let collider = self.contact.get(i).map_or(DVec3::ZERO, |c| c.to_dvec3());
                let (w, floor) = (f64::from(self.inv_mass[i]), self.floor_force[i] > 0.0);
                Mobility::held_by(w, floor, collider, grabbed)
            })
            .collect()
    }

    /// The rows of sweep `s`'s constraints (`nodes` in group order) at the forces so far.
    fn rows_of<const K: usize, F: ConstraintFamily<f32, K>>(
        &self,
        family: &F,
        s: usize,
        sweep: &Sweep,
        nodes: &[[u32; K]],
        rows: &mut StepRows<Vec3A>,
        slots: &mut Vec<Slot>,
    ) {
        for (p, (&e, ids)) in sweep.members.items.iter().zip(nodes).enumerate() {
            let (c, grad, softness, damping) =
                family.evaluate(e as usize, ids.map(|i| self.x[i as usize]));
            let (softness, damping) = (f64::from(softness), f64::from(damping));
            let (c, so_far, slot) = match softness > 0.0 {
                false => (self.k.solve.hard(f64::from(c)), 0.0, None),
                true => (
                    f64::from(c),
                    softness * f64::from(sweep.multipliers[p]),
                    Some((s, p)),
                ),
            };
            let b =
                self.numerator_sum(ids.iter().copied().zip(grad.map(|g| g.to_dvec3()))) - so_far;
            let residual = compliant_residual(c, b, self.dt, softness, damping);
            rows.push(ids, &grad, softness, residual);
            slots.push(slot);
        }
    }

    /// The rows of the global volume constraints (hard) at the forces so far.
    fn global_rows(&self, global: &Global, rows: &mut StepRows<Vec3A>, slots: &mut Vec<Slot>) {
        for (object, &(c, _)) in global.data.objects.iter().zip(&global.c_and_a) {
            let range =
                object.node_first as usize..(object.node_first + object.node_count) as usize;
            let nodes = &global.data.nodes[range.clone()];
            let grads = &global.grad[range];
            let b = self.numerator_sum(
                nodes
                    .iter()
                    .copied()
                    .zip(grads.iter().map(|g| g.to_dvec3())),
            );
            let c = self.k.solve.hard(f64::from(c));
            rows.push(
                nodes,
                grads,
                0.0,
                compliant_residual(c, b, self.dt, 0.0, 0.0),
            );
            slots.push(None);
        }
    }

    /// `sum_k grad_k . (v_k / dt + w_k F_k)` of a row's entries at the forces so far.
    fn numerator_sum(&self, entries: impl Iterator<Item = (u32, DVec3)>) -> f64 {
        let (mut a, mut b) = (0.0, 0.0);
        for (i, g) in entries {
            let i = i as usize;
            let (v, f, w) = (self.v[i].to_dvec3(), self.f[i].to_dvec3(), self.inv_mass[i]);
            implicit_accumulate(&mut a, &mut b, g, f64::from(w), 1.0, v, f, self.dt);
        }
        b
    }
}
