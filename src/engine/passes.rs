//! The passes of one time step and their recording. A frame is recorded once:
//!
//! ```text
//! for each substep:
//!     spring_scatter | spring_gather        F = m g + spring forces
//!     iterations x (distance | volume,      constraint sums from x(t), v(t), F
//!                   constraint_apply)       F += omega * weight * sum; sum = 0
//!     integrate                             v, x, floor; F = m g
//! volume_sum + copy to the host             the frame's volume metric
//! ```
//! Each pass is followed by a timestamp and a barrier on the buffers it wrote.

use std::sync::Arc;

use ash::vk;

use super::buffers::SimBuffers;
use crate::gpu::commands::{barrier, Access};
use crate::gpu::layout::{binding, PushConstants};
use crate::gpu::{AtomicsPath, Buffer, Context, Kernel, Timer};
use crate::params::Method;
use crate::Result;

/// A kernel with the pass name used in the timing report and its element count.
pub(crate) struct Pass {
    /// Name in the timing report (the shader's file stem).
    pub name: &'static str,
    kernel: Kernel,
    elements: u32,
}

/// Every pass the method needs, bound to the simulation buffers.
pub(crate) struct Passes {
    /// `spring_scatter` (mss, distance, volume) or `spring_gather` (mss-node).
    pub springs: Pass,
    /// `distance` or `volume`, with `constraint_apply`.
    pub constraint: Option<(Pass, Pass)>,
    /// `integrate`.
    pub integrate: Pass,
    /// `volume_sum`.
    pub volume_sum: Pass,
}

/// Element counts of the model.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Counts {
    pub nodes: u32,
    pub springs: u32,
    pub tets: u32,
}

impl Passes {
    /// Builds the pipelines of `method` with the given atomic path and workgroup size.
    pub fn new(
        ctx: &Arc<Context>,
        method: Method,
        atomics: AtomicsPath,
        wg: u32,
        b: &SimBuffers,
        n: Counts,
    ) -> Result<Self> {
        let variant = |file: &str| format!("passes/{file}.comp#{}", atomics.name());
        let pass = |name: &'static str,
                    key: String,
                    bindings: &[(u32, &Buffer)],
                    elements: u32|
         -> Result<Pass> {
            let kernel = Kernel::new(ctx, name, &key, bindings, wg)?;
            kernel.check_elements(elements)?;
            Ok(Pass {
                name,
                kernel,
                elements,
            })
        };
        let state = [
            (binding::POSITIONS, &b.positions),
            (binding::VELOCITIES, &b.velocities),
        ];
        let springs = match (method, &b.node_springs) {
            (Method::MssNode, Some((offsets, items))) => pass(
                "spring_gather",
                "passes/spring_gather.comp".into(),
                &[
                    state[0],
                    state[1],
                    (binding::SPRINGS, &b.springs),
                    (binding::NODE_SPRING_OFFSETS, offsets),
                    (binding::NODE_SPRING_ITEMS, items),
                    (binding::FORCES, &b.forces),
                ],
                n.nodes,
            )?,
            _ => pass(
                "spring_scatter",
                variant("spring_scatter"),
                &[
                    state[0],
                    state[1],
                    (binding::SPRINGS, &b.springs),
                    (binding::FORCES, &b.forces),
                ],
                n.springs,
            )?,
        };
        let constraint = match (method, &b.constraint_sum, &b.weights) {
            (Method::Distance | Method::Volume, Some(sum), Some(weights)) => {
                let solve = match (method, &b.rest_volumes) {
                    (Method::Volume, Some(rest)) => pass(
                        "volume",
                        variant("volume"),
                        &[
                            state[0],
                            state[1],
                            (binding::FORCES, &b.forces),
                            (binding::TETS, &b.tets),
                            (binding::REST_VOLUMES, rest),
                            (binding::CONSTRAINT_SUM, sum),
                        ],
                        n.tets,
                    )?,
                    _ => pass(
                        "distance",
                        variant("distance"),
                        &[
                            state[0],
                            state[1],
                            (binding::FORCES, &b.forces),
                            (binding::SPRINGS, &b.springs),
                            (binding::CONSTRAINT_SUM, sum),
                        ],
                        n.springs,
                    )?,
                };
                let apply = pass(
                    "constraint_apply",
                    "passes/constraint_apply.comp".into(),
                    &[
                        (binding::FORCES, &b.forces),
                        (binding::CONSTRAINT_SUM, sum),
                        (binding::CONSTRAINT_WEIGHT, weights),
                    ],
                    n.nodes,
                )?;
                Some((solve, apply))
            }
            _ => None,
        };
        let integrate = pass(
            "integrate",
            "passes/integrate.comp".into(),
            &[state[0], state[1], (binding::FORCES, &b.forces)],
            n.nodes,
        )?;
        let volume_sum = pass(
            "volume_sum",
            "passes/volume_sum.comp".into(),
            &[
                (binding::POSITIONS, &b.positions),
                (binding::TETS, &b.tets),
                (binding::VOLUME_PARTIALS, &b.partials),
            ],
            n.tets,
        )?;
        Ok(Passes {
            springs,
            constraint,
            integrate,
            volume_sum,
        })
    }

    /// Dispatches of one frame (the timestamp count).
    pub fn dispatches_per_frame(&self, substeps: u32, iterations: u32) -> u32 {
        let per_step = 2 + if self.constraint.is_some() {
            2 * iterations
        } else {
            0
        };
        substeps * per_step + 1
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
    fn pass(&mut self, pass: &Pass, writes: &[&Buffer]) -> Result<()> {
        pass.kernel.record(self.cmd, self.push, pass.elements);
        if let Some(timer) = self.timer.as_deref_mut() {
            timer.record_mark(self.cmd, pass.name)?;
        }
        barrier(self.ctx, self.cmd, writes, Access::COMPUTE, Access::COMPUTE);
        Ok(())
    }

    /// `spring_scatter` or `spring_gather`: F = m g + spring forces.
    pub fn record_springs(&mut self, p: &Passes, b: &SimBuffers) -> Result<()> {
        self.pass(&p.springs, &[&b.forces])
    }

    /// One Jacobi iteration: the constraint pass, then `constraint_apply`.
    pub fn record_constraint_iteration(&mut self, p: &Passes, b: &SimBuffers) -> Result<()> {
        if let (Some((solve, apply)), Some(sum)) = (&p.constraint, &b.constraint_sum) {
            self.pass(solve, &[sum])?;
            self.pass(apply, &[&b.forces, sum])?;
        }
        Ok(())
    }

    /// `integrate`: velocities, positions, floor, force reset.
    pub fn record_integrate(&mut self, p: &Passes, b: &SimBuffers) -> Result<()> {
        self.pass(&p.integrate, &[&b.positions, &b.velocities, &b.forces])
    }

    /// One time step.
    pub fn record_step(&mut self, p: &Passes, b: &SimBuffers, iterations: u32) -> Result<()> {
        self.record_springs(p, b)?;
        if p.constraint.is_some() {
            for _ in 0..iterations {
                self.record_constraint_iteration(p, b)?;
            }
        }
        self.record_integrate(p, b)
    }

    /// `volume_sum`, then the copy of its partials to the host-visible buffer.
    pub fn record_volume_sum(&mut self, p: &Passes, b: &SimBuffers) -> Result<()> {
        p.volume_sum
            .kernel
            .record(self.cmd, self.push, p.volume_sum.elements);
        if let Some(timer) = self.timer.as_deref_mut() {
            timer.record_mark(self.cmd, p.volume_sum.name)?;
        }
        barrier(
            self.ctx,
            self.cmd,
            &[&b.partials],
            Access::COMPUTE,
            Access::TRANSFER_READ,
        );
        let region =
            [vk::BufferCopy::default().size(b.partials.size.min(b.partials_readback.size))];
        // SAFETY: `cmd` is recording; both buffers are alive and at least `size` long.
        unsafe {
            self.ctx.device().cmd_copy_buffer(
                self.cmd,
                b.partials.raw,
                b.partials_readback.raw,
                &region,
            )
        };
        barrier(
            self.ctx,
            self.cmd,
            &[&b.partials_readback],
            Access::TRANSFER_WRITE,
            Access::HOST_READ,
        );
        Ok(())
    }

    /// A whole frame: `substeps` steps, then the volume metric.
    pub fn record_frame(
        &mut self,
        p: &Passes,
        b: &SimBuffers,
        substeps: u32,
        iterations: u32,
    ) -> Result<()> {
        if let Some(timer) = self.timer.as_deref_mut() {
            timer.record_start(self.cmd);
        }
        for _ in 0..substeps {
            self.record_step(p, b, iterations)?;
        }
        self.record_volume_sum(p, b)
    }
}
