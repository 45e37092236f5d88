//! The inversion floor's keys ([`SimParams::inversion_sweeps`],
//! [`SimParams::inversion_floor`]): their defaults and checks.

use super::{Method, SimParams};
use crate::error::{Error, Result};

/// The most inversion sweeps a step may ask for.
pub const MAX_INVERSION_SWEEPS: u32 = 64;

/// The default fraction of the rest volume the inversion sweeps restore: 10 %.
pub fn default_inversion_floor() -> f64 {
    0.1
}

impl SimParams {
    /// Checks the inversion floor's keys.
    pub(super) fn validate_inversion(&self) -> Result<()> {
        if !(self.inversion_floor > 0.0 && self.inversion_floor <= 1.0) {
            return Err(Error::param(
                "inversion_floor",
                format!(
                    "is a fraction of the rest volume in (0, 1], got {}",
                    self.inversion_floor
                ),
            ));
        }
        if self.inversion_sweeps > MAX_INVERSION_SWEEPS {
            return Err(Error::param(
                "inversion_sweeps",
                format!(
                    "must be at most {MAX_INVERSION_SWEEPS}, got {}",
                    self.inversion_sweeps
                ),
            ));
        }
        if self.inversion_sweeps > 0 && self.method != Method::Volume {
            return Err(Error::param(
                "inversion_sweeps",
                format!(
                    "sweep the volume constraints' groups; method {} has none (use method \
                     volume)",
                    self.method
                ),
            ));
        }
        Ok(())
    }
}
