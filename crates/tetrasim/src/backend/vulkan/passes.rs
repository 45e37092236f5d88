//! The passes of a frame and their recording, both driven by the [`EnginePlan`]:
//!
//! ```text
//! for each substep:
//!     (spring_scatter | spring_gather)      F += explicit spring forces (F = m g before;
//!                                           no spring force pass with implicit springs)
//!     (spring_warm_start)                   warm-started implicit springs: F += the
//!                                           stored multipliers' forces at x(t)
//!     (global_volume_prepare)               C_g, A and the surface gradients at x(t)
//!     iterations x sweeps x groups x        (implicit springs, then the method's
//!                                           constraints; one group for Jacobi, the colour
//!                                           groups for Gauss-Seidel)
//!        (spring_constraint | distance      the group's constraint forces from x(t),
//!         | volume,                         v(t), F: atomic sums, or per-constraint slots
//!         constraint_apply)                 F += omega * weight * (sum | gathered slots);
//!                                           then the floor's solve
//!     (global_volume)                       per iteration, after the groups (one
//!                                           workgroup per object)
//!     integrate                             v, x, floor (specialised away without one); F = m g
//!                                           (with colliders: their solve after the floor's,
//!                                           in constraint_apply and global_volume too,
//!                                           reading the substep's row of the poses the
//!                                           host wrote before the submit)
//! check                                     divergence flags + first bad node -> status
//! (contact_measure)                         with colliders or body contact and per-frame
//!                                           metrics: the frame's contact counts and
//!                                           deepest penetration -> the status's contact
//!                                           words (zeroed at the frame's start)
//! volume_sum (with per-frame metrics)       the frame's volume metric
//! copy status (+ partials) to the host      into the frame slot's own host-visible
//!                                           buffers, read after the slot's fence
//! ```
//! Each dispatch sits in a debug label region named for its pass (so RenderDoc and Nsight
//! captures name it) and is followed by a timestamp and a barrier on the buffers it writes.

use std::sync::Arc;

use ash::vk;

use super::buffers::SimBuffers;
use super::plan::{
    volume_sum_pass, BufferId, EnginePlan, PassPlan, CONTACT_STATUS_BYTES, STATUS_BYTES,
};
use crate::gpu::commands::{barrier, memory_barrier, Access};
use crate::gpu::layout::{phase, PushConstants};
use crate::gpu::{AtomicsPath, Buffer, Context, Kernel, Timer};
use crate::{Error, Result};

/// A kernel with its plan entry.
pub(crate) struct Pass {
    /// What the plan says about it.
    pub plan: PassPlan,
    kernel: Kernel,
}

/// Every pass of the plan plus the on-demand `volume_sum`, each on its own binding layout
/// and descriptor set (held by its kernel) that points every binding its stage lists at
/// its simulation buffer.
pub(crate) struct Passes {
    /// In the plan's order.
    pub frame: Vec<Pass>,
    /// `volume_sum` for measurements outside the frame.
    pub volume_sum: Pass,
}

impl Pass {
    /// The pipeline of `plan` on its own descriptor set, which points each binding its stage
    /// lists at its simulation buffer in `b`. A set per pass, not one for every pass: the
    /// union of a rich scene's arrays (global volume, colliders, Anderson, MINRES) passes
    /// the 32 storage buffers per stage lavapipe allows, and lavapipe crashed on it.
    fn new(
        ctx: &Arc<Context>,
        plan: &PassPlan,
        atomics: AtomicsPath,
        b: &SimBuffers,
    ) -> Result<Self> {
        let mut bound: Vec<(u32, &Buffer)> = Vec::new();
        for (id, _) in &plan.stage.bindings {
            let buffer = b.get(*id).ok_or_else(|| {
                Error::Gpu(format!(
                    "pass `{}` binds buffer `{}`, which the plan does not build",
                    plan.name(),
                    id.name()
                ))
            })?;
            if !bound.iter().any(|(n, _)| *n == id.binding()) {
                bound.push((id.binding(), buffer));
            }
        }
        bound.sort_by_key(|(n, _)| *n);
        let limit = ctx.info().max_storage_buffers;
        if bound.len() > limit as usize {
            return Err(Error::Gpu(format!(
                "pass `{}` binds {} storage buffers; the device allows {limit} per pass \
                 (maxPerStageDescriptorStorageBuffers)",
                plan.label(),
                bound.len()
            )));
        }
        let numbers: Vec<u32> = bound.iter().map(|(n, _)| *n).collect();
        let binding = Kernel::binding_layout(ctx, plan.name(), &numbers)?;
        binding.write(&bound);
        let key = plan.shader_key(atomics.name());
        let kernel = Kernel::with_constants(
            ctx,
            plan.name(),
            &key,
            &binding,
            plan.workgroup_size,
            &plan.constants,
        )?;
        kernel.check_elements(plan.elements)?;
        Ok(Pass {
            plan: plan.clone(),
            kernel,
        })
    }

    /// The buffers this pass writes (a barrier follows it).
    fn writes<'b>(&self, b: &'b SimBuffers) -> Vec<&'b Buffer> {
        (self.plan.stage.writes())
            .filter_map(|id| b.get(id))
            .collect()
    }
}

impl Passes {
    /// Builds the pipelines of `plan` with the given atomic path and workgroup size, each on
    /// its own descriptor set ([`Pass::new`]).
    pub fn new(
        ctx: &Arc<Context>,
        plan: &EnginePlan,
        atomics: AtomicsPath,
        b: &SimBuffers,
    ) -> Result<Self> {
        let volume_sum_plan = volume_sum_pass(plan.counts, plan.workgroup_size);
        let frame = plan
            .passes
            .iter()
            .map(|p| Pass::new(ctx, p, atomics, b))
            .collect::<Result<Vec<_>>>()?;
        let volume_sum = Pass::new(ctx, &volume_sum_plan, atomics, b)?;
        Ok(Passes { frame, volume_sum })
    }
}

/// Records passes into one command buffer: dispatch, timestamp, barrier.
pub(crate) struct Recorder<'a> {
    pub ctx: &'a Context,
    pub cmd: vk::CommandBuffer,
    pub push: &'a PushConstants,
    pub timer: Option<&'a mut Timer>,
}

impl Recorder<'_> {
    fn pass(&mut self, pass: &Pass, b: &SimBuffers) -> Result<()> {
        self.dispatch(pass, b, self.push, pass.plan.elements)
    }

    fn dispatch(
        &mut self,
        pass: &Pass,
        b: &SimBuffers,
        push: &PushConstants,
        elements: u32,
    ) -> Result<()> {
        self.ctx.begin_label(self.cmd, pass.plan.name());
        pass.kernel.record(self.cmd, push, elements);
        self.ctx.end_label(self.cmd);
        if let Some(timer) = self.timer.as_deref_mut() {
            timer.record_mark(self.cmd, pass.plan.name())?;
        }
        barrier(
            self.ctx,
            self.cmd,
            &pass.writes(b),
            Access::COMPUTE,
            Access::COMPUTE,
        );
        Ok(())
    }

    /// One time step: the schedule's dispatches ([`crate::schedule::Schedule::step`]) in
    /// order. A dispatch of a constraint group carries the group's index (over all sweeps),
    /// its range within the sweep, the sweep's offsets and the iteration's Chebyshev weight
    /// in the push constants; a per-group pass dispatches only the group's constraints.
    /// `step_push` is the step's block (its row of the collider poses).
    fn record_step(
        &mut self,
        plan: &EnginePlan,
        p: &Passes,
        b: &SimBuffers,
        step_push: &PushConstants,
    ) -> Result<()> {
        let schedule = &plan.schedule;
        for dispatch in schedule.step() {
            let pass = &p.frame[dispatch.stage];
            let step_push = &PushConstants {
                phase: phase::of(dispatch.solve),
                ..*step_push
            };
            let Some(at) = dispatch.group else {
                // The stages that end an iteration (Anderson's) read its index.
                let push = PushConstants {
                    iteration: dispatch.iteration.unwrap_or(0),
                    ..*step_push
                };
                self.dispatch(pass, b, &push, pass.plan.elements)?;
                continue;
            };
            let iteration = dispatch.iteration.unwrap_or(0);
            let offsets = plan.sweep_offsets(at.sweep);
            let push = PushConstants {
                group: offsets.group + at.group as u32,
                group_first: at.first,
                group_count: at.count,
                member_first: offsets.member,
                slot_first: offsets.slot,
                block_first: offsets.block,
                chebyshev_weight: schedule.chebyshev_weight(iteration) as f32,
                iteration,
                ..*step_push
            };
            let elements = match pass.plan.per_group() {
                true => at.count,
                false => pass.plan.elements,
            };
            self.dispatch(pass, b, &push, elements)?;
        }
        Ok(())
    }

    /// Copies `from` into the host-visible `to` (whole `to`), with the barriers around it.
    fn copy_to_host(&mut self, from: &Buffer, to: &Buffer) {
        barrier(
            self.ctx,
            self.cmd,
            &[from],
            Access::COMPUTE,
            Access::TRANSFER_READ,
        );
        let region = [vk::BufferCopy::default().size(from.size.min(to.size))];
        // SAFETY: `cmd` is recording; both buffers are alive and at least `size` long.
        unsafe {
            self.ctx
                .device()
                .cmd_copy_buffer(self.cmd, from.raw, to.raw, &region)
        };
        barrier(
            self.ctx,
            self.cmd,
            &[to],
            Access::TRANSFER_WRITE,
            Access::HOST_READ,
        );
    }

    /// Zeroes the status's contact words (after its divergence words), which
    /// `contact_measure` adds into, once the copies of earlier frames have read them.
    fn zero_contact_words(&mut self, status: &Buffer) {
        let start = STATUS_BYTES;
        memory_barrier(
            self.ctx,
            self.cmd,
            Access::TRANSFER_READ,
            Access::TRANSFER_WRITE,
        );
        // SAFETY: `cmd` is recording outside a render pass; `status` is alive, a transfer
        // destination and `CONTACT_STATUS_BYTES` long; offset and size are multiples of 4.
        unsafe {
            self.ctx.device().cmd_fill_buffer(
                self.cmd,
                status.raw,
                start,
                CONTACT_STATUS_BYTES - start,
                0,
            )
        };
        barrier(
            self.ctx,
            self.cmd,
            &[status],
            Access::TRANSFER_WRITE,
            Access::COMPUTE,
        );
    }

    /// `volume_sum` alone and the copy of its partials into `readback`.
    pub fn record_volume_sum(
        &mut self,
        p: &Passes,
        b: &SimBuffers,
        readback: &Buffer,
    ) -> Result<()> {
        self.pass(&p.volume_sum, b)?;
        self.copy_to_host(&b.partials, readback);
        Ok(())
    }

    /// A whole frame in frame slot `slot`: `substeps` steps (each reading its row of the
    /// slot's collider poses), the frame's passes, the host copies of the
    /// divergence status into `status_readback` and, with per-frame metrics, of the volume
    /// and reaction partials into `readbacks`. It starts with an execution barrier after every
    /// earlier copy, so a frame submitted right behind another (frames in flight) rewrites
    /// the status and the partials only once the earlier frame's copies have read them.
    pub fn record_frame(
        &mut self,
        plan: &EnginePlan,
        slot: u32,
        p: &Passes,
        b: &SimBuffers,
        status_readback: &Buffer,
        readbacks: [Option<&Buffer>; 2],
    ) -> Result<()> {
        memory_barrier(self.ctx, self.cmd, Access::TRANSFER_READ, Access::COMPUTE);
        if plan.measures_contact() {
            self.zero_contact_words(&b.status);
        }
        if let Some(timer) = self.timer.as_deref_mut() {
            timer.record_start(self.cmd);
        }
        let substeps = plan.schedule.substeps;
        let mut push = *self.push;
        for substep in 0..substeps {
            push = PushConstants {
                collider_first: (slot * substeps + substep) * plan.counts.colliders,
                step_row: slot * substeps + substep,
                grab_first: (slot * substeps + substep) * plan.counts.grabbed,
                ..*self.push
            };
            self.record_step(plan, p, b, &push)?;
        }
        // The frame's passes read the last step's rows (contact_measure: the colliders'
        // poses at the frame's end).
        for stage in plan.schedule.frame_end() {
            let pass = &p.frame[stage];
            self.dispatch(pass, b, &push, pass.plan.elements)?;
        }
        self.copy_to_host(&b.status, status_readback);
        let [partials, reactions] = readbacks;
        if let Some(readback) = partials {
            self.copy_to_host(&b.partials, readback);
        }
        if let (Some(readback), Some(sums)) = (reactions, b.get(BufferId::ReactionPartials)) {
            self.copy_to_host(sums, readback);
        }
        Ok(())
    }
}
