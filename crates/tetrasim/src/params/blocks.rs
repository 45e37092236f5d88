//! The checks of block Gauss-Seidel's key ([`SimParams::block_size`]).

use super::{SimParams, Solver};
use crate::error::{Error, Result};

/// The largest block a GPU workgroup solves ([`SimParams::block_size`]): one invocation per
/// constraint, and 1024 invocations is what GPUs offer. Blocks up to this size are
/// workgroup blocks (at most [`crate::model::MAX_BLOCK_NODES`] nodes, busy nodes as hubs);
/// larger ones are thread blocks, for the `cpu` backends only (docs/PHYSICS.md, "Thread
/// blocks").
pub const MAX_WORKGROUP_BLOCK: u32 = 1024;

/// The largest [`SimParams::block_size`]: more constraints than any mesh the engine runs (a
/// block larger than a sweep is the whole sweep, Gauss-Seidel in one order).
pub const MAX_BLOCK_SIZE: u32 = 1 << 24;

/// The most sweeps of a block per iteration ([`SimParams::block_sweeps`]).
pub const MAX_BLOCK_SWEEPS: u32 = 8;

/// Serde default of [`SimParams::block_sweeps`].
pub fn default_block_sweeps() -> u32 {
    1
}

impl SimParams {
    /// Checks `block_size`: at most [`MAX_BLOCK_SIZE`], only with what sweeps in blocks.
    pub(super) fn validate_blocks(&self) -> Result<()> {
        let sweeps = self.block_sweeps;
        if !(1..=MAX_BLOCK_SWEEPS).contains(&sweeps) {
            return Err(Error::param(
                "block_sweeps",
                format!("must be 1 to {MAX_BLOCK_SWEEPS}, got {sweeps}"),
            ));
        }
        if sweeps > 1 && self.block_size == 0 {
            return Err(Error::param(
                "block_sweeps",
                format!("{sweeps} sweeps per block need blocks: set block_size too"),
            ));
        }
        if self.block_size == 0 {
            return Ok(());
        }
        let refuse = |message: String| Err(Error::param("block_size", message));
        if self.block_size > MAX_BLOCK_SIZE {
            return refuse(format!(
                "must be at most {MAX_BLOCK_SIZE}, got {}",
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

    /// Checks that the blocks fit a GPU workgroup (the `vulkan` backend's plan asks): thread
    /// blocks, larger than [`MAX_WORKGROUP_BLOCK`], run on the `cpu` backends only.
    pub fn check_workgroup_blocks(&self) -> Result<()> {
        let size = self.block_size;
        if !self.solves_in_blocks() || size <= MAX_WORKGROUP_BLOCK {
            return Ok(());
        }
        Err(Error::param(
            "block_size",
            format!(
                "{size} makes thread blocks, which only the cpu backends run; on vulkan a \
                 block is one workgroup of at most {MAX_WORKGROUP_BLOCK} constraints (use a \
                 block_size of at most {MAX_WORKGROUP_BLOCK}, or backend cpu)"
            ),
        ))
    }
}
