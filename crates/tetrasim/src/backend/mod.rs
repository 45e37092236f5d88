//! The one interface every solver backend implements (`cpu-ref`, `cpu`, `vulkan`): same
//! model and parameters in, same state and metrics out. Tests compare backends through it.

use glam::DVec3;
use serde::Serialize;

use crate::error::Result;

/// Dynamic state of one object.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Node positions [m].
    pub positions: Vec<DVec3>,
    /// Node velocities [m/s].
    pub velocities: Vec<DVec3>,
}

/// Volume measures of one frame (physics.md, "Metrics").
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct VolumeSample {
    /// Sum of signed tet volumes [m^3].
    pub volume: f64,
    /// Tets with signed volume <= 0.
    pub inverted: u32,
    /// Sum over tets of `|V_t - V0_t|` [m^3] (physics.md, "Local volume error").
    pub local_error: f64,
    /// Contact measures, for a model with kinematic colliders, grabs or body contact (every
    /// backend; `vulkan` measures them on the device with per-frame metrics, and has none
    /// for an on-demand measurement); `None` otherwise.
    pub contact: Option<ContactSample>,
}

/// Contact measures of one frame (issue 24: "run records carry contact counts and the
/// deepest penetration per frame").
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct ContactSample {
    /// Nodes a kinematic collider pushed in the frame's last step.
    pub collider_nodes: u32,
    /// Contacts between bodies (or of a body with itself) pushing in that step.
    pub body_contacts: u32,
    /// The deepest any node is inside a collider's shape or behind the triangle of its
    /// body contact, at the frame's end [m] (0: none).
    pub deepest_m: f64,
}

/// The forces the supports exert on the bodies in the last step of the last frame [N]
/// (issue 51, "Forces out"; docs/PHYSICS.md, "Forces out"). Normal and constraint forces
/// only: the floor's and the colliders' friction acts on velocities and is not in them.
#[derive(Debug, Clone, PartialEq, Default, Serialize, serde::Deserialize)]
pub struct Reactions {
    /// The pinned nodes' (pins and clamps) total force on the bodies: what holds each
    /// pinned node against every other force on it (gravity, springs, constraints or the
    /// elastic forces of its tets, contact), summed.
    pub pin: DVec3,
    /// The floor's (zero without a floor).
    pub floor: DVec3,
    /// Each kinematic collider's, in the model's order.
    pub colliders: Vec<DVec3>,
    /// Each clamp's (its nodes' share of `pin`), in the model's order: what a tool that
    /// holds and moves part of a body exerts on it (a tensile test's force).
    pub clamps: Vec<DVec3>,
}

impl Reactions {
    /// No force, for a model with `colliders` colliders and `clamps` clamps.
    pub fn none(colliders: usize, clamps: usize) -> Self {
        Reactions {
            colliders: vec![DVec3::ZERO; colliders],
            clamps: vec![DVec3::ZERO; clamps],
            ..Reactions::default()
        }
    }

    /// Adds the holding force `held(i)` of each pinned node `i` of `pinned` to `pin`, and
    /// to the clamp that holds it, if any (`clamp_of`: [`crate::collider::clamp_of_nodes`]).
    pub fn add_pinned(
        &mut self,
        pinned: impl IntoIterator<Item = usize>,
        clamp_of: &[Option<u32>],
        mut held: impl FnMut(usize) -> DVec3,
    ) {
        for i in pinned {
            let force = held(i);
            self.pin += force;
            if let Some(&Some(c)) = clamp_of.get(i) {
                self.clamps[c as usize] += force;
            }
        }
    }

    /// Adds collider `c`'s force `force` on one node (`c` beyond the model's colliders:
    /// ignored).
    pub fn add_collider(&mut self, c: usize, force: DVec3) {
        if let Some(sum) = self.colliders.get_mut(c) {
            *sum += force;
        }
    }
}

/// Where and why a run diverged (defined with the error that carries it).
pub use crate::error::Divergence;

/// What a GPU backend reports about a run besides the physics (`vulkan` only).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GpuReport {
    /// Device name.
    pub device: String,
    /// Float-atomic path of the scatter passes: `ext` or `cas`.
    pub atomics: String,
    /// Invocations per workgroup.
    pub workgroup_size: u32,
    /// GPU time per frame of each pass [ms], in execution order (empty without timestamps).
    pub passes: Vec<crate::gpu::PassTime>,
    /// Validation-layer warnings and errors (empty when validation is off).
    pub validation_messages: Vec<String>,
    /// Device memory the allocator holds in live allocations on this backend's context
    /// [bytes] (gpu-allocator's report; what a long run watches for growth).
    pub memory_in_use: u64,
}

/// A solver backend advancing one model in time. Backends are `Send`: a program (the Python
/// package) steps one on another thread than the one that made it.
pub trait Backend: Send {
    /// Short name used on the command line and in reports (`cpu-ref`, `cpu`, `vulkan`).
    fn name(&self) -> &'static str;
    /// Advances one frame (`substeps` time steps).
    fn step_frame(&mut self) -> Result<()>;
    /// Total signed volume and inverted-tet count of the current positions.
    fn volume(&mut self) -> Result<VolumeSample>;
    /// Copies the current state out (a full readback on the GPU: not for every frame).
    fn state(&mut self) -> Result<State>;
    /// The likely cause a divergence report names, with advice
    /// ([`crate::stability::likely_cause`] of its model and parameters).
    fn likely_cause(&self) -> &str;
    /// Replaces every node's position and velocity between frames (a full upload on the
    /// GPU). Inverse masses stay the model's, so a pinned node (inverse mass 0) stays where
    /// it is put and then moves at the velocity it is given: this is how a program drags
    /// pinned nodes (`examples/pull.rs`). Fails unless `state` has one finite position and
    /// velocity per node.
    fn set_state(&mut self, state: &State) -> Result<()>;
    /// What its steps carry besides the state ([`Carried`]), for a checkpoint; by default
    /// an error saying the backend cannot save it.
    fn carried(&mut self) -> Result<Carried> {
        Err(crate::Error::param(
            "checkpoint",
            format!("the {} backend cannot save its state yet", self.name()),
        ))
    }
    /// Restores `state` and what the steps carry ([`Backend::carried`] of the same backend
    /// on the same problem): the next frame is the one the saved backend would have stepped.
    fn restore(&mut self, state: &State, carried: &Carried) -> Result<()> {
        let _ = (state, carried);
        Err(crate::Error::param(
            "checkpoint",
            format!("the {} backend cannot resume a checkpoint yet", self.name()),
        ))
    }
    /// Frames [`Backend::submit_frame`] may queue before [`Backend::collect_frame`] must
    /// finish the oldest: 1 (the default) for a backend whose frames finish as they are
    /// submitted; 2 for `vulkan`, whose next frame runs while the host reads the last.
    fn frames_in_flight(&self) -> usize {
        1
    }
    /// Starts the next frame: queues it (a GPU backend returns without waiting for it) or,
    /// by default, steps it. At most [`Backend::frames_in_flight`] frames may be started and
    /// not yet collected; [`Backend::state`], [`Backend::volume`] and
    /// [`Backend::set_state`] first finish every started frame (without its divergence
    /// check: collect the frames a run cares about).
    fn submit_frame(&mut self) -> Result<()> {
        self.step_frame()
    }
    /// Finishes the oldest started frame: waits for it, reports its divergence as
    /// [`crate::Error::Diverged`], and with `sample` returns its volume measures. With no
    /// frame started (or all finished by a state read), it only takes the sample.
    fn collect_frame(&mut self, sample: bool) -> Result<Option<VolumeSample>> {
        match sample {
            true => self.volume().map(Some),
            false => Ok(None),
        }
    }
    /// The forces the supports exerted in the last step of the last frame
    /// ([`Reactions`]); `None` where the backend does not measure them (`vulkan` without
    /// per-frame metrics).
    fn reactions(&mut self) -> Result<Option<Reactions>> {
        Ok(None)
    }
    /// Forgets the GPU pass times measured so far, so a benchmark times only the frames after
    /// its warm-up; nothing on backends without GPU timing.
    fn reset_timing(&mut self) -> Result<()> {
        Ok(())
    }
    /// Device, atomic path and per-pass GPU times; `None` for CPU backends.
    fn gpu_report(&mut self) -> Result<Option<GpuReport>> {
        Ok(None)
    }
}

mod carried;
pub use carried::{flatten, restore_coarse, unflatten, Carried, COARSE_KEY};

pub mod cpu;
pub mod vulkan;
