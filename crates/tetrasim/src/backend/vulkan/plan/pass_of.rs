//! How a stage of the schedule becomes a pass of the plan: its shader variant, its
//! specialisation constants, its workgroup size and its invocations.

use super::anderson::{anderson_chunks, mixed_multipliers};
use super::GLOBAL_WORKGROUP;
use super::{workgroups, BodyCounts, GlobalCounts, MinresCounts, PassPlan, PlanCounts, Variant};
use crate::model::ConstraintKind;
use crate::params::SimParams;
use crate::schedule::{BufferId, Domain, PassKind, Schedule, Stage};

impl PassPlan {
    /// The pass that runs `stage` of `schedule` for a model of `counts`: the shader variant
    /// of the schedule's path (gather or atomics, Chebyshev), the floor or the global
    /// chunks as specialisation constants, and the invocations of its domain.
    pub fn of(
        stage: &Stage,
        schedule: &Schedule,
        counts: PlanCounts,
        global: Option<GlobalCounts>,
        workgroup_size: u32,
        params: &SimParams,
    ) -> Self {
        let floor = u32::from(params.floor);
        let chebyshev = !schedule.chebyshev.is_empty();
        // Kinematic colliders and grabs (colliders are refused with Chebyshev by
        // `Problem::new`): whether the floor's stages solve them.
        let colliders = match chebyshev {
            true => 0,
            false => schedule.colliders,
        };
        let solve = !chebyshev && (colliders > 0 || schedule.grabs);
        let variant = match (stage.kind, schedule.gather) {
            (PassKind::ConstraintApply, true) if solve => Variant::Named("gather_colliders"),
            (PassKind::ConstraintApply, false) if solve => Variant::Named("sums_colliders"),
            (PassKind::Integrate, _) if schedule.split && solve => {
                Variant::Named("colliders_split")
            }
            (PassKind::Integrate, _) if schedule.split => Variant::Named("split"),
            (
                PassKind::Integrate
                | PassKind::GlobalVolume
                | PassKind::GlobalVolumeSum
                | PassKind::SplitVelocity
                | PassKind::ElasticContacts
                | PassKind::ElasticStart
                | PassKind::Elastic
                | PassKind::ElasticRigidPart,
                _,
            ) if solve => Variant::Named("colliders"),
            (PassKind::SpringScatter, _) => Variant::Atomics,
            (
                PassKind::SpringConstraint
                | PassKind::Distance
                | PassKind::Volume
                | PassKind::InversionFloor,
                true,
            ) => Variant::Named("gather"),
            (
                PassKind::SpringConstraint
                | PassKind::Distance
                | PassKind::Volume
                | PassKind::InversionFloor,
                false,
            ) => Variant::Atomics,
            (PassKind::ConstraintApply, true) if chebyshev => Variant::Named("gather_chebyshev"),
            (PassKind::ConstraintApply, true) => Variant::Named("gather"),
            (PassKind::ConstraintApply, false) if chebyshev => Variant::Named("chebyshev"),
            (PassKind::ConstraintApply, false) => Variant::Named("sums"),
            (PassKind::ContactMeasure, _) => {
                match (colliders > 0, stage.touches(BufferId::Contacts)) {
                    (true, true) => Variant::Named("colliders_bodies"),
                    (true, false) => Variant::Named("colliders"),
                    _ => Variant::Named("bodies"),
                }
            }
            _ => Variant::Plain,
        };
        // The global passes reduce in shared memory per chunk of an object's surface: one
        // workgroup per chunk of every object, its chunk count and the floor as constants.
        let global_workgroup = workgroup_size.min(GLOBAL_WORKGROUP);
        let (workgroup_size, mut constants) = match (stage.domain, global) {
            (Domain::Surface, Some(g)) => {
                (global_workgroup, vec![floor, g.chunks(global_workgroup)])
            }
            _ if stage.kind.has_floor_constant() => (workgroup_size, vec![floor]),
            _ => (workgroup_size, Vec::new()),
        };
        if stage.kind == PassKind::ClampDrive {
            constants = vec![counts.clamped, counts.clamps];
        }
        if stage.kind == PassKind::InversionFloor {
            constants = vec![(schedule.inversion_floor as f32).to_bits()];
        }
        // The collider count follows the floor's constants (id 2, or 3 after the chunks).
        // Then the grabbed nodes' count (the rows of one step's grab targets).
        if solve && stage.kind.has_floor_constant() {
            constants.extend([colliders, counts.grabbed]);
        }
        // The finite elements' step checks the colliders (constants 2 and 3).
        if solve && stage.kind == PassKind::Elastic {
            constants = vec![floor, colliders, counts.grabbed];
        }
        if stage.kind == PassKind::ContactMeasure && colliders > 0 {
            constants = vec![colliders];
        }
        // The gather's lanes per node (constant 4, after the colliders' and grabs').
        let lanes = match (stage.kind, schedule.gather) {
            (PassKind::ConstraintApply, true) => {
                workgroups::gather_lanes(schedule, counts.nodes, workgroup_size)
            }
            _ => 1,
        };
        if lanes > 1 {
            constants.resize(3, 0);
            constants.push(lanes);
        }
        // Anderson's passes reduce per workgroup (a chunk of nodes) in shared memory, as
        // the global passes do: the floor, the chunks, the colliders and grabs (0 without)
        // and the memory as constants 1 to 5.
        let mut workgroup_size = workgroup_size;
        let mut variant = variant;
        if matches!(stage.kind, PassKind::AndersonSum | PassKind::AndersonMix) {
            workgroup_size = global_workgroup;
            let chunks = anderson_chunks(counts.nodes, workgroup_size);
            let (c, g) = if solve {
                (colliders, counts.grabbed)
            } else {
                (0, 0)
            };
            let (springs, tets) = mixed_multipliers(schedule, counts);
            constants = vec![floor, chunks, c, g, schedule.anderson, springs, tets];
            variant = match solve && stage.kind == PassKind::AndersonMix {
                true => Variant::Named("colliders"),
                false => Variant::Plain,
            };
        }
        // Forces out: `integrate` leaves each node's holding inputs (constant 5, after the
        // finite elements' ELASTIC_WARM), `reactions` sums them per workgroup in shared
        // memory, its colliders and clamps as constants 1 and 2.
        if schedule.runs(PassKind::Reactions) {
            if stage.kind == PassKind::Integrate {
                constants.resize(4, 0);
                constants.push(1);
            }
            if stage.kind == PassKind::Reactions {
                workgroup_size = global_workgroup;
                constants = vec![schedule.colliders, counts.clamps];
                if schedule.runs(PassKind::Elastic) {
                    variant = Variant::Named("elastic");
                }
            }
        }
        let constraints = |sweep: Option<usize>| match sweep.map(|s| schedule.sweeps[s].kind) {
            Some(ConstraintKind::Volume) => counts.tets,
            _ => counts.springs,
        };
        let elements = match (stage.domain, global) {
            (Domain::Nodes, _) if stage.kind == PassKind::ClampDrive => counts.clamped,
            (Domain::Nodes, _) => counts.nodes * lanes,
            (Domain::Springs, _) => counts.springs,
            (Domain::Tets, _) => counts.tets,
            (Domain::Group, _) => constraints(stage.sweep),
            (Domain::Surface, Some(g)) => g.objects * g.chunks(global_workgroup) * global_workgroup,
            (Domain::Surface, None) => 0,
            // MINRES's row passes: set with their constants below; the finite elements'
            // workgroup passes with the coarse level's sizes (EnginePlan::with_elastic).
            (Domain::Rows | Domain::Coarse, _) => 0,
        };
        // Block Gauss-Seidel: a stage of a blocked sweep (its constraints, the inversion
        // floor) runs one workgroup per block.
        let blocks = stage.sweep.and_then(|s| schedule.sweeps[s].blocks);
        let (variant, workgroup_size, elements) = match blocks {
            Some(shape) if schedule.gather => {
                let size = workgroups::for_blocks(shape);
                constants.resize(1, 0); // BLOCK_SWEEPS is constant 2, after the floor's
                constants.push(schedule.block_sweeps_of(stage.kind));
                (Variant::Named("block"), size, shape.blocks * size)
            }
            _ => (variant, workgroup_size, elements),
        };
        let pass = PassPlan {
            stage: stage.clone(),
            variant,
            constants,
            workgroup_size,
            elements,
        };
        match MinresCounts::of(schedule, counts, global, global_workgroup) {
            Some(m) if pass.stage.kind.is_minres() => {
                let (c, g) = match solve {
                    true => (colliders, counts.grabbed),
                    false => (0, 0),
                };
                pass.minres(m, [floor, c, g], schedule.minres, counts.nodes)
            }
            _ => pass,
        }
    }

    /// A MINRES pass ([`MinresCounts`]): the row passes' workgroup (its sums' layout) and
    /// invocations (the fixed rows', then a workgroup per object), the node passes' `LANES`
    /// per node ([`workgroups::lanes`] over the rows' entries; `minres_nodes` as many
    /// workgroups as the row passes when they are more), the setup's one; the floor,
    /// colliders and grabs as constants 1 to 3, the node passes' lanes as 4 (0 in the
    /// others), MINRES's sizes from 5 on; the variants of the rows' segments and of the
    /// colliders.
    fn minres(mut self, m: MinresCounts, contacts: [u32; 3], iterations: u32, nodes: u32) -> Self {
        let kind = self.stage.kind;
        let lanes = match kind {
            PassKind::MinresNodes | PassKind::MinresForces => {
                workgroups::lanes(m.entries(), nodes, m.workgroup)
            }
            _ => 0,
        };
        self.constants = contacts.to_vec();
        self.constants.push(lanes);
        self.constants.extend(m.constants(iterations));
        self.variant = match kind {
            PassKind::MinresRows => Variant::Named(m.kinds.variant()),
            PassKind::MinresFinish => match m.finish_variant() {
                "plain" => Variant::Plain,
                v => Variant::Named(v),
            },
            PassKind::MinresSetup | PassKind::MinresForces
                if contacts[1] > 0 || contacts[2] > 0 =>
            {
                Variant::Named("colliders")
            }
            _ => Variant::Plain,
        };
        self.workgroup_size = m.workgroup;
        let rows = m.workgroups() * m.workgroup;
        let node_lanes = nodes * lanes.max(1);
        self.elements = match (kind, self.stage.domain) {
            // Each workgroup a node workgroup, then a row workgroup that ends the last
            // iteration: as many as the larger part needs.
            (PassKind::MinresNodes, _) => {
                (node_lanes.div_ceil(m.workgroup) * m.workgroup).max(rows)
            }
            (_, Domain::Rows) => rows,
            _ => node_lanes,
        };
        self
    }

    /// A body contact pass's elements, constants and variant (nothing for the others):
    /// the broad phase's count and fill per triangle, its scan in one workgroup, the find
    /// and solve per surface node (the solve on the device's float-atomic path), the apply
    /// per node with the floor and collider constants of [`Self::of`].
    pub(super) fn body_contact(
        &mut self,
        body: BodyCounts,
        counts: PlanCounts,
        workgroup_size: u32,
    ) {
        let elements = match self.stage.kind {
            PassKind::ContactCount | PassKind::ContactFill => body.triangles,
            PassKind::ContactScan => workgroup_size,
            PassKind::ContactFind | PassKind::ContactSolve => body.nodes,
            PassKind::ContactApply => {
                self.elements = counts.nodes;
                if self.constants.len() > 1 {
                    self.variant = Variant::Named("colliders");
                }
                return;
            }
            _ => return,
        };
        self.elements = elements;
        self.constants = body.constants();
        if self.stage.kind == PassKind::ContactSolve {
            self.variant = Variant::Atomics;
        }
    }
}
