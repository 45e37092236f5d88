//! What a backend's steps carry from one to the next besides the positions and velocities
//! ([`Carried`]): the clocks of its colliders and clamps and the arrays a step starts from
//! (warm-started multipliers, the finite elements' forces). A checkpoint holds it, so that
//! a run resumed from one continues bit for bit ([`crate::sim::Checkpoint`]).

use crate::error::{Error, Result};
use crate::physics::CoarseSpace;

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

/// The name of the finite elements' coarse level among the carried arrays (both CPU
/// backends; [`crate::physics::CoarseSpace::to_values`]).
pub const COARSE_KEY: &str = "coarse_level";

/// The coarse level `carried` holds, for a run of `aggregates` aggregates: none (built at
/// the next step) when it holds none, as a checkpoint written before the level was kept
/// from step to step; an error naming the array when its numbers do not fit the run.
pub fn restore_coarse(carried: &Carried, aggregates: usize) -> Result<CoarseSpace> {
    let Some((_, values)) = carried.arrays.iter().find(|(n, _)| n == COARSE_KEY) else {
        return Ok(CoarseSpace::default());
    };
    CoarseSpace::from_values(values, aggregates).ok_or_else(|| {
        Error::param(
            "checkpoint",
            format!(
                "its `{COARSE_KEY}` ({} values) is not the coarse level of this run's \
                 {aggregates} aggregates",
                values.len()
            ),
        )
    })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::Aggregates;
    use glam::DVec3;

    #[test]
    fn the_coarse_level_comes_back_or_is_refused_naming_it() {
        // Two aggregates of a row of nodes, factored with a diagonal A_c.
        let positions: Vec<DVec3> = (0..128).map(|i| DVec3::X * i as f64).collect();
        let aggregates = Aggregates::group(&positions, &[1.0; 128], &[0, 128], &[]);
        assert_eq!(aggregates.len(), 2);
        let mut coarse = CoarseSpace::new(&aggregates, |k| positions[k]);
        let n = coarse.unknowns();
        let columns: Vec<f64> = (0..n * n)
            .map(|k| if k % (n + 1) == 0 { 2.0 } else { 0.0 })
            .collect();
        coarse.assemble(&columns);
        let carried = |values: Vec<f64>| Carried {
            arrays: vec![(COARSE_KEY.to_string(), values)],
            ..Carried::default()
        };
        let back = restore_coarse(&carried(coarse.to_values()), 2).unwrap();
        assert_eq!(back.to_values(), coarse.to_values());
        // None carried (an older checkpoint): built at the next step.
        assert!(!restore_coarse(&Carried::default(), 2).unwrap().is_built());
        // Cut short, or of another run's aggregates: refused, naming the array.
        let mut short = coarse.to_values();
        short.pop();
        for (values, aggregates) in [(short, 2), (coarse.to_values(), 3)] {
            let error = restore_coarse(&carried(values), aggregates).unwrap_err();
            assert!(error.to_string().contains(COARSE_KEY), "{error}");
        }
    }
}
