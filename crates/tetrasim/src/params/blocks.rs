//! The checks of block Gauss-Seidel's key ([`SimParams::block_size`]).

use super::{SimParams, Solver, SpringKind};
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
    /// Sweeps of each block of implicit springs per iteration: `spring_block_sweeps` when
    /// it is set, `block_sweeps` otherwise (every other kind's; per kind:
    /// [`crate::model::ConstraintKind::block_sweeps`]). On the horse of issue 26 the volume
    /// constraints gain the most from a second sweep, and the springs are the larger sweep
    /// (docs/PHYSICS.md, "Thread blocks").
    pub fn spring_sweeps(&self) -> u32 {
        match self.spring_block_sweeps {
            0 => self.block_sweeps,
            s => s,
        }
    }

    /// Checks `block_size`: at most [`MAX_BLOCK_SIZE`], only with what sweeps in blocks.
    pub(super) fn validate_blocks(&self) -> Result<()> {
        let springs = self.spring_block_sweeps;
        for (key, sweeps, least) in [
            ("block_sweeps", self.block_sweeps, 1),
            ("spring_block_sweeps", springs, 0),
        ] {
            if !(least..=MAX_BLOCK_SWEEPS).contains(&sweeps) {
                return Err(Error::param(
                    key,
                    format!("must be {least} to {MAX_BLOCK_SWEEPS}, got {sweeps}"),
                ));
            }
            if sweeps > 1 && self.block_size == 0 {
                return Err(Error::param(
                    key,
                    format!("{sweeps} sweeps per block need blocks: set block_size too"),
                ));
            }
        }
        if springs > 0 && self.springs != SpringKind::Implicit {
            return Err(Error::param(
                "spring_block_sweeps",
                format!(
                    "sweeps the implicit springs' blocks; springs = {} are forces, not \
                     constraints (use springs = implicit, or spring_block_sweeps 0)",
                    self.springs.name()
                ),
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
