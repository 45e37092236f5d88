//! The one frame driver: [`Simulation::advance`] steps a backend by one frame, samples the
//! volume when asked, turns a divergence (a backend's report, or a volume that went
//! non-finite) into a stop, and keeps the per-frame series every report is made from. `run`,
//! `bench`/`tradeoff` and `render` all drive their backends through it and add only their
//! extras (progress and mesh files; timing and position samples; pictures).
//!
//! [`Simulation::advance_frames`] does the same for many frames with several in flight
//! ([`Backend::frames_in_flight`]): on `vulkan` it queues frame N + 1 before it waits for
//! frame N and reads its volume, so the GPU has the next frame while the host reads the
//! last. Both give the same frames, bit for bit (`tests/frame_driver.rs` on the CPU,
//! `tests/gpu_frames_in_flight.rs` on `vulkan`).

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use crate::backend::{Backend, ContactSample, Divergence, Reactions, VolumeSample};
use crate::error::{Error, Result};
use crate::geometry::tet_volume;
use crate::metrics::{local_error_pct, volume_pct, RunRecord};
use crate::model::Model;
use crate::params::SimParams;

/// The per-frame series of a run, one entry per sampled frame.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Series {
    /// Simulated time at the end of the frame [s].
    pub time_s: Vec<f64>,
    /// Total volume over the rest volume [%].
    pub volume_pct: Vec<f64>,
    /// Tets with V <= 0.
    pub inverted: Vec<u32>,
    /// Local volume error [%] (`100 sum_t |V_t - V0_t| / sum_t V0_t`).
    pub local_error_pct: Vec<f64>,
    /// Contact measures, when the backend takes them ([`crate::backend::ContactSample`]).
    pub contact: Vec<ContactSample>,
    /// The forces the supports exerted, when the backend measures them.
    pub reactions: Vec<Reactions>,
}

/// How far a run got and what it measured: what a checkpoint keeps of its driver.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Progress {
    /// Frames completed.
    pub frames: u32,
    /// The sampled frames' measures.
    pub series: Series,
    /// Wall time spent stepping so far [s].
    pub stepping_s: f64,
}

/// A run in progress: how far it got, what it measured, and why it stopped, if it did.
#[derive(Debug, Clone)]
pub struct Simulation {
    method: String,
    rest_volume: f64,
    /// The sum of the signed tet volumes at the model's initial positions [m^3] (negative
    /// for a mesh given inside out).
    initial_volume: f64,
    frame_time: f64,
    frames: u32,
    /// The sampled frames' measures.
    pub series: Series,
    /// Where and why the run diverged; no frame advances after it.
    pub divergence: Option<String>,
    /// Wall time spent in `step_frame` over all frames [s] (sampling excluded).
    pub stepping_s: f64,
    /// Set (by a signal handler, say) to end the run after the frames in flight
    /// ([`Simulation::stop_on`]).
    interrupt: Option<Arc<AtomicBool>>,
}

/// What one call of [`Simulation::advance`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Advance {
    /// A frame was stepped; its `step_frame` took this long [s].
    Stepped(f64),
    /// The run has stopped (it diverged, now or before): nothing was stepped.
    Stopped,
}

impl Simulation {
    /// A run of `model` under `params`, before its first frame.
    pub fn new(model: &Model, params: &SimParams) -> Self {
        Simulation {
            method: params.method.name().to_string(),
            rest_volume: model.total_rest_volume(),
            initial_volume: (model.tets.iter())
                .map(|tet| tet_volume(tet.map(|k| model.positions[k as usize])))
                .sum(),
            frame_time: params.frame_time(),
            frames: 0,
            series: Series::default(),
            divergence: None,
            stepping_s: 0.0,
            interrupt: None,
        }
    }

    /// Ends the run, once `flag` is set, after the frames already started: no further frame
    /// is submitted, those in flight are completed and recorded, and [`Simulation::interrupted`]
    /// says so (the command line sets it on SIGINT and SIGTERM).
    pub fn stop_on(&mut self, flag: Arc<AtomicBool>) {
        self.interrupt = Some(flag);
    }

    /// Whether the run was asked to end before its last frame ([`Simulation::stop_on`]).
    pub fn interrupted(&self) -> bool {
        (self.interrupt.as_ref()).is_some_and(|flag| flag.load(Ordering::SeqCst))
    }

    /// Frames completed.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Simulated time reached [s].
    pub fn time(&self) -> f64 {
        f64::from(self.frames) * self.frame_time
    }

    /// What it has measured so far and how far it got, for a checkpoint.
    pub fn progress(&self) -> Progress {
        Progress {
            frames: self.frames,
            series: self.series.clone(),
            stepping_s: self.stepping_s,
        }
    }

    /// Continues from `progress` (a checkpoint's), as if it had run those frames.
    pub fn resume(&mut self, progress: Progress) {
        self.frames = progress.frames;
        self.series = progress.series;
        self.stepping_s = progress.stepping_s;
        self.divergence = None;
    }

    /// Whether the run has stopped (diverged).
    pub fn stopped(&self) -> bool {
        self.divergence.is_some()
    }

    /// Puts the per-frame series and the divergence into `record`, then
    /// [`RunRecord::summarise`]s it.
    pub fn fill_record(&self, record: &mut RunRecord) {
        let series = self.series.clone();
        record.time_s = series.time_s;
        record.volume_pct = series.volume_pct;
        record.inverted_tets = series.inverted;
        record.local_error_pct = series.local_error_pct;
        record.collider_nodes = series.contact.iter().map(|c| c.collider_nodes).collect();
        record.body_contacts = series.contact.iter().map(|c| c.body_contacts).collect();
        record.deepest_m = series.contact.iter().map(|c| c.deepest_m).collect();
        let xyz = |v: glam::DVec3| v.to_array();
        record.pin_force = series.reactions.iter().map(|r| xyz(r.pin)).collect();
        if record.params.floor {
            record.floor_force = series.reactions.iter().map(|r| xyz(r.floor)).collect();
        }
        if series.reactions.iter().any(|r| !r.colliders.is_empty()) {
            record.collider_force = (series.reactions.iter())
                .map(|r| r.colliders.iter().map(|&c| xyz(c)).collect())
                .collect();
        }
        if series.reactions.iter().any(|r| !r.clamps.is_empty()) {
            record.clamp_force = (series.reactions.iter())
                .map(|r| r.clamps.iter().map(|&c| xyz(c)).collect())
                .collect();
        }
        record.diverged = self.divergence.is_some();
        record.divergence = self.divergence.clone();
        record.interrupted = self.interrupted();
        record.summarise();
    }

    /// The last sampled total volume [%], if any frame was sampled.
    pub fn last_volume_pct(&self) -> Option<f64> {
        self.series.volume_pct.last().copied()
    }

    /// Steps `backend` by one frame and, when `sample` is set, reads its volume into
    /// [`Simulation::series`]. A divergence stops the run (recorded in
    /// [`Simulation::divergence`], not returned as an error); other failures are errors.
    pub fn advance(&mut self, backend: &mut dyn Backend, sample: bool) -> Result<Advance> {
        if self.stopped() {
            return Ok(Advance::Stopped);
        }
        let t0 = Instant::now();
        let stepped = backend.step_frame();
        let step_s = t0.elapsed().as_secs_f64();
        match stepped {
            Ok(()) => {}
            Err(Error::Diverged(d)) => {
                self.divergence = Some(d.to_string());
                return Ok(Advance::Stopped);
            }
            Err(e) => return Err(e),
        }
        self.stepping_s += step_s;
        self.frames += 1;
        if sample {
            let measured = backend.volume()?;
            if !self.record_sample(measured, backend) {
                return Ok(Advance::Stopped);
            }
            self.series.reactions.extend(backend.reactions()?);
        }
        Ok(Advance::Stepped(step_s))
    }

    /// Advances `backend` by `frames` frames (fewer if the run stops), with up to
    /// [`Backend::frames_in_flight`] of them started before the oldest is collected.
    /// `sample(n)` says whether to sample the volume after the run's `n`-th frame (counted
    /// from 1 over the whole run); `on_frame` runs after each frame is recorded (progress).
    /// A divergence stops the run as in [`Simulation::advance`]; frames still in flight
    /// then finish unrecorded. [`Simulation::stepping_s`] grows by the wall time of the
    /// whole call (the few sampled reads included). Returns the frames advanced.
    pub fn advance_frames(
        &mut self,
        backend: &mut dyn Backend,
        frames: u32,
        sample: &dyn Fn(u32) -> bool,
        on_frame: &mut dyn FnMut(&Simulation),
    ) -> Result<u32> {
        let depth = backend.frames_in_flight().max(1);
        let first = self.frames;
        let t0 = Instant::now();
        // Whether each started frame is to be sampled, oldest first.
        let mut started: VecDeque<bool> = VecDeque::with_capacity(depth);
        let mut submitted = 0;
        let mut failed_submit = None;
        loop {
            while !self.stopped()
                && !self.interrupted()
                && failed_submit.is_none()
                && submitted < frames
                && started.len() < depth
            {
                let n = self.frames + started.len() as u32 + 1;
                match backend.submit_frame() {
                    Ok(()) => {
                        started.push_back(sample(n));
                        submitted += 1;
                    }
                    Err(Error::Diverged(d)) => failed_submit = Some(d.to_string()),
                    Err(e) => return Err(e),
                }
            }
            let Some(sampled) = started.pop_front() else {
                break;
            };
            if self.stopped() {
                // Frames started before the stop was seen: finish them, unrecorded.
                match backend.collect_frame(false) {
                    Ok(_) | Err(Error::Diverged(_)) => continue,
                    Err(e) => return Err(e),
                }
            }
            match backend.collect_frame(sampled) {
                Ok(measured) => {
                    self.frames += 1;
                    if let Some(measured) = measured {
                        if self.record_sample(measured, backend) {
                            self.series.reactions.extend(backend.reactions()?);
                        }
                    }
                    on_frame(self);
                }
                Err(Error::Diverged(d)) => self.divergence = Some(d.to_string()),
                Err(e) => return Err(e),
            }
        }
        if self.divergence.is_none() {
            self.divergence = failed_submit;
        }
        self.stepping_s += t0.elapsed().as_secs_f64();
        Ok(self.frames - first)
    }

    /// Appends the measures of the frame just finished to the series; volumes that mean the
    /// run diverged stop the run instead (returns `false`): not finite, inside out where the
    /// last sample (or the initial state) was not, or blown up
    /// ([`crate::stability::volume_divergence`]), while a node may still be slower than
    /// the speed limit. The report names the fastest node and `backend`'s likely cause.
    fn record_sample(&mut self, measured: VolumeSample, backend: &mut dyn Backend) -> bool {
        let pct = volume_pct(measured, self.rest_volume);
        let local = local_error_pct(measured, self.rest_volume);
        let was_positive = match self.series.volume_pct.last() {
            Some(&last) => last > 0.0,
            None => self.initial_volume > 0.0,
        };
        if let Some(cause) = crate::stability::volume_divergence(pct, local, was_positive) {
            // The node to look at: the fastest (a readback, once, as the run stops).
            let fastest = backend.state().ok().and_then(|state| {
                (state.velocities.iter().enumerate())
                    .map(|(i, v)| (i, v.length()))
                    .max_by(|a, b| a.1.total_cmp(&b.1))
            });
            let speed = fastest.map_or(String::new(), |(_, v)| {
                format!(" (the node named moves at {v:.3e} m/s, the fastest)")
            });
            let divergence = Divergence {
                frame: self.frames.saturating_sub(1),
                substep: None,
                method: self.method.clone(),
                node: fastest.map(|(i, _)| i as u32),
                cause: format!("{cause}{speed}; {}", backend.likely_cause()),
            };
            self.divergence = Some(divergence.to_string());
            return false;
        }
        let time = self.time();
        let series = &mut self.series;
        series.time_s.push(time);
        series.volume_pct.push(pct);
        series.inverted.push(measured.inverted);
        series.local_error_pct.push(local);
        series.contact.extend(measured.contact);
        true
    }
}
