//! The [`Backend`] interface of the `vulkan` backend: frames submitted into their slots and
//! collected, the divergence status and volume partials read from the host-visible copies,
//! and the state read back or uploaded between frames.

use super::*;

impl Backend for VulkanBackend {
    fn name(&self) -> &'static str {
        "vulkan"
    }

    fn reset_timing(&mut self) -> Result<()> {
        self.reset_pass_times()
    }

    /// Submits a recorded frame and waits for it (and for any frame still in flight before
    /// it): one fence wait, no extra transfer (the divergence status and, with per-frame
    /// metrics, the volume partials are copied to host-visible memory by the frame itself).
    /// A diverged frame is an [`Error::Diverged`] naming the frame and the first bad node
    /// (no substep: the check runs once per frame).
    fn step_frame(&mut self) -> Result<()> {
        self.settle()?;
        self.submit_frame()?;
        self.collect_frame(false).map(|_| ())
    }

    fn frames_in_flight(&self) -> usize {
        self.slots.len()
    }

    /// Queues the next frame in its slot without waiting for it (the GPU runs it after the
    /// frames queued before it).
    fn submit_frame(&mut self) -> Result<()> {
        if self.queued.len() >= self.slots.len() {
            return Err(Error::Gpu(format!(
                "submit_frame: {} frames are already in flight; collect_frame first",
                self.queued.len()
            )));
        }
        let k = self.next_slot;
        self.write_poses(k)?;
        self.slots[k].frame.submit()?;
        self.submitted += 1;
        self.queued.push_back(k);
        self.max_queued = self.max_queued.max(self.queued.len());
        self.next_slot = (k + 1) % self.slots.len();
        self.fresh_slot = None;
        self.measure_fresh = false;
        Ok(())
    }

    /// Waits for the oldest frame in flight, reports its divergence, and reads its volume
    /// from its own partials (with per-frame metrics), or measures the current positions
    /// once nothing is in flight (on-demand volume: ask only at a run's last frame). With
    /// nothing in flight (a state read finished every frame), only the sample is taken.
    fn collect_frame(&mut self, sample: bool) -> Result<Option<VolumeSample>> {
        let Some(k) = self.finish_oldest()? else {
            return match sample {
                true => self.volume().map(Some),
                false => Ok(None),
            };
        };
        self.check_status(k)?;
        if !sample {
            return Ok(None);
        }
        match &self.slots[k].partials_readback {
            Some(readback) => self.read_partials(readback, Some(k)).map(Some),
            None if self.queued.is_empty() => self.volume().map(Some),
            None => Err(Error::Gpu(
                "collect_frame: the volume is measured on demand, which needs every frame \
                 finished; sample only the last frame"
                    .into(),
            )),
        }
    }

    fn volume(&mut self) -> Result<VolumeSample> {
        self.settle()?;
        if let Some(k) = self.fresh_slot {
            if let Some(readback) = &self.slots[k].partials_readback {
                return self.read_partials(readback, Some(k));
            }
        }
        if !self.measure_fresh {
            self.measure.submit()?;
            self.measure.wait()?;
            self.measure_fresh = true;
        }
        self.read_partials(&self.measure_readback, None)
    }

    fn likely_cause(&self) -> &str {
        &self.likely
    }

    fn state(&mut self) -> Result<State> {
        self.settle()?;
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
        crate::backend::cpu::check_state(self.inv_mass.len(), state)?;
        self.settle()?;
        self.fresh_slot = None;
        self.measure_fresh = false;
        let gravity = self.plan.elastic_counts().map(|_| self.gravity);
        self.buffers
            .upload_state(state, &self.inv_mass, &self.mass, gravity)
    }

    /// The frame and step counters, and the finite elements' forces and coarse level
    /// (`carry.rs`). Everything else a step starts from is the state or is rebuilt at the
    /// step's start, except warm-started springs' multipliers, which stay on the device
    /// (refused for now).
    fn carried(&mut self) -> Result<Carried> {
        self.settle()?;
        if self.plan.schedule.warm_start {
            return Err(Error::param(
                "checkpoint",
                "the vulkan backend keeps warm-started springs' multipliers on the device, \
                 and cannot save them yet (run on cpu or cpu-ref, or without warm_start)",
            ));
        }
        Ok(Carried {
            frames: self.frames,
            steps: self.submitted * u64::from(self.plan.schedule.substeps),
            arrays: self.carried_arrays()?,
        })
    }

    fn restore(&mut self, state: &State, carried: &Carried) -> Result<()> {
        let substeps = u64::from(self.plan.schedule.substeps);
        if self.plan.schedule.warm_start || carried.steps % substeps != 0 {
            return Err(Error::param(
                "checkpoint",
                "it was not saved by the vulkan backend on this problem",
            ));
        }
        self.set_state(state)?;
        self.restore_arrays(carried)?;
        (self.frames, self.submitted) = (carried.frames, carried.steps / substeps);
        Ok(())
    }

    /// The forces the supports exerted in the last collected frame's last step, from its
    /// copy of the `reactions` pass's partials (with per-frame metrics; `None` without).
    fn reactions(&mut self) -> Result<Option<crate::backend::Reactions>> {
        let Some(k) = self.collected_slot else {
            return Ok(None);
        };
        let Some(readback) = &self.slots[k].reactions_readback else {
            return Ok(None);
        };
        let pass = self.plan.passes.iter();
        let wg = pass
            .filter(|p| p.stage.kind == crate::schedule::PassKind::Reactions)
            .map(|p| p.workgroup_size);
        let groups = self.counts.nodes.div_ceil(wg.max().unwrap_or(1)) as usize;
        let (colliders, clamps) = (self.colliders.len(), self.clamps.len());
        reactions::sum(readback.mapped()?, groups, colliders, clamps).map(Some)
    }

    fn gpu_report(&mut self) -> Result<Option<GpuReport>> {
        let passes = self.pass_times()?;
        Ok(Some(GpuReport {
            device: self.device().name.clone(),
            atomics: self.atomics.name().to_string(),
            workgroup_size: self.workgroup_size,
            passes,
            validation_messages: self.validation_messages(),
            memory_in_use: self
                .ctx
                .allocator()?
                .generate_report()
                .total_allocated_bytes,
        }))
    }
}
