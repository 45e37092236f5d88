//! The `vulkan` backend: the paper's solver in compute shaders.
//!
//! The model is uploaded once; only the buffers and pipelines the method needs are built;
//! the frame's command buffer (substeps x passes, barriers, timestamps, the volume metric)
//! is recorded once and replayed by [`Backend::step_frame`], which submits it and waits on
//! its fence. [`Backend::volume`] then only reads the few volume partials the frame copied
//! to host-visible memory; only [`Backend::state`] reads back every node.

mod buffers;
pub mod pass_kind;
mod passes;
pub mod plan;

use std::sync::Arc;

use glam::DVec3;

use crate::backend::{Backend, Divergence, GpuReport, State, VolumeSample};
use crate::error::{Error, Result};
use crate::gpu::commands::{self, Access, Recorded};
use crate::gpu::layout::{PushConstants, VolumePartial};
use crate::gpu::{
    AtomicsPath, Buffer, Context, ContextOptions, DeviceInfo, DeviceSelector, PassTime, Timer,
};
use crate::model::{GlobalVolume, Model, Sweep};
use crate::params::SimParams;
use buffers::SimBuffers;
use passes::{Passes, Recorder};
use plan::{EnginePlan, GlobalCounts, PlanCounts, SweepPlan};

/// The model's constraint sweeps and global volume constraints under `params` (what the
/// plan and the buffers are built from).
fn constraint_data(model: &Model, params: &SimParams) -> (Vec<Sweep>, Option<GlobalVolume>) {
    let sweeps = model.constraint_sweeps(params);
    let global = params
        .solves_global_volume()
        .then(|| GlobalVolume::new(model));
    (sweeps, global)
}

/// GPU choices that are not physics: which device, validation, workgroup size.
#[derive(Debug, Clone, Default)]
pub struct EngineOptions {
    /// Which device to use (`--device NAME|INDEX`).
    pub device: DeviceSelector,
    /// Enable the Khronos validation layer and record its messages.
    pub validation: bool,
    /// Invocations per workgroup (a power of two); `None`: from the device limits.
    pub workgroup_size: Option<u32>,
    /// `false` (default): every frame measures the volume (`volume_sum` and the copy of
    /// its partials); `true`: only when [`Backend::volume`] asks, so a frame reads back
    /// nothing but the 16-byte divergence status.
    pub volume_on_demand: bool,
    /// `false` (default): a GPU timestamp after every pass ([`VulkanBackend::pass_times`]);
    /// `true`: none. A timestamp costs about 0.06 ms per pass on lavapipe (10 ms of a
    /// 30 ms bunny frame with the default solver's 175 passes), so wall-clock benchmarks run
    /// untimed and measure the pass breakdown in a separate run.
    pub untimed: bool,
}

/// The Vulkan compute backend. Field order is drop order: GPU work is waited for in
/// `Drop`, then command buffers, pipelines and buffers go, and the context last.
pub struct VulkanBackend {
    frame: Recorded,
    measure: Recorded,
    timer: Option<Timer>,
    /// Never read after recording, but the recorded frame uses its pipelines.
    #[allow(dead_code)]
    passes: Passes,
    readback: Option<(Buffer, Buffer)>,
    buffers: SimBuffers,
    plan: EnginePlan,
    /// Method name and likely cause, for divergence reports.
    method: &'static str,
    likely: String,
    atomics: AtomicsPath,
    workgroup_size: u32,
    counts: PlanCounts,
    /// Whether `partials_readback` holds the volume of the current positions.
    partials_fresh: bool,
    frames: u32,
    /// The model's inverse masses and masses, the `w` of the uploaded positions and
    /// velocities ([`Backend::set_state`]).
    inv_mass: Vec<f64>,
    mass: Vec<f64>,
    ctx: Arc<Context>,
}

impl VulkanBackend {
    /// Creates a context per `options` and the backend on it.
    pub fn new(model: &Model, params: &SimParams, options: &EngineOptions) -> Result<Self> {
        let ctx = Arc::new(Context::new(&ContextOptions {
            device: options.device.clone(),
            validation: options.validation,
        })?);
        Self::with_context_and_options(ctx, model, params, options)
    }

    /// The backend on an existing context (several backends may share one).
    pub fn with_context(
        ctx: Arc<Context>,
        model: &Model,
        params: &SimParams,
        workgroup_size: Option<u32>,
    ) -> Result<Self> {
        let options = EngineOptions {
            workgroup_size,
            ..Default::default()
        };
        Self::with_context_and_options(ctx, model, params, &options)
    }

    /// The plan of `model` under `params` on a device with `info` (what [`Self::new`]
    /// would build; `tetrasim plan` prints it).
    pub fn plan_for(
        info: &DeviceInfo,
        model: &Model,
        params: &SimParams,
        options: &EngineOptions,
    ) -> Result<EnginePlan> {
        let (sweeps, global) = constraint_data(model, params);
        Self::plan_with(info, model, params, options, &sweeps, global.as_ref())
    }

    /// [`Self::plan_for`] with the model's constraint sweeps and global volume constraints
    /// already computed.
    fn plan_with(
        info: &DeviceInfo,
        model: &Model,
        params: &SimParams,
        options: &EngineOptions,
        sweeps: &[Sweep],
        global: Option<&GlobalVolume>,
    ) -> Result<EnginePlan> {
        let wg = options
            .workgroup_size
            .unwrap_or_else(|| info.default_workgroup_size());
        info.check_workgroup_size(wg)?;
        Ok(EnginePlan::new(
            PlanCounts::of(model)?,
            params,
            wg,
            !options.volume_on_demand,
            &sweeps.iter().map(SweepPlan::of).collect::<Vec<_>>(),
            global.map(GlobalCounts::of),
        ))
    }

    /// The backend on an existing context with all options but the device.
    pub fn with_context_and_options(
        ctx: Arc<Context>,
        model: &Model,
        params: &SimParams,
        options: &EngineOptions,
    ) -> Result<Self> {
        params.validate()?;
        let info = ctx.info();
        let atomics = info.atomics_path(params.atomics)?;
        let (sweeps, global) = constraint_data(model, params);
        let plan = Self::plan_with(info, model, params, options, &sweeps, global.as_ref())?;
        let wg = plan.workgroup_size;
        let counts = plan.counts;
        let speed_limit = crate::stability::speed_limit(model, params) as f32;
        let buffers = SimBuffers::new(
            &ctx,
            model,
            params,
            &plan,
            &sweeps,
            global.as_ref(),
            speed_limit,
        )?;
        let passes = Passes::new(&ctx, &plan, atomics, &buffers)?;
        let push = PushConstants::new(
            params,
            model.node_count(),
            model.springs.len(),
            model.tets.len(),
        );

        let mut timer = match options.untimed {
            true => None,
            false => Timer::new(&ctx, plan.dispatches_per_frame())?,
        };
        let frame = Recorded::begin(&ctx, "frame", false)?;
        Recorder {
            ctx: &ctx,
            cmd: frame.cmd,
            push: &push,
            timer: timer.as_mut(),
        }
        .record_frame(&plan, &passes, &buffers)?;
        frame.end()?;
        let measure = Recorded::begin(&ctx, "volume measure", false)?;
        let mut buffers = buffers;
        if buffers.partials_readback.is_none() {
            buffers.partials_readback = Some(Buffer::readback(
                &ctx,
                "volume partials (readback)",
                buffers.partials.size,
            )?);
        }
        if let Some(readback) = &buffers.partials_readback {
            Recorder {
                ctx: &ctx,
                cmd: measure.cmd,
                push: &push,
                timer: None,
            }
            .record_volume_sum(&passes, &buffers, readback)?;
        }
        measure.end()?;
        Ok(VulkanBackend {
            frame,
            measure,
            timer,
            passes,
            readback: None,
            buffers,
            plan,
            method: params.method.name(),
            likely: crate::stability::likely_cause(model, params),
            atomics,
            workgroup_size: wg,
            counts,
            partials_fresh: false,
            frames: 0,
            inv_mass: model.inv_mass.clone(),
            mass: model.mass.clone(),
            ctx,
        })
    }

    /// The float-atomic path the scatter passes use.
    pub fn atomics(&self) -> AtomicsPath {
        self.atomics
    }

    /// The device in use.
    pub fn device(&self) -> &DeviceInfo {
        self.ctx.info()
    }

    /// Invocations per workgroup.
    pub fn workgroup_size(&self) -> u32 {
        self.workgroup_size
    }

    /// What this backend built and records per frame.
    pub fn plan(&self) -> &EnginePlan {
        &self.plan
    }

    /// Device-local bytes of the simulation buffers actually created.
    pub fn device_bytes(&self) -> u64 {
        self.buffers.device_bytes()
    }

    /// Frames completed on the GPU so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// GPU time per frame of every pass, averaged over the frames so far (empty when the
    /// device has no timestamps). Waits for a frame in flight.
    pub fn pass_times(&mut self) -> Result<Vec<PassTime>> {
        self.finish_frame()?;
        Ok(self
            .timer
            .as_ref()
            .map(Timer::per_frame)
            .unwrap_or_default())
    }

    /// Forgets the pass times measured so far (e.g. after warm-up frames).
    pub fn reset_pass_times(&mut self) -> Result<()> {
        self.finish_frame()?;
        if let Some(t) = self.timer.as_mut() {
            t.reset_totals();
        }
        Ok(())
    }

    /// Validation-layer warnings and errors so far (empty when validation is off).
    pub fn validation_messages(&self) -> Vec<String> {
        self.ctx.validation_messages()
    }

    /// The device-local position buffer (vec4 per node: xyz [m], w = inverse mass [1/kg]),
    /// for drawing in place (`crate::render`). Holds the last finished frame's positions
    /// once [`Backend::step_frame`] has returned.
    pub fn positions(&self) -> &Buffer {
        &self.buffers.positions
    }

    /// The context (shared with other backends or tests).
    pub fn context(&self) -> &Arc<Context> {
        &self.ctx
    }

    /// Waits for a frame in flight and collects its timestamps.
    fn finish_frame(&mut self) -> Result<()> {
        if self.frame.wait()? {
            if let Some(t) = self.timer.as_mut() {
                t.collect()?;
            }
            self.frames += 1;
            self.partials_fresh = self.plan.metrics;
        }
        Ok(())
    }

    /// Reads the divergence status the last frame copied to the host; on flags, names the
    /// frame, the first bad node (with its speed, from one state readback) and the cause.
    fn check_status(&mut self) -> Result<()> {
        let words: [u32; 4] = {
            let bytes = self.buffers.status_readback.mapped()?;
            let b = bytes
                .get(..16)
                .ok_or_else(|| Error::Gpu("divergence status readback is short".into()))?;
            bytemuck::pod_read_unaligned(b)
        };
        let [flags, node, limit, _] = words;
        if flags == 0 {
            return Ok(());
        }
        let limit = f32::from_bits(limit);
        let node = (node != u32::MAX).then_some(node);
        let what = match (flags & 1 != 0, node) {
            (true, _) => "a position or velocity became non-finite".to_string(),
            (false, Some(n)) => {
                let speed = self
                    .state()
                    .ok()
                    .and_then(|s| s.velocities.get(n as usize).map(|v| v.length()));
                match speed {
                    Some(v) => format!(
                        "its speed {v:.3e} m/s exceeds the divergence limit {limit:.3e} m/s"
                    ),
                    None => format!("its speed exceeds the divergence limit {limit:.3e} m/s"),
                }
            }
            (false, None) => format!("a speed exceeds the divergence limit {limit:.3e} m/s"),
        };
        Err(Error::Diverged(Box::new(Divergence {
            frame: self.frames.saturating_sub(1),
            substep: None,
            method: self.method.to_string(),
            node,
            cause: format!("{what}; {}", self.likely),
        })))
    }
}

impl Backend for VulkanBackend {
    fn name(&self) -> &'static str {
        "vulkan"
    }

    fn reset_timing(&mut self) -> Result<()> {
        self.reset_pass_times()
    }

    /// Submits the recorded frame and waits for it: one fence wait, no extra transfer (the
    /// divergence status and, with per-frame metrics, the volume partials are copied to
    /// host-visible memory by the frame itself). A diverged frame is an
    /// [`Error::Diverged`] naming the frame and the first bad node (no substep: the check
    /// runs once per frame).
    fn step_frame(&mut self) -> Result<()> {
        self.finish_frame()?;
        self.partials_fresh = false;
        self.frame.submit()?;
        self.finish_frame()?;
        self.check_status()
    }

    fn volume(&mut self) -> Result<VolumeSample> {
        self.finish_frame()?;
        if !self.partials_fresh {
            self.measure.submit()?;
            self.measure.wait()?;
            self.partials_fresh = true;
        }
        let bytes = self
            .buffers
            .partials_readback
            .as_ref()
            .ok_or_else(|| Error::Gpu("volume partials readback missing".into()))?
            .mapped()?;
        let groups = self.counts.tets.div_ceil(self.workgroup_size) as usize;
        let partials: &[VolumePartial] = bytes
            .get(..groups * std::mem::size_of::<VolumePartial>())
            .and_then(|b| bytemuck::try_cast_slice(b).ok())
            .ok_or_else(|| {
                Error::Gpu(format!(
                    "volume partials readback holds {} bytes, {groups} partials expected",
                    bytes.len()
                ))
            })?;
        Ok(VolumeSample {
            volume: partials.iter().map(|p| f64::from(p.volume)).sum(),
            inverted: partials.iter().map(|p| p.inverted).sum(),
            local_error: partials.iter().map(|p| f64::from(p.local_error)).sum(),
        })
    }

    fn state(&mut self) -> Result<State> {
        self.finish_frame()?;
        let size = u64::from(self.counts.nodes) * 16;
        if self.readback.is_none() {
            self.readback = Some((
                Buffer::readback(&self.ctx, "positions (readback)", size)?,
                Buffer::readback(&self.ctx, "velocities (readback)", size)?,
            ));
        }
        let (pos, vel) = self
            .readback
            .as_ref()
            .ok_or_else(|| Error::Gpu("state readback buffers missing".into()))?;
        let b = &self.buffers;
        let ctx = &self.ctx;
        commands::one_shot(ctx, |cmd| {
            commands::barrier(
                ctx,
                cmd,
                &[&b.positions, &b.velocities],
                Access::COMPUTE,
                Access::TRANSFER_READ,
            );
            let region = [ash::vk::BufferCopy::default().size(size)];
            // SAFETY: `cmd` is recording; all four buffers are alive and `size` long.
            unsafe {
                ctx.device()
                    .cmd_copy_buffer(cmd, b.positions.raw, pos.raw, &region);
                ctx.device()
                    .cmd_copy_buffer(cmd, b.velocities.raw, vel.raw, &region);
            }
            commands::barrier(
                ctx,
                cmd,
                &[pos, vel],
                Access::TRANSFER_WRITE,
                Access::HOST_READ,
            );
        })?;
        let read = |buffer: &Buffer| -> Result<Vec<DVec3>> {
            let bytes = buffer
                .mapped()?
                .get(..size as usize)
                .ok_or_else(|| Error::Gpu(format!("`{}` is short", buffer.name)))?;
            let v: &[[f32; 4]] = bytemuck::try_cast_slice(bytes)
                .map_err(|e| Error::Gpu(format!("reading `{}`: {e}", buffer.name)))?;
            Ok(v.iter()
                .map(|p| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])))
                .collect())
        };
        Ok(State {
            positions: read(pos)?,
            velocities: read(vel)?,
        })
    }

    /// Waits for a frame in flight, then uploads positions and velocities (the volume
    /// partials of the old positions are stale until the next frame or measure).
    fn set_state(&mut self, state: &State) -> Result<()> {
        crate::cpu::check_state(self.inv_mass.len(), state)?;
        self.finish_frame()?;
        self.partials_fresh = false;
        self.buffers.upload_state(state, &self.inv_mass, &self.mass)
    }

    fn gpu_report(&mut self) -> Result<Option<GpuReport>> {
        let passes = self
            .pass_times()?
            .into_iter()
            .map(|t| (t.name, t.ms_per_frame))
            .collect();
        Ok(Some(GpuReport {
            device: self.device().name.clone(),
            atomics: self.atomics.name().to_string(),
            workgroup_size: self.workgroup_size,
            passes,
            validation_messages: self.validation_messages(),
        }))
    }
}

impl Drop for VulkanBackend {
    fn drop(&mut self) {
        // Buffers and pipelines may only go once the GPU is done with them; the fields then
        // drop in declaration order, the context last.
        let _ = self.frame.wait();
        let _ = self.measure.wait();
    }
}
