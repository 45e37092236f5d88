//! The checks of block Gauss-Seidel's key ([`SimParams::block_size`]).

use super::{SimParams, Solver, MAX_BLOCK_SIZE};
use crate::error::{Error, Result};

impl SimParams {
    /// Checks `block_size`: at most [`MAX_BLOCK_SIZE`], only with what sweeps in blocks.
    pub(super) fn validate_blocks(&self) -> Result<()> {
        if self.block_size == 0 {
            return Ok(());
        }
        let refuse = |message: String| Err(Error::param("block_size", message));
        if self.block_size > MAX_BLOCK_SIZE {
            return refuse(format!(
                "must be at most {MAX_BLOCK_SIZE} (a block is one GPU workgroup), got {}",
                self.block_size
            ));
        }
        if self.solver != Solver::GaussSeidel {
            return refuse(format!(
                "cuts the gauss-seidel solver's sweep into blocks; solver {} has none (use \
                 gauss-seidel, or block_size 0)",
                self.solver
            ));
        }
        if !self.has_constraints() {
            return refuse(format!(
                "cuts the constraint sweeps into blocks; method {} with explicit springs has \
                 none (use method volume or distance, or springs = implicit)",
                self.method
            ));
        }
        Ok(())
    }
}
