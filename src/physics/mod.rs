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
//!    and added to `F`, times `omega`;
//! 3. [`symplectic_euler`], then [`resolve_floor`].
//!
//! Choices the specification leaves open (documented here, in `docs/PHYSICS.md`, and exposed
//! where they are parameters):
//! - a spring of zero current length has no direction and exerts no force;
//! - a constraint whose `A = sum_k w_k |grad_k C|^2` is at or below
//!   [`SimParams::constraint_epsilon`](crate::params::SimParams::constraint_epsilon) is
//!   skipped (multiplier 0);
//! - gravity enters `F` as `m g`, so a pinned node (`w = 0`) does not fall;
//! - the floor acts on nodes strictly below `y = 0`.

mod constraint;
mod integrate;
mod real;
mod spring;

pub use constraint::{distance_constraint, implicit_lambda, tet_volume, volume_constraint};
pub use integrate::{resolve_floor, symplectic_euler};
pub use real::{Real, Vector};
pub use spring::spring_force;
