//! Constraint families, one file each: what a constraint of the family is (its math, from
//! [`crate::physics`]), how many nodes it binds, the data it reads (prepared once from the
//! [`Problem`], in the backend's precision), the arrays its stage binds and the pass that
//! solves it. The schedule, the Vulkan plan and both CPU backends ask here; a new family is
//! a file here, its arm in [`ConstraintKind`]'s look-ups below, its shader and its
//! [`PassKind`].

mod distance;
mod elastic;
mod spring;
mod volume;

pub use distance::Distances;
pub use elastic::{
    backtrack, node_elements, Backtracked, ElasticNodes, TRUSTED_RATIO, TRUSTED_STRAIN,
};
pub use spring::ImplicitSprings;
pub use volume::Volumes;

use super::{Access, BufferId, Domain, PassKind};
use crate::model::{ConstraintKind, Csr, Model, Sweep};
use crate::physics::{Real, Vector};
use crate::problem::Problem;

/// A constraint family on `K` nodes, its data in precision `R`.
pub trait ConstraintFamily<R: Real, const K: usize>: Sized {
    /// Which family.
    const KIND: ConstraintKind;

    /// Its data for `problem`, rounded to `R` (what is derived, derived in f64 first).
    fn prepare(problem: &Problem) -> Self;

    /// Each constraint's nodes.
    fn elements(model: &Model) -> &[[u32; K]];

    /// Constraint `e` at its nodes' positions `p`: the value `C`, its gradients, the
    /// softness of its compliance (0: hard) and its damping.
    fn evaluate<V: Vector<Real = R>>(&self, e: usize, p: [V; K]) -> (R, [V; K], R, R);
}

/// The data of one sweep's family, in precision `R`.
#[derive(Debug, Clone)]
pub enum Family<R> {
    /// Implicit springs.
    Springs(ImplicitSprings<R>),
    /// Distance constraints.
    Distances(Distances<R>),
    /// Volume constraints.
    Volumes(Volumes<R>),
    /// Finite elements' per-node steps.
    Elastic(ElasticNodes<R>),
}

impl<R: Real> Family<R> {
    /// The family of each of `problem`'s sweeps, prepared.
    pub fn of_sweeps(problem: &Problem) -> Vec<Self> {
        (problem.sweeps.iter())
            .map(|sweep| match sweep.kind {
                ConstraintKind::Spring => Family::Springs(ImplicitSprings::prepare(problem)),
                ConstraintKind::Distance => Family::Distances(Distances::prepare(problem)),
                ConstraintKind::Volume => Family::Volumes(Volumes::prepare(problem)),
                ConstraintKind::Elastic => Family::Elastic(ElasticNodes::prepare(problem)),
            })
            .collect()
    }
}

impl ConstraintKind {
    /// The pass that solves a sweep of the family.
    pub fn pass(self) -> PassKind {
        match self {
            ConstraintKind::Spring => spring::PASS,
            ConstraintKind::Distance => distance::PASS,
            ConstraintKind::Volume => volume::PASS,
            ConstraintKind::Elastic => elastic::PASS,
        }
    }

    /// Nodes per constraint.
    pub fn arity(self) -> usize {
        match self {
            ConstraintKind::Spring | ConstraintKind::Distance => 2,
            ConstraintKind::Volume => 4,
            ConstraintKind::Elastic => 1,
        }
    }

    /// The elements a sweep of the family covers when it is not solved group by group, and
    /// the arrays its solve reads besides the nodes'.
    pub fn data(self) -> (Domain, Vec<(BufferId, Access)>) {
        match self {
            ConstraintKind::Spring => (Domain::Springs, spring::bindings()),
            ConstraintKind::Distance => (Domain::Springs, distance::bindings()),
            ConstraintKind::Volume => (Domain::Tets, volume::bindings()),
            ConstraintKind::Elastic => (Domain::Nodes, elastic::bindings()),
        }
    }

    /// Per group `g` and node `i` of `sweep` (row `g * n + i`): the node's slots among the
    /// group's constraint results (`K * position + corner`).
    pub fn node_slots(sweep: &Sweep, model: &Model) -> Csr {
        let n = model.node_count();
        match sweep.kind {
            ConstraintKind::Spring => sweep
                .groups
                .node_slots(ImplicitSprings::<f64>::elements(model), n),
            ConstraintKind::Distance => sweep
                .groups
                .node_slots(Distances::<f64>::elements(model), n),
            ConstraintKind::Volume => sweep.groups.node_slots(Volumes::<f64>::elements(model), n),
            ConstraintKind::Elastic => sweep.groups.node_slots(&node_elements(model), n),
        }
    }
}
