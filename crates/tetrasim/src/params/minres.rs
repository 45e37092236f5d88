//! MINRES after the sweeps ([`SimParams::minres`]): its checks.

use super::SimParams;
use crate::error::{Error, Result};
use crate::physics::MINRES_MAX_ITERATIONS;

impl SimParams {
    /// Checks `minres`: at most [`MINRES_MAX_ITERATIONS`], and only where there are
    /// constraints to solve.
    pub(super) fn validate_minres(&self) -> Result<()> {
        if self.minres > MINRES_MAX_ITERATIONS {
            return Err(Error::param(
                "minres",
                format!(
                    "must be at most {MINRES_MAX_ITERATIONS} iterations, got {}",
                    self.minres
                ),
            ));
        }
        if self.minres > 0 && !self.has_constraints() {
            return Err(Error::param(
                "minres",
                format!(
                    "solves the step's constraints; method {} with explicit springs has none \
                     (use method volume or distance, or springs = implicit)",
                    self.method
                ),
            ));
        }
        Ok(())
    }
}
