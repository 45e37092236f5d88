//! Implicit springs: `C = |x_i - x_j| - L` on a spring's two nodes, with compliance `1 / k_e`
//! and the spring's damping ([`spring_constraint`], [`spring_softness`]); their multipliers
//! are kept through the step (and, warm-started, into the next).

use super::{Access, BufferId, ConstraintFamily, PassKind};
use crate::model::{ConstraintKind, Model};
use crate::physics::{spring_constraint, spring_softness, Real, Vector};
use crate::problem::Problem;

/// The pass that solves them.
pub(super) const PASS: PassKind = PassKind::SpringConstraint;

/// What the pass reads besides the nodes (and writes: the multipliers so far).
pub(super) fn bindings() -> Vec<(BufferId, Access)> {
    vec![
        (BufferId::Springs, Access::Read),
        (BufferId::SpringDamping, Access::Read),
        (BufferId::SpringMultipliers, Access::ReadWrite),
    ]
}

/// Per spring: rest length, softness and damping.
#[derive(Debug, Clone)]
pub struct ImplicitSprings<R> {
    rest: Vec<R>,
    softness: Vec<R>,
    damping: Vec<R>,
}

impl<R: Real> ConstraintFamily<R, 2> for ImplicitSprings<R> {
    const KIND: ConstraintKind = ConstraintKind::Spring;

    fn prepare(problem: &Problem) -> Self {
        let (m, dt) = (&problem.material, problem.params.dt);
        let stiffness = m.spring_stiffness.iter().zip(&m.spring_damping);
        ImplicitSprings {
            rest: problem
                .model
                .rest_length
                .iter()
                .map(|&l| R::from_f64(l))
                .collect(),
            softness: stiffness
                .map(|(&k, &kd)| R::from_f64(spring_softness(k, kd, dt)))
                .collect(),
            damping: m.spring_damping.iter().map(|&kd| R::from_f64(kd)).collect(),
        }
    }

    fn elements(model: &Model) -> &[[u32; 2]] {
        &model.springs
    }

    #[inline]
    fn evaluate<V: Vector<Real = R>>(&self, e: usize, [a, b]: [V; 2]) -> (R, [V; 2], R, R) {
        let (c, grad) = spring_constraint(a, b, self.rest[e]);
        (c, grad, self.softness[e], self.damping[e])
    }
}
