//! The passes of a plan: how often each runs, which shader variant, what it binds.

use super::PlanCounts;
use crate::schedule::{volume_sum, Domain, PassKind, Stage};

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

/// One planned compute pass: a stage of the schedule as the Vulkan engine runs it.
#[derive(Debug, Clone, PartialEq)]
pub struct PassPlan {
    /// The stage it runs (kind, repetition, domain, sweep, bindings).
    pub stage: Stage,
    /// Which of the shader's variants.
    pub variant: Variant,
    /// Specialisation constants from id 1 on (id 0 is the workgroup size).
    pub constants: Vec<u32>,
    /// Invocations per workgroup ([`super::EnginePlan::size_workgroups`]).
    pub workgroup_size: u32,
    /// Invocations (one per node, spring or tet; for a constraint pass of the gather path,
    /// all constraints, of which each dispatch covers one group's).
    pub elements: u32,
}

impl PassPlan {
    /// Name with its variant and specialisation, e.g. `constraint_apply#gather[floor]`.
    pub fn label(&self) -> String {
        let variant = match self.variant {
            Variant::Named(v) => format!("#{v}"),
            _ => String::new(),
        };
        let floor = match (self.stage.kind.has_floor_constant(), self.constants.first()) {
            (true, Some(1)) => "[floor]",
            (true, Some(_)) => "[no floor]",
            _ => "",
        };
        format!("{}{variant}{floor}", self.name())
    }

    /// Invocations per node: the `LANES` (constant 4, common/lanes.glsl) of
    /// `constraint_apply#gather` ([`super::workgroups::gather_lanes`]) and of MINRES's node
    /// passes, 1 for every other pass.
    pub fn lanes(&self) -> u32 {
        match (self.stage.kind, self.variant) {
            (PassKind::ConstraintApply, Variant::Named(v)) if v.starts_with("gather") => {
                self.constants.get(3).copied().unwrap_or(1)
            }
            (PassKind::MinresNodes | PassKind::MinresForces, _) => {
                self.constants.get(3).copied().unwrap_or(1).max(1)
            }
            _ => 1,
        }
    }

    /// Whether each dispatch covers only the current group's constraints (block
    /// Gauss-Seidel's pass covers its blocks, one workgroup each).
    pub fn per_group(&self) -> bool {
        self.stage.domain == Domain::Group && !self.solves_blocks()
    }

    /// Whether it is block Gauss-Seidel's pass (`volume#block`): its workgroup size is its
    /// blocks', whatever the plan's.
    pub fn solves_blocks(&self) -> bool {
        self.variant == Variant::Named("block")
    }

    /// The pass's name (the shader's file stem), as timings and records print it.
    pub fn name(&self) -> &'static str {
        self.stage.kind.name()
    }

    /// The shader module's key in [`crate::shaders::SHADERS`] for a device on `atomics`.
    pub fn shader_key(&self, atomics: &str) -> String {
        let shader = self.stage.kind.shader();
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
        stage: volume_sum(),
        variant: Variant::Plain,
        constants: Vec::new(),
        workgroup_size,
        elements: counts.tets,
    }
}
