//! The inversion floor on `cpu-ref` (`inversion_floor`, docs/PHYSICS.md "Inversion floor"):
//! each tet of a volume group measured where its nodes end the step, in double precision,
//! tet after tet; in block Gauss-Seidel's blocks, against the block's copies of its nodes'
//! forces, which each tet's force moves as the volume sweep's do.

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
        let model = &self.problem.model;
        let factors = &self.group_factors[at.sweep][at.group];
        let sweep = &self.problem.sweeps[at.sweep];
        let mut sum = vec![DVec3::ZERO; model.node_count()];
        // A position correction: none in split contact's velocity solve.
        if step.solve == Solve::Velocity {
            return sum;
        }
        let members = sweep.groups.group(at.group);
        let Some(blocks) = &sweep.blocks else {
            for &t in members {
                let ids = model.tets[t as usize].map(|i| i as usize);
                if let Some(force) = self.floor_force(t, ids.map(|i| step.total[i]), factors) {
                    for k in 0..4 {
                        sum[ids[k]] += force[k];
                    }
                }
            }
            return sum;
        };
        let omega = self.problem.params.omega;
        for b in 0..blocks.len() {
            let nodes = blocks.nodes.row(b);
            let mut local: Vec<DVec3> = nodes.iter().map(|&k| step.total[k as usize]).collect();
            for p in blocks.members(b) {
                let t = members[p];
                let ids = model.tets[t as usize].map(|i| i as usize);
                let corners = blocks.corners[p].map(|l| l as usize);
                let Some(force) = self.floor_force(t, corners.map(|l| local[l]), factors) else {
                    continue;
                };
                for k in 0..4 {
                    sum[ids[k]] += force[k];
                    local[corners[k]] += force[k] * blocks.copy_scale(ids[k], factors, omega);
                }
            }
        }
        sum
    }

    /// The floor's forces on tet `t` whose nodes have the forces `f`, if it ends the step
    /// below the floor (`factors`: each node's `(a_scale, weight)`).
    fn floor_force(&self, t: u32, f: [DVec3; 4], factors: &[(f64, f64)]) -> Option<[DVec3; 4]> {
        let (model, params) = (&self.problem.model, &self.problem.params);
        let ids = model.tets[t as usize].map(|i| i as usize);
        let w = ids.map(|i| model.inv_mass[i]);
        let end = [0, 1, 2, 3].map(|k| {
            let i = ids[k];
            end_position(self.x[i], self.v[i], f[k], w[k], params.dt)
        });
        let rest = model.rest_volume[t as usize];
        let (c, grad) = inversion_floor(end, rest, params.inversion_floor)?;
        let a: f64 = (0..4)
            .map(|k| factors[ids[k]].0 * w[k] * grad[k].length_squared())
            .sum();
        let lambda = implicit_multiplier(c, a, 0.0, params.dt, params.constraint_epsilon)?;
        Some(grad.map(|g| g * -lambda))
    }
}
