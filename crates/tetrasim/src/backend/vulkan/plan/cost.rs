//! A cost model of a frame on a named GPU, so that a plan can be judged without one: every
//! dispatch costs a fixed latency (launch, barrier, the first loads), plus the time its
//! busiest multiprocessor spends on its share of the elements (occupancy: a colour group
//! of 2300 tets in workgroups of 1024 leaves all but three multiprocessors idle) and on
//! the slots each node gathers, plus its bytes over the effective bandwidth, plus its float
//! atomics over the atomic throughput.
//! The constants of a GPU are fitted to its measured passes (docs/GPU.md, "A cost model");
//! `tests/gpu_cost_model.rs` checks the predictions against the measured frames.

use super::{EnginePlan, PassPlan, Variant};
use crate::schedule::PassKind;

/// The cost constants of one GPU.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpuProfile {
    /// The device name as `tetrasim info` prints it.
    pub name: &'static str,
    /// Multiprocessors (compute units).
    pub multiprocessors: u32,
    /// Fixed cost of one dependent dispatch [us].
    pub dispatch_us: f64,
    /// Cost of one constraint (a tet's or a spring's solve) on the busiest multiprocessor
    /// [ns].
    pub constraint_ns: f64,
    /// Cost of one element of the other passes (nodes, springs' forces) on the busiest
    /// multiprocessor [ns].
    pub element_ns: f64,
    /// Cost of one gathered slot (a constraint's force on a node, summed by
    /// `constraint_apply#gather`) on the busiest multiprocessor [ns]: the gather is a loop of
    /// dependent loads per node.
    pub slot_ns: f64,
    /// Effective memory bandwidth [bytes/s].
    pub bandwidth: f64,
    /// Float atomic additions per second, device-wide.
    pub atomics_per_s: f64,
    /// Invocations one multiprocessor holds at once (blocks of block Gauss-Seidel resident
    /// together).
    pub threads_per_multiprocessor: u32,
    /// One colour of a block of block Gauss-Seidel (`volume#block`): a tet's solve from
    /// shared memory and the workgroup's barrier [ns]. Assumed, not fitted: no GPU has run
    /// the pass yet (docs/GPU.md, "Block Gauss-Seidel").
    pub block_colour_ns: f64,
}

/// The GPUs with fitted constants. NVIDIA H200 (132 SMs, driver 580.159.04): fitted to the
/// pass times of bunny20k and horse86m, default solver and Jacobi, measured on 2026-11-26
/// (docs/data/gpu-nvidia-h200/).
pub const GPU_PROFILES: [GpuProfile; 1] = [GpuProfile {
    name: "NVIDIA H200",
    multiprocessors: 132,
    dispatch_us: 4.5,
    constraint_ns: 5.5,
    element_ns: 2.5,
    slot_ns: 5.3,
    bandwidth: 2.9e12,
    atomics_per_s: 80e9,
    threads_per_multiprocessor: 2048,
    block_colour_ns: 250.0,
}];

/// The fitted profile of the GPU named `name` (exact, as `tetrasim info` prints it).
pub fn profile(name: &str) -> Option<GpuProfile> {
    GPU_PROFILES.iter().copied().find(|p| p.name == name)
}

impl GpuProfile {
    /// Predicted time of one dispatch of `pass` in `plan` [us].
    pub fn dispatch_us(&self, plan: &EnginePlan, pass: &PassPlan) -> f64 {
        if let Some(shape) = plan.block_shape(pass) {
            // Blocks resident together run their colours side by side: the dispatch takes
            // the colours of its rounds of blocks one after another, once per block sweep.
            let wg = pass.workgroup_size.max(1);
            let resident = (self.threads_per_multiprocessor / wg).max(1) * self.multiprocessors;
            let rounds = shape.blocks.div_ceil(resident.max(1));
            let sweeps = plan.schedule.block_sweeps_of(pass.stage.kind);
            let colours = f64::from(rounds * sweeps) * f64::from(shape.colours);
            let bytes = plan.pass_bytes(pass) as f64;
            return self.dispatch_us
                + colours * self.block_colour_ns * 1e-3
                + bytes / self.bandwidth * 1e6;
        }
        let elements = plan.elements_per_dispatch(pass).max(1);
        let wg = pass.workgroup_size.max(1);
        let workgroups = elements.div_ceil(wg);
        let rounds = workgroups.div_ceil(self.multiprocessors.max(1));
        // Counted per node and per lane: a gather's lanes split a node's chain of slots, so
        // each lane sums `slots / lanes` of them (fitted to 2026-11-27-lanes/).
        let lanes = f64::from(pass.lanes());
        let busiest = f64::from(rounds) * f64::from(wg.min(elements)) / lanes;
        let bytes = plan.pass_bytes(pass) as f64;
        let per_element = match pass.stage.kind {
            PassKind::Volume | PassKind::Distance | PassKind::SpringConstraint => {
                self.constraint_ns
            }
            _ => self.element_ns,
        };
        self.dispatch_us
            + busiest * (per_element + gathered_slots(plan, pass) / lanes * self.slot_ns) * 1e-3
            + bytes / self.bandwidth * 1e6
            + atomics(pass, elements) / self.atomics_per_s * 1e6
    }

    /// Predicted GPU time of one frame of `plan` [ms].
    pub fn frame_ms(&self, plan: &EnginePlan) -> f64 {
        plan.passes
            .iter()
            .map(|p| f64::from(plan.runs_per_frame(p)) * self.dispatch_us(plan, p))
            .sum::<f64>()
            * 1e-3
    }
}

/// Slots one node of a gather pass sums per dispatch, on average over the groups: a
/// Gauss-Seidel colour group of the horse gives each node about 2, one group (Chebyshev)
/// about 14, MINRES's node passes every entry of the node's rows (about 20 on the horse).
fn gathered_slots(plan: &EnginePlan, pass: &PassPlan) -> f64 {
    // MINRES's node passes gather every entry of their node's rows (about the constraint
    // slots of all sweeps together).
    if matches!(
        pass.stage.kind,
        PassKind::MinresNodes | PassKind::MinresForces
    ) {
        return plan.minres_counts().map_or(0.0, |m| {
            m.entries() as f64 / f64::from(plan.counts.nodes.max(1))
        });
    }
    if pass.stage.kind != PassKind::ConstraintApply || !plan.schedule.gather {
        return 0.0;
    }
    let slots: u64 = plan
        .schedule
        .sweeps
        .iter()
        .map(|w| w.corners() * w.constraints())
        .sum();
    slots as f64 / f64::from(plan.group_count()) / f64::from(plan.counts.nodes.max(1))
}

/// Float atomic additions of one dispatch: three per corner of every element on the
/// atomic paths (a tet has four corners, a spring two).
fn atomics(pass: &PassPlan, elements: u32) -> f64 {
    if pass.variant != Variant::Atomics {
        return 0.0;
    }
    let corners = match pass.stage.kind {
        PassKind::Volume => 4.0,
        _ => 2.0,
    };
    3.0 * corners * f64::from(elements)
}
