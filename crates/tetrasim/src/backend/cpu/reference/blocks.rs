//! Block Gauss-Seidel on `cpu-ref` (docs/PHYSICS.md, "Block Gauss-Seidel"): every block
//! from the iteration's forces, its tets one after another in colour order against the
//! forces its earlier tets left, in double precision.

use glam::DVec3;

use super::step_forces::StepForces;
use super::ReferenceBackend;
use crate::model::ConstraintBlocks;
use crate::schedule::family::{ConstraintFamily, Volumes};

impl ReferenceBackend {
    /// The per-node sums of the volume constraints' forces of one block sweep (`members`,
    /// the sweep's one group in block order). Each block starts from the step's forces and
    /// keeps its own copy of its nodes' forces: a tet's force `f` moves them by
    /// `a_scale * weight * omega * f` (`factors`: the node's `(a_scale, weight)` for its
    /// block degree), as the node will move when every block's forces are applied, so later
    /// tets of the block see it; a hub's copy stays (Jacobi).
    pub(super) fn sweep_blocks(
        &self,
        members: &[u32],
        blocks: &ConstraintBlocks,
        family: &Volumes<f64>,
        step: &mut StepForces,
        factors: &[(f64, f64)],
    ) -> Vec<DVec3> {
        let (model, omega) = (&self.problem.model, self.problem.params.omega);
        let a_scale: Vec<f64> = factors.iter().map(|f| f.0).collect();
        let mut sum = vec![DVec3::ZERO; model.node_count()];
        for b in 0..blocks.len() {
            let nodes = blocks.nodes.row(b);
            let mut local: Vec<DVec3> = nodes.iter().map(|&k| step.total[k as usize]).collect();
            for p in blocks.members(b) {
                let e = members[p] as usize;
                let ids = model.tets[e].map(|i| i as usize);
                let corners = blocks.corners[p].map(|l| l as usize);
                let (c, grad, softness, damping) = family.evaluate(e, ids.map(|i| self.x[i]));
                let (c, so_far) = match softness > 0.0 {
                    true => (c, softness * step.volume_lambda[e]),
                    false => (step.solve.hard(c), 0.0),
                };
                let forces = corners.map(|l| local[l]);
                let Some(delta) =
                    self.lambda(c, &grad, ids, forces, &a_scale, so_far, softness, damping)
                else {
                    continue;
                };
                if softness > 0.0 {
                    step.volume_lambda[e] += omega * delta;
                }
                for k in 0..4 {
                    let force = grad[k] * -delta;
                    let (scale, weight) = factors[ids[k]];
                    sum[ids[k]] += force;
                    if !blocks.hub[ids[k]] {
                        local[corners[k]] += force * (scale * weight * omega);
                    }
                }
            }
        }
        sum
    }
}
