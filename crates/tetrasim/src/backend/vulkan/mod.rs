//! The `vulkan` backend: the paper's solver in compute shaders.
//!
//! The model is uploaded once; only the buffers and pipelines the method needs are built;
//! the frame's command buffer (substeps x passes, barriers, timestamps, the volume metric)
//! is recorded once per frame slot and replayed. Two slots, each with its own fence, its own
//! host-visible copies of the divergence status and the volume partials, and its own
//! timestamps, let two frames be in flight: [`Backend::submit_frame`] queues a frame without
//! waiting and [`Backend::collect_frame`] finishes the oldest, so the driver reads frame N's
//! volume while frame N + 1 runs ([`crate::sim::Simulation::advance_frames`]).
//! [`Backend::step_frame`] submits one frame and waits for it. [`Backend::volume`] only reads
//! the few volume partials a frame copied to host-visible memory; only [`Backend::state`]
//! reads back every node.

mod buffers;
mod carry;
mod coarse;
mod colliders;
mod elastic;
mod frames;
mod minres;
mod options;
mod passes;
pub mod plan;
mod reactions;

use std::collections::VecDeque;
use std::sync::Arc;

use glam::DVec3;

use crate::backend::{Backend, Carried, ContactSample, Divergence, GpuReport, State, VolumeSample};
use crate::error::{Error, Result};
use crate::gpu::commands::{self, Access, Recorded};
use crate::gpu::layout::{PushConstants, VolumePartial};
pub use crate::gpu::AtomicsMode;
use crate::gpu::{
    AtomicsPath, Buffer, Context, ContextOptions, DeviceInfo, DeviceSelector, PassTime, Timer,
};
use crate::model::Model;
use crate::params::SimParams;
use crate::problem::Problem;
use buffers::SimBuffers;
pub use coarse::CoarseIndex;
pub use colliders::{poses as collider_poses, static_data as collider_data};
pub use elastic::ElasticData;
pub use options::{EngineOptions, FRAMES_IN_FLIGHT, MAX_FRAMES_IN_FLIGHT};
use passes::{Passes, Recorder};
use plan::{EnginePlan, PlanCounts};

/// What a renderer draws from (`render::Renderer::render`, feature `render`): node positions and the
/// model's static data, all of them the engine's own buffers, so the renderer uploads only
/// what drawing alone needs (the surface and its adjacency).
#[derive(Clone, Copy)]
pub struct DrawBuffers<'a> {
    /// vec4 per node: position [m], w = inverse mass [1/kg].
    pub positions: &'a Buffer,
    /// uvec4 per tet.
    pub tets: &'a Buffer,
    /// float per tet: rest volume [m^3].
    pub rest_volumes: &'a Buffer,
    /// One [`crate::gpu::layout::GpuSpring`] per spring: `a`, `b`, rest length [m] (f32
    /// bits), stiffness.
    pub springs: &'a Buffer,
}

/// One recorded frame with its own fence (in `frame`), timestamps and host-visible copies of
/// the divergence status and (with per-frame metrics) the volume partials. Field order is
/// drop order: the command buffer waits for its submission before the rest goes.
struct FrameSlot {
    frame: Recorded,
    timer: Option<Timer>,
    status_readback: Buffer,
    partials_readback: Option<Buffer>,
    /// Host-visible copy of the frame's reaction partials (with per-frame metrics).
    reactions_readback: Option<Buffer>,
}

/// The Vulkan compute backend. Field order is drop order: GPU work is waited for in
/// `Drop`, then command buffers, pipelines and buffers go, and the context last.
pub struct VulkanBackend {
    slots: Vec<FrameSlot>,
    /// Slots submitted and not yet finished, oldest first.
    queued: VecDeque<usize>,
    /// The slot the next frame goes to.
    next_slot: usize,
    /// The slot of the last finished frame, while its partials hold the volume of the
    /// current positions.
    fresh_slot: Option<usize>,
    /// The slot of the last frame collected (its reactions are the run's latest).
    collected_slot: Option<usize>,
    /// Most frames ever queued at once.
    max_queued: usize,
    measure: Recorded,
    /// Host-visible copy of the partials of an on-demand measurement.
    measure_readback: Buffer,
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
    /// Whether `measure_readback` holds the volume of the current positions.
    measure_fresh: bool,
    frames: u32,
    /// Frames submitted so far: the next frame's first step is `submitted * substeps`
    /// (counted from the backend's creation; [`Backend::set_state`] does not reset it).
    submitted: u64,
    /// The model's kinematic colliders, whose poses each frame slot gets before its submit.
    colliders: Vec<crate::collider::Collider>,
    /// The model's clamps, whose poses each frame slot gets before its submit.
    clamps: Vec<crate::collider::Clamp>,
    /// The model's grabs, the nodes they hold (the rows of the grab targets) and the
    /// initial positions they hold from (empty without grabs).
    grabs: Vec<crate::collider::Grab>,
    grabbed: Vec<u32>,
    rest: Vec<DVec3>,
    /// Time step [s] (f64: the colliders' poses are computed on the host in f64).
    dt: f64,
    /// Gravity's acceleration [m/s^2] (the finite elements' forces after a new state).
    gravity: DVec3,
    /// The model's inverse masses and masses, the `w` of the uploaded positions and
    /// velocities ([`Backend::set_state`]).
    inv_mass: Vec<f64>,
    mass: Vec<f64>,
    ctx: Arc<Context>,
}

impl VulkanBackend {
    /// The backend on the shared context for `options` ([`Self::from_problem`]).
    pub fn new(model: &Model, params: &SimParams, options: &EngineOptions) -> Result<Self> {
        Self::from_problem(&Problem::new(model, params)?, options)
    }

    /// The backend for a prepared problem on the process's shared context for `options`'
    /// device and validation ([`Context::shared`]: created with the first backend, freed
    /// with the last).
    pub fn from_problem(problem: &Problem, options: &EngineOptions) -> Result<Self> {
        let ctx = Context::shared(&ContextOptions {
            device: options.device.clone(),
            validation: options.validation,
        })?;
        Self::on_context(ctx, problem, options)
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
        Self::on_context(ctx, &Problem::new(model, params)?, &options)
    }

    /// The backend on an existing context with all options but the device.
    pub fn with_context_and_options(
        ctx: Arc<Context>,
        model: &Model,
        params: &SimParams,
        options: &EngineOptions,
    ) -> Result<Self> {
        Self::on_context(ctx, &Problem::new(model, params)?, options)
    }

    /// The plan of `problem` on a device with `info` (what [`Self::from_problem`] would
    /// build; `tetrasim plan` prints it).
    pub fn plan_for(
        info: &DeviceInfo,
        problem: &Problem,
        options: &EngineOptions,
    ) -> Result<EnginePlan> {
        let metrics = !options.volume_on_demand;
        let plan = match options.workgroup_size {
            Some(wg) => {
                info.check_workgroup_size(wg)?;
                EnginePlan::of_problem(problem, wg, metrics)
            }
            None => EnginePlan::of_problem(problem, info.default_workgroup_size(), metrics)
                .map(EnginePlan::size_workgroups),
        }?;
        if let Some(pass) = plan.passes.iter().find(|p| p.solves_blocks()) {
            info.check_block_workgroup(pass.workgroup_size, problem.params.block_size)?;
        }
        Ok(plan)
    }

    /// What [`Self::on_context`] checks before it allocates anything, and the plan it then
    /// builds: the method runs here, the frames in flight are in range, and the plan's
    /// buffers fit the device's memory (at most `options.memory_limit` of it), refused
    /// otherwise with what it needs and what the device offers. `tetrasim run` asks it
    /// before it makes any output.
    pub fn preflight(
        info: &DeviceInfo,
        problem: &Problem,
        options: &EngineOptions,
    ) -> Result<EnginePlan> {
        if problem.params.method == crate::params::Method::NeoHookean {
            let unsupported = match (problem.params.contact, problem.bodies.is_some()) {
                (crate::params::ContactMode::Split, _) => Some(("contact", "split contact")),
                (_, true) => Some(("backend", "contact between bodies")),
                _ => None,
            };
            if let Some((key, what)) = unsupported {
                return Err(Error::param(
                    key,
                    format!(
                        "the vulkan engine's finite elements do not run with {what} yet (use \
                         --backend cpu for neo-hookean with it)"
                    ),
                ));
            }
        }
        let depth = options.frames_in_flight.unwrap_or(FRAMES_IN_FLIGHT);
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&depth) {
            return Err(Error::param(
                "frames-in-flight",
                format!("must be 1 to {MAX_FRAMES_IN_FLIGHT}, not {depth}"),
            ));
        }
        let plan = Self::plan_for(info, problem, options)?;
        let needs = plan.memory_needs(depth);
        info.memory.check(needs, options.memory_limit, &info.name)?;
        Ok(plan)
    }

    /// The backend for a prepared problem on an existing context, with all options but the
    /// device.
    pub fn on_context(
        ctx: Arc<Context>,
        problem: &Problem,
        options: &EngineOptions,
    ) -> Result<Self> {
        let (model, params) = (&problem.model, &problem.params);
        let depth = options.frames_in_flight.unwrap_or(FRAMES_IN_FLIGHT);
        let info = ctx.info();
        let plan = Self::preflight(info, problem, options)?;
        let atomics = info.atomics_path(options.atomics)?;
        let wg = plan.workgroup_size;
        let counts = plan.counts;
        let buffers = SimBuffers::new(&ctx, problem, &plan)?;
        let passes = Passes::new(&ctx, &plan, atomics, &buffers)?;
        let push = PushConstants::new(
            params,
            model.node_count(),
            model.springs.len(),
            model.tets.len(),
        );

        let slots = (0..depth)
            .map(|k| {
                let mut timer = match options.untimed {
                    true => None,
                    false => Timer::new(&ctx, plan.dispatches_per_frame())?,
                };
                let status_readback = Buffer::readback(
                    &ctx,
                    &format!("divergence status (readback {k})"),
                    plan.buffer(plan::BufferId::Status)
                        .map_or(16, |b| b.readback_bytes),
                )?;
                let partials_readback = match plan.metrics {
                    true => Some(Buffer::readback(
                        &ctx,
                        &format!("volume partials (readback {k})"),
                        buffers.partials.size,
                    )?),
                    false => None,
                };
                let reactions_readback = match plan.buffer(plan::BufferId::ReactionPartials) {
                    Some(b) => Some(Buffer::readback(&ctx, "reactions (readback)", b.bytes)?),
                    None => None,
                };
                let frame = Recorded::begin(&ctx, &format!("frame {k}"), false)?;
                Recorder {
                    ctx: &ctx,
                    cmd: frame.cmd,
                    push: &push,
                    timer: timer.as_mut(),
                }
                .record_frame(
                    &plan,
                    k,
                    &passes,
                    &buffers,
                    &status_readback,
                    [partials_readback.as_ref(), reactions_readback.as_ref()],
                )?;
                frame.end()?;
                Ok(FrameSlot {
                    frame,
                    timer,
                    status_readback,
                    partials_readback,
                    reactions_readback,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let measure = Recorded::begin(&ctx, "volume measure", false)?;
        let measure_readback =
            Buffer::readback(&ctx, "volume partials (measure)", buffers.partials.size)?;
        Recorder {
            ctx: &ctx,
            cmd: measure.cmd,
            push: &push,
            timer: None,
        }
        .record_volume_sum(&passes, &buffers, &measure_readback)?;
        measure.end()?;
        Ok(VulkanBackend {
            slots,
            queued: VecDeque::new(),
            next_slot: 0,
            fresh_slot: None,
            collected_slot: None,
            max_queued: 0,
            measure,
            measure_readback,
            passes,
            readback: None,
            buffers,
            plan,
            method: params.method.name(),
            likely: problem.likely_cause.clone(),
            atomics,
            workgroup_size: wg,
            counts,
            measure_fresh: false,
            frames: 0,
            submitted: 0,
            colliders: model.colliders.clone(),
            clamps: model.clamps.clone(),
            grabs: model.grabs.clone(),
            grabbed: plan::grabbed_nodes(&model.grabs),
            rest: match model.grabs.is_empty() {
                true => Vec::new(),
                false => model.positions.clone(),
            },
            dt: params.dt,
            gravity: params.gravity,
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

    /// The most frames that were ever in flight at once (1 when every frame was waited
    /// for before the next was submitted).
    pub fn max_frames_in_flight(&self) -> usize {
        self.max_queued
    }

    /// GPU time per frame of every pass, averaged over the frames so far (empty when the
    /// device has no timestamps). Waits for the frames in flight.
    pub fn pass_times(&mut self) -> Result<Vec<PassTime>> {
        self.settle()?;
        let timers: Vec<&Timer> = self.slots.iter().filter_map(|s| s.timer.as_ref()).collect();
        Ok(Timer::per_frame_of(&timers))
    }

    /// Forgets the pass times measured so far (e.g. after warm-up frames).
    pub fn reset_pass_times(&mut self) -> Result<()> {
        self.settle()?;
        for t in self.slots.iter_mut().filter_map(|s| s.timer.as_mut()) {
            t.reset_totals();
        }
        Ok(())
    }

    /// Validation-layer warnings and errors so far (empty when validation is off).
    pub fn validation_messages(&self) -> Vec<String> {
        self.ctx.validation_messages()
    }

    /// This backend's positions (those of the last finished frame once
    /// [`Backend::step_frame`] has returned) with the model's tets, rest volumes and springs,
    /// for drawing in place.
    pub fn draw_buffers(&self) -> DrawBuffers<'_> {
        DrawBuffers {
            positions: &self.buffers.positions,
            tets: &self.buffers.tets,
            rest_volumes: &self.buffers.rest_volumes,
            springs: &self.buffers.springs,
        }
    }

    /// The context (shared with other backends or tests).
    pub fn context(&self) -> &Arc<Context> {
        &self.ctx
    }

    /// Writes the colliders' and the clamps' poses over the next frame's steps into frame
    /// slot `k`'s rows of the host-visible poses buffers (slot `k` is not in flight: its
    /// last frame was collected before it is reused). Nothing without either.
    fn write_poses(&mut self, k: usize) -> Result<()> {
        let substeps = self.plan.schedule.substeps;
        let first = self.submitted * u64::from(substeps);
        if let Some(buffer) = (self.buffers.optional.get_mut(&plan::BufferId::GrabTargets))
            .filter(|_| !self.grabbed.is_empty())
        {
            let rows = colliders::grab_targets(
                &self.grabs,
                &self.grabbed,
                &self.rest,
                first,
                substeps,
                self.dt,
            );
            let bytes: &[u8] = bytemuck::cast_slice(&rows);
            buffer.write_at(k * bytes.len(), bytes)?;
        }
        if let Some(buffer) = self.buffers.optional.get_mut(&plan::BufferId::ClampPoses) {
            let rows = colliders::clamp_poses(&self.clamps, first, substeps, self.dt);
            let bytes: &[u8] = bytemuck::cast_slice(&rows);
            buffer.write_at(k * bytes.len(), bytes)?;
        }
        let Some(buffer) = self
            .buffers
            .optional
            .get_mut(&plan::BufferId::ColliderPoses)
        else {
            return Ok(());
        };
        let rows = colliders::poses(&self.colliders, first, substeps, self.dt);
        let bytes: &[u8] = bytemuck::cast_slice(&rows);
        buffer.write_at(k * bytes.len(), bytes)
    }

    /// Waits for the oldest frame in flight and collects its timestamps; returns its slot
    /// (`None`: nothing was in flight).
    fn finish_oldest(&mut self) -> Result<Option<usize>> {
        let Some(k) = self.queued.pop_front() else {
            return Ok(None);
        };
        let slot = &mut self.slots[k];
        slot.frame.wait()?;
        if let Some(t) = slot.timer.as_mut() {
            t.collect()?;
        }
        self.frames += 1;
        self.fresh_slot = (self.queued.is_empty() && slot.partials_readback.is_some()).then_some(k);
        self.collected_slot = Some(k);
        Ok(Some(k))
    }

    /// Waits for every frame in flight (without checking their divergence status: that is
    /// [`Backend::collect_frame`]'s and [`Backend::step_frame`]'s).
    fn settle(&mut self) -> Result<()> {
        while self.finish_oldest()?.is_some() {}
        Ok(())
    }

    /// The volume measures of the partials a frame or a measurement copied to `readback`,
    /// with the contact measures frame slot `slot` copied with its status (`None`: a
    /// measurement, which has none).
    fn read_partials(&self, readback: &Buffer, slot: Option<usize>) -> Result<VolumeSample> {
        let bytes = readback.mapped()?;
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
            contact: match slot {
                Some(k) => self.read_contact(k)?,
                None => None,
            },
        })
    }

    /// The contact measures frame slot `k` copied to the host after its status words
    /// (contact_measure.comp), when the frame measures contact.
    fn read_contact(&self, k: usize) -> Result<Option<ContactSample>> {
        if !self.plan.measures_contact() {
            return Ok(None);
        }
        let bytes = self.slots[k].status_readback.mapped()?;
        let words: [u32; 4] = bytes
            .get(plan::STATUS_BYTES as usize..plan::CONTACT_STATUS_BYTES as usize)
            .map(bytemuck::pod_read_unaligned)
            .ok_or_else(|| Error::Gpu("the contact words' readback is short".into()))?;
        Ok(Some(ContactSample {
            collider_nodes: words[0],
            body_contacts: words[1],
            deepest_m: f64::from(f32::from_bits(words[2])),
        }))
    }

    /// Reads the divergence status frame slot `k` copied to the host; on flags, names the
    /// frame, the first bad node, the fastest speed and the cause (all from the status: no
    /// state read-back, which with frames in flight would show a later frame).
    fn check_status(&self, k: usize) -> Result<()> {
        let words: [u32; 4] = {
            let bytes = self.slots[k].status_readback.mapped()?;
            let b = bytes
                .get(..16)
                .ok_or_else(|| Error::Gpu("divergence status readback is short".into()))?;
            bytemuck::pod_read_unaligned(b)
        };
        let [flags, node, limit, fastest] = words;
        if flags == 0 {
            return Ok(());
        }
        if flags & 4 != 0 {
            return Err(Error::Gpu(format!(
                "frame {}: body contact's spatial hash overflowed (a surface triangle covers \
                 more than 4096 cells, or the triangles' cells exceed the item array sized \
                 from the rest mesh): the surface has stretched far beyond its rest size",
                self.frames.saturating_sub(1)
            )));
        }
        let frame = self.frames.saturating_sub(1);
        let limit = f32::from_bits(limit);
        let node = (node != u32::MAX).then_some(node);
        let what = match (flags & 1 != 0, node) {
            (true, _) => "a position or velocity became non-finite".to_string(),
            (false, _) => format!(
                "the fastest node's speed {:.3e} m/s exceeds the divergence limit {limit:.3e} m/s",
                f32::from_bits(fastest)
            ),
        };
        Err(Error::Diverged(Box::new(Divergence {
            frame,
            substep: None,
            method: self.method.to_string(),
            node,
            cause: format!("{what}; {}", self.likely),
        })))
    }
}

impl Drop for VulkanBackend {
    fn drop(&mut self) {
        // Buffers and pipelines may only go once the GPU is done with them; the fields then
        // drop in declaration order, the context last.
        for slot in &mut self.slots {
            let _ = slot.frame.wait();
        }
        let _ = self.measure.wait();
    }
}
