//! The inversion floor on `cpu-ref` (`inversion_floor`, docs/PHYSICS.md "Inversion floor"):
//! each tet of a volume group measured where its nodes end the step, in double precision,
//! tet after tet.

use glam::DVec3;

use super::step_forces::StepForces;
use super::ReferenceBackend;
use crate::physics::{end_position, implicit_multiplier, inversion_floor, Solve};
use crate::schedule::GroupAt;

impl ReferenceBackend {
    /// The per-node sums of the inversion floor's forces of group `at` (a volume group)
    /// against the step's forces: every tet whose volume at its nodes' end positions is
    /// below `inversion_floor` times its rest volume gets the one-sided force
    /// `-lambda grad C` that lifts it back to first order ([`inversion_floor`]). None in
    /// split contact's velocity solve: the floor corrects positions, which the full solve
    /// keeps, and gives them no velocity.
    pub(super) fn inversion_group(&self, at: GroupAt, step: &StepForces) -> Vec<DVec3> {
        let (model, params) = (&self.problem.model, &self.problem.params);
        let dt = params.dt;
        let a_scale = &self.group_factors[at.sweep][at.group];
        let sweep = &self.problem.sweeps[at.sweep];
        let mut sum = vec![DVec3::ZERO; model.node_count()];
        // A position correction: none in split contact's velocity solve.
        if step.solve == Solve::Velocity {
            return sum;
        }
        for &t in sweep.groups.group(at.group) {
            let ids = model.tets[t as usize].map(|i| i as usize);
            let w = ids.map(|i| model.inv_mass[i]);
            let end = [0, 1, 2, 3].map(|k| {
                let i = ids[k];
                end_position(self.x[i], self.v[i], step.total[i], w[k], dt)
            });
            let rest = model.rest_volume[t as usize];
            let Some((c, grad)) = inversion_floor(end, rest, params.inversion_floor) else {
                continue;
            };
            let a: f64 = (0..4)
                .map(|k| a_scale[ids[k]].0 * w[k] * grad[k].length_squared())
                .sum();
            if let Some(lambda) = implicit_multiplier(c, a, 0.0, dt, params.constraint_epsilon) {
                for k in 0..4 {
                    sum[ids[k]] -= grad[k] * lambda;
                }
            }
        }
        sum
    }
}
