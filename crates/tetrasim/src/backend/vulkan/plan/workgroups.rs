//! Workgroup sizes per pass, from the work of each dispatch: a colour group of a few
//! thousand tets in workgroups of 1024 keeps three multiprocessors of a 132-SM GPU busy and
//! the rest idle, so element-wise passes get the largest power of two that still gives
//! every multiprocessor of a large GPU a workgroup ([`MIN_WORKGROUPS`]), between
//! [`MIN_WORKGROUP_SIZE`] and the plan's size. Passes that reduce in shared memory keep
//! theirs (`volume_sum`'s partials are sized by the plan's, the global and Anderson passes
//! have [`super::GLOBAL_WORKGROUP`] at most, their chunk count a specialisation constant);
//! `--workgroup-size` sets every pass and skips this.

use super::{EnginePlan, PassPlan, MIN_WORKGROUPS, MIN_WORKGROUP_SIZE};
use crate::schedule::{BlockShape, PassKind, Schedule};

/// Most invocations a gather gives one node.
pub const MAX_GATHER_LANES: u32 = 8;

/// Invocations per node of `constraint_apply` on the gather path (its `LANES`, [`lanes`])
/// for the slots a node sums on average after the largest group of any sweep. A group of
/// the default's eight gives a horse node about 2 slots (1 lane); a sweep in one group
/// (Chebyshev, `gauss-seidel:1`) about 14 (4 lanes).
pub fn gather_lanes(schedule: &Schedule, nodes: u32, workgroup_size: u32) -> u32 {
    let slots = (schedule.sweeps.iter())
        .map(|w| w.corners() * u64::from(w.groups.iter().copied().max().unwrap_or(0)))
        .max()
        .unwrap_or(0);
    lanes(slots, nodes, workgroup_size)
}

/// Invocations per node of a gather of `slots` items over `nodes` nodes (common/lanes.glsl):
/// the largest power of two, at most [`MAX_GATHER_LANES`] and `workgroup_size`, that leaves
/// each lane at least two items of an average node. MINRES's node passes sum every entry of
/// their node's rows: about 25 on the horse (8 lanes).
pub fn lanes(slots: u64, nodes: u32, workgroup_size: u32) -> u32 {
    let per_lane_pair =
        (slots / (2 * u64::from(nodes.max(1)))).clamp(1, u64::from(u32::MAX)) as u32;
    let power = 1u32 << (31 - per_lane_pair.leading_zeros());
    power.min(MAX_GATHER_LANES).min(workgroup_size.max(1))
}

/// The workgroup of block Gauss-Seidel's pass (`volume#block`, one workgroup per block): an
/// invocation per tet of the largest block, rounded up to a multiple of 32 (a warp).
pub fn for_blocks(shape: BlockShape) -> u32 {
    shape.largest.max(1).next_multiple_of(32)
}

/// The size for a dispatch of `elements` invocations, at most `largest`.
pub fn for_elements(elements: u32, largest: u32) -> u32 {
    let wanted = (elements / MIN_WORKGROUPS).max(1);
    let power = 1u32 << (31 - wanted.leading_zeros());
    power.clamp(MIN_WORKGROUP_SIZE.min(largest), largest)
}

impl EnginePlan {
    /// Invocations of one dispatch of `pass` (a constraint pass of the gather path covers
    /// one group: its sweep's largest).
    pub fn elements_per_dispatch(&self, pass: &PassPlan) -> u32 {
        match (pass.per_group(), pass.stage.sweep) {
            (true, Some(index)) => (self.schedule.sweeps[index].groups.iter().copied())
                .max()
                .unwrap_or(0),
            _ => pass.elements,
        }
    }

    /// Gives every element-wise pass the workgroup size of [`for_elements`] (module doc).
    pub fn size_workgroups(mut self) -> Self {
        let largest = self.workgroup_size;
        let sizes: Vec<Option<u32>> = self
            .passes
            .iter()
            .map(|p| {
                (element_wise(p.stage.kind) && !p.solves_blocks())
                    .then(|| for_elements(self.elements_per_dispatch(p), largest))
            })
            .collect();
        for (pass, size) in self.passes.iter_mut().zip(sizes) {
            if let Some(size) = size {
                pass.workgroup_size = size;
            }
        }
        self
    }
}

/// Whether each invocation of `kind` works alone (no shared-memory reduction). MINRES's
/// passes but its setup keep the row passes' workgroup (at most 256): common/minres.glsl
/// declares the sums' shared arrays, and the node passes add their lanes'. The finite
/// elements' passes keep theirs (`elastic_workgroup`): their scalar passes add the node
/// passes' partials, one per workgroup.
fn element_wise(kind: PassKind) -> bool {
    !kind.is_elastic()
        && !matches!(
            kind,
            PassKind::GlobalVolumePrepare
                | PassKind::GlobalVolumeSum
                | PassKind::GlobalVolume
                | PassKind::Check
                | PassKind::VolumeSum
                | PassKind::Reactions
                | PassKind::ContactScan
                | PassKind::AndersonSum
                | PassKind::AndersonMix
                | PassKind::MinresRows
                | PassKind::MinresNodes
                | PassKind::MinresProduct
                | PassKind::MinresNext
                | PassKind::MinresFinish
                | PassKind::MinresForces
        )
}

#[cfg(test)]
mod tests {
    use super::for_elements;

    #[test]
    fn small_dispatches_get_small_workgroups_within_limits() {
        // A bunny colour group (~2300 tets) spreads over 36 workgroups of 64.
        assert_eq!(for_elements(2300, 1024), 64);
        // The horse's nodes (24k): 189 per SM wanted, 128 given.
        assert_eq!(for_elements(24_228, 1024), 128);
        // All of the horse's tets (Jacobi): 512.
        assert_eq!(for_elements(85_638, 1024), 512);
        // Millions of tets: the plan's size at most.
        assert_eq!(for_elements(4_000_000, 1024), 1024);
        assert_eq!(for_elements(4_000_000, 256), 256);
        // Tiny dispatches and tiny limits.
        assert_eq!(for_elements(10, 1024), 64);
        assert_eq!(for_elements(10, 32), 32);
    }
}
