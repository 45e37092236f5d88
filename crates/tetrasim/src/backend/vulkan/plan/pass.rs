//! The passes of a plan: how often each runs, which shader variant, what it binds.

use super::{Access, BufferId, PlanCounts};
use crate::backend::vulkan::pass_kind::PassKind;

/// How often a pass runs in a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Repeat {
    /// Once per time step.
    Substep,
    /// `iterations` times per time step and, within an iteration, once per constraint group:
    /// a pass of one sweep ([`PassPlan::sweep`]) for each of that sweep's groups, followed
    /// each time by the passes of no sweep (consecutive such passes repeat together).
    Iteration,
    /// Once per iteration, after its constraint groups (the global volume constraints).
    IterationEnd,
    /// Once per frame, after the last time step.
    Frame,
}

/// Which compiled variant of a pass's shader runs (build.rs, `// @variant`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// The shader has no variants.
    Plain,
    /// `#ext` or `#cas`, whichever float-atomic path the device uses.
    Atomics,
    /// A named variant, e.g. `gather`.
    Named(&'static str),
}

/// One planned compute pass.
#[derive(Debug, Clone, PartialEq)]
pub struct PassPlan {
    /// Which pass (its name in the timing report and its shader).
    pub kind: PassKind,
    /// Which of the shader's variants.
    pub variant: Variant,
    /// Specialisation constants from id 1 on (id 0 is the workgroup size).
    pub constants: Vec<u32>,
    /// Invocations per workgroup ([`super::EnginePlan::size_workgroups`]).
    pub workgroup_size: u32,
    /// Invocations (one per node, spring or tet; for a constraint pass of the gather path,
    /// all constraints, of which each dispatch covers one group's).
    pub elements: u32,
    /// Whether each dispatch covers only the current group's constraints.
    pub per_group: bool,
    /// The sweep ([`super::EnginePlan::sweeps`]) whose constraints the pass solves, for the
    /// constraint passes; `None` for the others (an [`Repeat::Iteration`] pass of no sweep
    /// follows every group of every sweep).
    pub sweep: Option<usize>,
    /// Bound buffers and how the pass uses them.
    pub bindings: Vec<(BufferId, Access)>,
    /// How often it runs.
    pub repeat: Repeat,
}

impl PassPlan {
    /// Name with its variant and specialisation, e.g. `constraint_apply#gather[floor]`.
    pub fn label(&self) -> String {
        let variant = match self.variant {
            Variant::Named(v) => format!("#{v}"),
            _ => String::new(),
        };
        let floor = match (self.kind.has_floor_constant(), self.constants.first()) {
            (true, Some(1)) => "[floor]",
            (true, Some(_)) => "[no floor]",
            _ => "",
        };
        format!("{}{variant}{floor}", self.name())
    }

    /// The pass's name (the shader's file stem), as timings and records print it.
    pub fn name(&self) -> &'static str {
        self.kind.name()
    }

    /// The shader module's key in [`crate::shaders::SHADERS`] for a device on `atomics`.
    pub fn shader_key(&self, atomics: &str) -> String {
        let shader = self.kind.shader();
        match self.variant {
            Variant::Plain => shader.to_string(),
            Variant::Atomics => format!("{shader}#{atomics}"),
            Variant::Named(v) => format!("{shader}#{v}"),
        }
    }
}

/// The `volume_sum` pass (per frame with metrics; on demand otherwise).
pub fn volume_sum_pass(counts: PlanCounts, workgroup_size: u32) -> PassPlan {
    PassPlan {
        kind: PassKind::VolumeSum,
        variant: Variant::Plain,
        constants: Vec::new(),
        workgroup_size,
        elements: counts.tets,
        per_group: false,
        sweep: None,
        bindings: vec![
            (BufferId::Positions, Access::Read),
            (BufferId::Tets, Access::Read),
            (BufferId::RestVolumes, Access::Read),
            (BufferId::Partials, Access::Write),
        ],
        repeat: Repeat::Frame,
    }
}
