//! `cpu-ref`'s finite elements: the node steps of one colour group.

use glam::DVec3;

use super::step_forces::StepForces;
use super::ReferenceBackend;
use crate::physics::end_position;
use crate::schedule::family::Family;
use crate::schedule::GroupAt;

impl ReferenceBackend {
    /// The finite elements' node steps of group `at` (a node colour) against the step's
    /// forces: each node's force increment ([`ElasticNodes::step`]) at its own slot.
    pub(super) fn elastic_group(&self, at: GroupAt, step: &StepForces) -> Vec<DVec3> {
        let Family::Elastic(nodes) = &self.families[at.sweep] else {
            return vec![DVec3::ZERO; self.problem.model.node_count()];
        };
        let (model, dt) = (&self.problem.model, self.problem.params.dt);
        let w = &model.inv_mass;
        let end = |k: usize| end_position(self.x[k], self.v[k], step.total[k], w[k], dt);
        let mut sum = vec![DVec3::ZERO; model.node_count()];
        for &i in self.problem.sweeps[at.sweep].groups.group(at.group) {
            let i = i as usize;
            sum[i] = nodes.step(
                i,
                w[i],
                dt,
                step.elastic(i),
                &model.tets,
                |k| self.x[k],
                end,
            );
        }
        sum
    }
}
