//! Volume constraints: `C = V - V0` on a tet's four nodes, hard or with the material's
//! compliance ([`volume_constraint`], [`volume_softness`]); a compliant one keeps its
//! multiplier through the step.

use super::{Access, BufferId, ConstraintFamily, PassKind};
use crate::model::{ConstraintKind, Model};
use crate::physics::{volume_constraint, volume_softness, Real, Vector};
use crate::problem::Problem;

/// The pass that solves them.
pub(super) const PASS: PassKind = PassKind::Volume;

/// What the pass reads besides the nodes (and writes: the multipliers so far).
pub(super) fn bindings() -> Vec<(BufferId, Access)> {
    vec![
        (BufferId::Tets, Access::Read),
        (BufferId::RestVolumes, Access::Read),
        (BufferId::VolumeCompliance, Access::Read),
        (BufferId::VolumeMultipliers, Access::ReadWrite),
    ]
}

/// Per tet: rest volume and softness (0: hard).
#[derive(Debug, Clone)]
pub struct Volumes<R> {
    rest: Vec<R>,
    softness: Vec<R>,
}

impl<R: Real> ConstraintFamily<R, 4> for Volumes<R> {
    const KIND: ConstraintKind = ConstraintKind::Volume;

    fn prepare(problem: &Problem) -> Self {
        let (compliance, dt) = (&problem.material.volume_compliance, problem.params.dt);
        Volumes {
            rest: (problem.model.rest_volume.iter())
                .map(|&v| R::from_f64(v))
                .collect(),
            softness: (compliance.iter())
                .map(|&alpha| R::from_f64(volume_softness(alpha, dt)))
                .collect(),
        }
    }

    fn elements(model: &Model) -> &[[u32; 4]] {
        &model.tets
    }

    #[inline]
    fn evaluate<V: Vector<Real = R>>(&self, e: usize, p: [V; 4]) -> (R, [V; 4], R, R) {
        let (c, grad) = volume_constraint(p, self.rest[e]);
        (c, grad, self.softness[e], R::ZERO)
    }
}
