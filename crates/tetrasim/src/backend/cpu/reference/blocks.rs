//! Block Gauss-Seidel on `cpu-ref` (docs/PHYSICS.md, "Block Gauss-Seidel"): every block
//! from the iteration's forces, its constraints one after another in colour order against
//! the forces its earlier constraints left, in double precision.

use glam::DVec3;

use super::ReferenceBackend;
use crate::model::ConstraintBlocks;
use crate::physics::Solve;
use crate::schedule::family::ConstraintFamily;

impl ReferenceBackend {
    /// The per-node sums of the constraint forces of one block sweep (`members`, the sweep's
    /// one group in block order) against the forces `f`; `lambda`: the compliant
    /// multipliers so far, per constraint. Each block starts from `f` and keeps its own copy
    /// of its nodes' forces: a constraint's force moves them by `a_scale * weight * omega`
    /// times it (`factors`: the node's `(a_scale, weight)` for its block degree), as the
    /// node will move when every block's forces are applied, so later constraints of the
    /// block see it; a hub's copy stays (Jacobi). A block is swept `block_sweeps` times
    /// ([`crate::model::ConstraintKind::block_sweeps`] of its kind).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn sweep_blocks<const K: usize, F: ConstraintFamily<f64, K>>(
        &self,
        members: &[u32],
        blocks: &ConstraintBlocks,
        family: &F,
        solve: Solve,
        f: &[DVec3],
        factors: &[(f64, f64)],
        lambda: &mut [f64],
    ) -> Vec<DVec3> {
        let (model, params) = (&self.problem.model, &self.problem.params);
        let (omega, sweeps) = (params.omega, F::KIND.block_sweeps(params));
        let elements = F::elements(model);
        let a_scale: Vec<f64> = factors.iter().map(|f| f.0).collect();
        let mut sum = vec![DVec3::ZERO; model.node_count()];
        for b in 0..blocks.len() {
            let nodes = blocks.nodes.row(b);
            let mut local: Vec<DVec3> = nodes.iter().map(|&k| f[k as usize]).collect();
            for p in (0..sweeps).flat_map(|_| blocks.members(b)) {
                let e = members[p] as usize;
                let ids = elements[e].map(|i| i as usize);
                let corners: [usize; K] = std::array::from_fn(|k| blocks.corners[p][k] as usize);
                let (c, grad, softness, damping) = family.evaluate(e, ids.map(|i| self.x[i]));
                let (c, so_far) = match softness > 0.0 {
                    true => (c, softness * lambda[e]),
                    false => (solve.hard(c), 0.0),
                };
                let forces = corners.map(|l| local[l]);
                let Some(delta) =
                    self.lambda(c, &grad, ids, forces, &a_scale, so_far, softness, damping)
                else {
                    continue;
                };
                if softness > 0.0 {
                    lambda[e] += omega * delta;
                }
                for k in 0..K {
                    let force = grad[k] * -delta;
                    sum[ids[k]] += force;
                    local[corners[k]] += force * blocks.copy_scale(ids[k], factors, omega);
                }
            }
        }
        sum
    }
}
