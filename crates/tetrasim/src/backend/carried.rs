//! What a backend's steps carry from one to the next besides the positions and velocities
//! ([`Carried`]): the clocks of its colliders and clamps and the arrays a step starts from
//! (warm-started multipliers, the finite elements' forces). A checkpoint holds it, so that
//! a run resumed from one continues bit for bit ([`crate::sim::Checkpoint`]).

use crate::error::{Error, Result};

/// A backend's carried state ([module docs](self)).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Carried {
    /// Frames stepped since the backend was made (divergence messages count from here).
    pub frames: u32,
    /// Time steps taken since the backend was made: the colliders' and clamps' clock.
    pub steps: u64,
    /// Named arrays, each the backend's own (a backend restores only the names it wrote).
    pub arrays: Vec<(String, Vec<f64>)>,
}

impl Carried {
    /// The array `name`, which must hold `len` values; an error naming it otherwise.
    pub fn array(&self, name: &str, len: usize) -> Result<&[f64]> {
        let found = self.arrays.iter().find(|(n, _)| n == name);
        match found {
            Some((_, values)) if values.len() == len => Ok(values),
            Some((_, values)) => Err(Error::param(
                "checkpoint",
                format!(
                    "its `{name}` holds {} values; this run has {len}",
                    values.len()
                ),
            )),
            None => Err(Error::param(
                "checkpoint",
                format!("it holds no `{name}`, which this run carries from step to step"),
            )),
        }
    }

    /// Whether it holds an array `name`.
    pub fn has(&self, name: &str) -> bool {
        self.arrays.iter().any(|(n, _)| n == name)
    }
}

/// `vectors` as `x y z` triples of f64.
pub fn flatten<V: Into<glam::DVec3> + Copy>(vectors: &[V]) -> Vec<f64> {
    vectors.iter().flat_map(|&v| v.into().to_array()).collect()
}

/// Triples of `values` as vectors.
pub fn unflatten(values: &[f64]) -> Vec<glam::DVec3> {
    values
        .chunks_exact(3)
        .map(|c| glam::DVec3::new(c[0], c[1], c[2]))
        .collect()
}
