//! The paper's distance constraints: `C = |x_i - x_j|^2 - L^2` on a spring's two nodes, hard
//! ([`distance_constraint`]).

use super::{Access, BufferId, ConstraintFamily, PassKind};
use crate::model::{ConstraintKind, Model};
use crate::physics::{distance_constraint, Real, Vector};
use crate::problem::Problem;

/// The pass that solves them.
pub(super) const PASS: PassKind = PassKind::Distance;

/// What the pass reads besides the nodes.
pub(super) fn bindings() -> Vec<(BufferId, Access)> {
    vec![(BufferId::Springs, Access::Read)]
}

/// Per spring: rest length.
#[derive(Debug, Clone)]
pub struct Distances<R> {
    rest: Vec<R>,
}

impl<R: Real> ConstraintFamily<R, 2> for Distances<R> {
    const KIND: ConstraintKind = ConstraintKind::Distance;

    fn prepare(problem: &Problem) -> Self {
        let rest = &problem.model.rest_length;
        Distances {
            rest: rest.iter().map(|&l| R::from_f64(l)).collect(),
        }
    }

    fn elements(model: &Model) -> &[[u32; 2]] {
        &model.springs
    }

    #[inline]
    fn evaluate<V: Vector<Real = R>>(&self, e: usize, [a, b]: [V; 2]) -> (R, [V; 2], R, R) {
        let (c, grad) = distance_constraint(a, b, self.rest[e]);
        (c, grad, R::ZERO, R::ZERO)
    }
}
