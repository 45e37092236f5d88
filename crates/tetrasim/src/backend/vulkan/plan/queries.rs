//! What a plan holds and moves: buffer and pass look-ups, dispatches, bytes per frame.

use super::*;

impl EnginePlan {
    /// MINRES's sizes, when the step runs it.
    pub fn minres_counts(&self) -> Option<MinresCounts> {
        let workgroup = self.workgroup_size.min(GLOBAL_WORKGROUP);
        MinresCounts::of(&self.schedule, self.counts, self.global, workgroup)
    }

    /// MINRES's global rows' loop: the most surface nodes of one object, and how many of
    /// them each invocation of the object's one workgroup sums in `minres_rows` and
    /// `minres_product` (glsl/common/minres.glsl); `None` without MINRES's global rows.
    /// The cost model spreads a pass's work evenly over the multiprocessors, so it does not
    /// count this loop (docs/GPU.md, "MINRES's object rows in one workgroup").
    pub fn minres_object_loop(&self) -> Option<(u32, u32)> {
        let m = self.minres_counts().filter(|m| m.objects > 0)?;
        let nodes = self.global?.largest_nodes;
        Some((nodes, nodes.div_ceil(m.workgroup.max(1))))
    }

    /// Whether buffer `id` is built.
    pub fn has(&self, id: BufferId) -> bool {
        self.buffers.iter().any(|b| b.id == id)
    }

    /// The plan of buffer `id`, if it is built.
    pub fn buffer(&self, id: BufferId) -> Option<&BufferPlan> {
        self.buffers.iter().find(|b| b.id == id)
    }

    /// Whether every frame measures contact into the status's contact words (per-frame
    /// metrics with colliders, grabs or body contact; `contact_measure` runs when there are
    /// colliders or body contact, the words stay 0 with grabs alone).
    pub fn measures_contact(&self) -> bool {
        super::measures_contact(self.counts, self.metrics, self.body.is_some())
    }

    /// Whether pass `name` is part of the frame.
    pub fn has_pass(&self, name: &str) -> bool {
        PassKind::from_name(name).is_some_and(|k| self.runs(k))
    }

    /// Whether `pass` is part of the frame.
    pub fn runs(&self, pass: PassKind) -> bool {
        self.passes.iter().any(|p| p.stage.kind == pass)
    }

    /// How many times `pass` runs in a frame (twice per step for the solve's passes with
    /// split contact).
    pub fn runs_per_frame(&self, pass: &PassPlan) -> u32 {
        let solves = self.schedule.solves_running(pass.stage.kind);
        match pass.stage.repeat {
            Repeat::Substep | Repeat::AfterIterations => solves * self.schedule.substeps,
            Repeat::Minres => solves * self.schedule.substeps * self.schedule.minres,
            r @ (Repeat::Iteration | Repeat::FirstIteration | Repeat::LastIteration) => {
                let per_step = r.iterations_of(self.schedule.iterations) * self.groups_of(pass)
                    + match pass.stage.sweep {
                        // constraint_apply also follows every group of the restore sweeps.
                        None => self.schedule.restore_groups(),
                        Some(_) => 0,
                    };
                solves * self.schedule.substeps * per_step
            }
            Repeat::Restore => {
                solves
                    * self.schedule.substeps
                    * self.schedule.inversion_sweeps
                    * self.groups_of(pass)
            }
            Repeat::IterationEnd => {
                solves * self.schedule.substeps * self.schedule.iteration_ends(pass.stage.kind)
            }
            Repeat::Frame => 1,
        }
    }

    /// The blocks `pass` solves, when it is block Gauss-Seidel's.
    pub fn block_shape(&self, pass: &PassPlan) -> Option<crate::schedule::BlockShape> {
        let sweep = pass.stage.sweep.and_then(|s| self.schedule.sweeps.get(s))?;
        sweep.blocks.filter(|_| pass.solves_blocks())
    }

    /// Constraint groups solved one after another per iteration, over all sweeps (at
    /// least 1).
    pub fn group_count(&self) -> u32 {
        self.schedule.group_count()
    }

    /// The groups a per-iteration pass runs for in one iteration: its sweep's, or every
    /// sweep's for a pass of no sweep (at least 1).
    fn groups_of(&self, pass: &PassPlan) -> u32 {
        match pass.stage.sweep.and_then(|s| self.schedule.sweeps.get(s)) {
            Some(sweep) => sweep.groups.len().max(1) as u32,
            None => self.group_count(),
        }
    }

    /// Where sweep `index`'s groups, members and slots start in the buffers that hold every
    /// sweep one after another (degrees, group members, contributions, node-slot CSR).
    pub fn sweep_offsets(&self, index: usize) -> SweepOffsets {
        let mut at = SweepOffsets::default();
        let sweeps = &self.schedule.sweeps;
        for sweep in &sweeps[..index.min(sweeps.len())] {
            at.group += sweep.groups.len() as u32;
            at.member += sweep.constraints() as u32;
            at.slot += (sweep.corners() * sweep.constraints()) as u32;
            at.block += sweep.blocks.map_or(0, |b| b.blocks);
        }
        at
    }

    /// Dispatches of one frame (the timestamp count).
    pub fn dispatches_per_frame(&self) -> u32 {
        self.passes.iter().map(|p| self.runs_per_frame(p)).sum()
    }

    /// Labels of every pass in execution order: one time step's (the iteration group
    /// written `N x (a, b)`), then the frame's.
    pub fn pass_list(&self) -> Vec<String> {
        let mut out = self.step_list();
        out.extend(
            self.passes
                .iter()
                .filter(|p| p.stage.repeat == Repeat::Frame)
                .map(PassPlan::label),
        );
        out
    }

    /// Device-local bytes of all buffers.
    pub fn device_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.bytes).sum()
    }

    /// What the backend allocates for this plan with `slots` frame slots: its buffers on
    /// the device; on the host side the initial uploads' staging (at most every buffer's
    /// size, all of it alive at once) and each slot's readbacks.
    pub fn memory_needs(&self, slots: u32) -> MemoryNeeds {
        MemoryNeeds {
            device_local: self.device_bytes(),
            host_visible: self.device_bytes() + u64::from(slots) * self.readback_bytes(),
        }
    }

    /// Host-visible bytes copied back every frame.
    pub fn readback_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.readback_bytes).sum()
    }

    /// Bytes the host writes before every frame's submit (the collider poses).
    pub fn upload_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.upload_bytes).sum()
    }

    /// Bytes `pass` moves per run, estimated as every bound buffer streamed once per read
    /// and once per write (gathers through indices make the real traffic larger). A pass run
    /// once per constraint group streams only its group's share of its sweep's element
    /// buffers and of the buffers that hold every sweep's groups (degrees, members,
    /// contributions, slots).
    pub fn pass_bytes(&self, pass: &PassPlan) -> u64 {
        let all_groups = u64::from(self.group_count());
        let sweep_groups = u64::from(self.groups_of(pass));
        pass.stage
            .bindings
            .iter()
            .map(|(id, access)| {
                let size = self.buffer(*id).map_or(0, |b| b.bytes);
                let size = match (pass.stage.repeat, id) {
                    (
                        Repeat::Iteration | Repeat::Restore,
                        BufferId::Tets
                        | BufferId::RestVolumes
                        | BufferId::VolumeCompliance
                        | BufferId::VolumeMultipliers
                        | BufferId::Springs
                        | BufferId::SpringMultipliers
                        | BufferId::SpringDamping,
                    ) => size / sweep_groups,
                    (
                        Repeat::Iteration | Repeat::Restore,
                        BufferId::Degrees
                        | BufferId::GroupMembers
                        | BufferId::Contributions
                        | BufferId::NodeSlotOffsets
                        | BufferId::NodeSlotItems,
                    ) => size / all_groups,
                    // A dispatch reads its own substep's poses only.
                    (_, BufferId::ColliderPoses) => {
                        size / u64::from(POSE_SLOTS * self.schedule.substeps.max(1))
                    }
                    _ => size,
                };
                match access {
                    Access::Read | Access::Write => size,
                    Access::ReadWrite => 2 * size,
                }
            })
            .sum()
    }

    /// Estimated bytes moved per frame: every pass run plus the host copies and writes.
    pub fn bytes_per_frame(&self) -> u64 {
        let passes: u64 = self
            .passes
            .iter()
            .map(|p| u64::from(self.runs_per_frame(p)) * self.pass_bytes(p))
            .sum();
        passes + 2 * self.readback_bytes() + self.upload_bytes()
    }
}
