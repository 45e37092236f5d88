//! The physics of `physics.md` as small pure functions, written once and shared by every CPU
//! backend (generic over precision through [`Real`] and [`Vector`]); the GLSL includes under
//! `glsl/physics/` mirror them one to one, with the same names.
//!
//! One time step of length `dt` (physics.md, "Iterations, relaxation and substeps"):
//! 1. `F = m g` plus [`spring_force`] on both ends of every spring;
//! 2. `iterations` times: every constraint ([`distance_constraint`] or
//!    [`volume_constraint`]) reads `x(t)`, `v(t)` and the current `F`, gets its multiplier
//!    from [`implicit_lambda`] and contributes `-lambda grad_k C` to each of its nodes; the
//!    per-node sums are combined ([`ConstraintCombine`](crate::params::ConstraintCombine))
//!    and added to `F`, times `omega`; then each node's [`floor_force`] is solved again
//!    against the new `F` (the floor is a one-sided constraint in the same iterations);
//! 3. the floor force once more (the only floor solve for springs-only methods), then
//!    [`integrate_node`]: symplectic Euler, with [`floor_friction`] for nodes in contact.
//!
//! Choices the specification leaves open (documented here, in `docs/PHYSICS.md`, and exposed
//! where they are parameters):
//! - a spring of zero current length has no direction and exerts no force;
//! - a constraint whose `A = sum_k w_k |grad_k C|^2` is at or below
//!   [`SimParams::constraint_epsilon`](crate::params::SimParams::constraint_epsilon) is
//!   skipped (multiplier 0);
//! - gravity enters `F` as `m g`, so a pinned node (`w = 0`) does not fall;
//! - the floor never moves a node: it pushes (never pulls) just enough that the node ends the
//!   step on `y = 0` or above; a node with a positive floor force is in contact.

mod anderson;
mod chebyshev;
mod coarse;
mod constraint;
mod contact;
mod definite;
mod elastic;
mod held;
mod integrate;
mod minres;
mod rigid;
mod spring;
mod stiffness;

pub use anderson::{
    anderson_weights, gram_index, gram_terms, AndersonIteration, ANDERSON_MAX_MEMORY,
    ANDERSON_REGULARIZATION,
};
pub use chebyshev::{
    chebyshev_rho, chebyshev_rho_limit, chebyshev_weights, CHEBYSHEV_MAX_REVERSAL,
};
pub use coarse::{
    rebuilds, touching, Aggregates, CoarseSpace, COARSE_REBUILD_STEPS, MOST_AGGREGATES,
    NO_AGGREGATE,
};
pub use constraint::{
    compliant_multiplier, contact_held, distance_constraint, face_volume, global_multiplier,
    held_direction, implicit_accumulate, implicit_lambda, implicit_multiplier, inversion_floor,
    spring_constraint, spring_softness, volume_constraint, volume_softness,
};
pub use contact::{contact_push, end_position, surface_friction, Solve};
pub use definite::{definite_volume_term, singular_values};
pub use elastic::{
    elastic_corner, elastic_energy, elastic_rate, elastic_start, elastic_step, lame, node_block,
    shape_gradients, stable_neo_hookean, sym3_apply, sym3_inverse, ElasticTet, Sym3,
};
pub use held::{floor_holds, held_block, held_increment, held_mass, HELD_GAP, HELD_STIFFNESS};
pub use integrate::{
    coulomb_friction, floor_force, floor_friction, floor_solve, integrate_node, symplectic_euler,
};
pub use minres::{
    compliant_residual, Held, Mobility, NodeRows, StepRows, HELD_SHARE, MINRES_MAX_ITERATIONS,
};
pub use rigid::{correction_length, RigidPart};
pub use spring::spring_force;
pub use stiffness::{
    elastic_linearise, elastic_product, elastic_product_strain, elastic_relinearise, ElasticLinear,
    KEPT_STIFFNESS_STRAIN,
};
pub use tetmesh::geometry::{tet_volume, Real, Vector};
