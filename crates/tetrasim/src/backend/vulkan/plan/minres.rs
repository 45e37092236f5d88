//! MINRES's sizes in a plan (docs/GPU.md, "MINRES"): its rows and entries
//! ([`crate::schedule::MinresRowKinds`]), its buffers and its passes' constants.

use super::{GlobalCounts, PlanCounts};
use crate::schedule::{BufferId, MinresRowKinds, Schedule};

/// Floats per row of MINRES's vectors (glsl/common/minres.glsl, `P_*`).
pub const MINRES_PLANES: u64 = 10;

/// Bytes of one iteration's recurrence in `MinresState`.
pub const MINRES_STATE_BYTES: u64 = 64;

/// The sizes of MINRES's rows for one plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MinresCounts {
    /// Which segments the rows have.
    pub kinds: MinresRowKinds,
    /// Rows of implicit springs (one per spring, or 0).
    pub springs: u32,
    /// Rows of distance constraints (one per spring, or 0).
    pub distances: u32,
    /// Rows of volume constraints (one per tet, or 0).
    pub tets: u32,
    /// Rows of global volume constraints (one per object, or 0).
    pub objects: u32,
    /// Surface nodes of every object (the global rows' entries).
    pub surface: u32,
    /// Chunks per object of the global volume passes.
    pub chunks: u32,
    /// Invocations per workgroup of the row passes (a power of two, as their sums need).
    pub workgroup: u32,
}

impl MinresCounts {
    /// MINRES's sizes in a plan of `schedule` for a model of `counts` with the global volume
    /// constraints of `global` (when solved), row passes of `workgroup` invocations; `None`
    /// without MINRES.
    pub fn of(
        schedule: &Schedule,
        counts: PlanCounts,
        global: Option<GlobalCounts>,
        workgroup: u32,
    ) -> Option<Self> {
        if schedule.minres == 0 || schedule.sweeps.is_empty() {
            return None;
        }
        let kinds = MinresRowKinds::of(&schedule.sweeps, global.is_some());
        let on = |yes: bool, n: u32| if yes { n } else { 0 };
        Some(MinresCounts {
            kinds,
            springs: on(kinds.springs, counts.springs),
            distances: on(kinds.distances, counts.springs),
            tets: on(kinds.volumes, counts.tets),
            objects: global.map_or(0, |g| g.objects),
            surface: global.map_or(0, |g| g.nodes),
            chunks: global.map_or(1, |g| g.chunks(workgroup)),
            workgroup,
        })
    }

    /// Rows with an invocation each (every row but the global ones).
    pub fn fixed_rows(&self) -> u32 {
        self.springs + self.distances + self.tets
    }

    /// Every row.
    pub fn rows(&self) -> u32 {
        self.fixed_rows() + self.objects
    }

    /// Every entry: two per spring row, four per tet, one per surface node.
    pub fn entries(&self) -> u64 {
        2 * u64::from(self.springs + self.distances)
            + 4 * u64::from(self.tets)
            + u64::from(self.surface)
    }

    /// Workgroups of a row pass: the fixed rows', then one per object. Each leaves its
    /// partial of the pass's dot product, and a counter follows them.
    pub fn workgroups(&self) -> u32 {
        self.fixed_rows().div_ceil(self.workgroup.max(1)) + self.objects
    }

    /// The specialisation constants from id 5 on (glsl/common/minres.glsl).
    pub fn constants(&self, iterations: u32) -> [u32; 6] {
        [
            self.springs,
            self.distances,
            self.tets,
            self.objects,
            iterations,
            self.chunks,
        ]
    }

    /// MINRES's buffers and their bytes for `nodes` nodes and `iterations` iterations.
    pub fn buffers(&self, nodes: u32, iterations: u32) -> [(BufferId, u64); 6] {
        let (n, e) = (u64::from(nodes), self.entries());
        let transpose = (n + 1) + 3 * e + u64::from(self.objects) + 1;
        [
            (BufferId::MinresTranspose, 4 * transpose),
            (BufferId::MinresGrads, 16 * e),
            (
                BufferId::MinresVectors,
                4 * MINRES_PLANES * u64::from(self.rows()),
            ),
            (BufferId::MinresNodeVectors, 32 * n),
            (BufferId::MinresSums, 4 * (u64::from(self.workgroups()) + 1)),
            (
                BufferId::MinresState,
                MINRES_STATE_BYTES * (u64::from(iterations) + 1),
            ),
        ]
    }

    /// The `minres_finish` variant: the segments whose multipliers it adds to.
    pub fn finish_variant(&self) -> &'static str {
        match (self.kinds.springs, self.kinds.volumes) {
            (true, true) => "sv",
            (true, false) => "s",
            (false, true) => "v",
            (false, false) => "plain",
        }
    }
}
