//! CPU backends: [`ReferenceBackend`] (`cpu-ref`: f64, single-threaded, the oracle every other
//! backend is tested against) and [`ParallelBackend`] (`cpu`: f32, every core, the fast CPU
//! competitor of the Vulkan engine). Both call the same math in [`crate::physics`].

mod barrier;
pub mod memory;
mod minres;
mod parallel;
mod reference;
mod shared;
mod team;
mod team_choice;

pub use parallel::ParallelBackend;
pub use reference::{Forces, ReferenceBackend};

use crate::backend::{Divergence, State};
use crate::error::{Error, Result};
use crate::model::{Csr, Model};
use crate::params::Method;

/// For each node, the `(tet, corner)` slots it occupies, encoded as `4 * tet + corner`
/// (node-centric gather of per-tet results, no atomics).
pub fn node_tet_corners(model: &Model) -> Csr {
    Csr::from_pairs(model.node_count(), || {
        model.tets.iter().enumerate().flat_map(|(t, tet)| {
            tet.iter()
                .enumerate()
                .map(move |(corner, &v)| (v as usize, (4 * t + corner) as u32))
        })
    })
}

/// Checks that `state` has `n` nodes and is finite.
pub(crate) fn check_state(n: usize, state: &State) -> Result<()> {
    if state.positions.len() != n || state.velocities.len() != n {
        return Err(Error::param(
            "state",
            format!(
                "has {} positions and {} velocities, the model has {n} nodes",
                state.positions.len(),
                state.velocities.len()
            ),
        ));
    }
    let bad = state
        .positions
        .iter()
        .zip(&state.velocities)
        .position(|(x, v)| !x.is_finite() || !v.is_finite());
    match bad {
        Some(i) => Err(Error::param("state", format!("node {i} is not finite"))),
        None => Ok(()),
    }
}

/// How a node failed the divergence check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Bad {
    /// A position or velocity is NaN or infinite.
    NonFinite,
    /// Its speed [m/s] exceeds the limit.
    TooFast(f64),
}

/// The error for a state that failed the divergence check at `node`; `likely` is the
/// backend's [`crate::stability::likely_cause`].
fn diverged(
    frame: u32,
    substep: u32,
    method: Method,
    node: u32,
    bad: Bad,
    limit: f64,
    likely: &str,
) -> Error {
    let what = match bad {
        Bad::NonFinite => "a position or velocity became non-finite".to_string(),
        Bad::TooFast(speed) => {
            format!("its speed {speed:.3e} m/s exceeds the divergence limit {limit:.3e} m/s")
        }
    };
    Error::Diverged(Box::new(Divergence {
        frame,
        substep: Some(substep),
        method: method.name().to_string(),
        node: Some(node),
        cause: format!("{what}; {likely}"),
    }))
}
