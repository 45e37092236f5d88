//! What a scene adds to the step: clamps, kinematic colliders and grabs, and the frame's
//! measures (`volume_sum`, `contact_measure`).

use super::stages::stage;
use super::{Access, BufferId, Domain, PassKind, Repeat, Schedule, Stage};

impl Schedule {
    /// The same schedule with `clamped` nodes held by clamps: `clamp_drive` first in every
    /// step, setting their velocities from the host's per-step clamp poses.
    pub fn with_clamps(mut self, clamped: u32) -> Self {
        use Access::{Read, ReadWrite};
        use BufferId::*;
        if clamped > 0 {
            let bindings = vec![
                (Positions, Read),
                (ClampNodes, Read),
                (ClampPoses, Read),
                (Velocities, ReadWrite),
            ];
            let drive = stage(
                PassKind::ClampDrive,
                Repeat::Substep,
                Domain::Nodes,
                bindings,
            );
            self.stages.insert(0, drive);
        }
        self
    }

    /// The same schedule with `colliders` kinematic colliders and, when `grabs`, grabs:
    /// every stage that solves the floor ([`PassKind::has_floor_constant`]) solves their
    /// contacts (a grabbed node's attachment first) too, reading their data, poses and
    /// attachments and keeping their force in [`BufferId::ColliderContacts`]; MINRES's
    /// setup reads their forces and the grabbed nodes, and `global_volume_sum` their forces
    /// (the nodes they hold).
    pub fn with_colliders(mut self, colliders: u32, grabs: bool) -> Self {
        use Access::{Read, ReadWrite};
        use BufferId::*;
        self.colliders = colliders;
        self.grabs = grabs;
        if colliders > 0 || grabs {
            for stage in (self.stages.iter_mut()).filter(|s| s.kind.has_floor_constant()) {
                stage.bindings.extend([
                    (ColliderContacts, ReadWrite),
                    (Colliders, Read),
                    (ColliderGrids, Read),
                    (ColliderPoses, Read),
                    (GrabNodes, Read),
                    (GrabTargets, Read),
                ]);
            }
            // MINRES holds the nodes the colliders push or the grabs hold.
            for stage in (self.stages.iter_mut()).filter(|s| s.kind == PassKind::MinresSetup) {
                stage
                    .bindings
                    .extend([(ColliderContacts, Read), (GrabNodes, Read)]);
            }
            // The finite elements' step checks where the nodes end against the colliders,
            // and their rigid part leaves the colliders' force out.
            for stage in self.stages.iter_mut() {
                match stage.kind {
                    PassKind::Elastic => stage.bindings.extend([
                        (ColliderContacts, Read),
                        (Colliders, Read),
                        (ColliderGrids, Read),
                        (ColliderPoses, Read),
                        (GrabNodes, Read),
                        (GrabTargets, Read),
                    ]),
                    PassKind::ElasticRigidPart => stage.bindings.push((ColliderContacts, Read)),
                    _ => {}
                }
            }
            // The global volume constraints count the nodes the colliders hold.
            for stage in (self.stages.iter_mut()).filter(|s| s.kind == PassKind::GlobalVolumeSum) {
                stage.bindings.push((ColliderContacts, Read));
            }
        }
        self
    }
}

/// The `volume_sum` stage (per frame with metrics; on demand otherwise).
pub fn volume_sum() -> Stage {
    use Access::{Read, Write};
    use BufferId::*;
    stage(
        PassKind::VolumeSum,
        Repeat::Frame,
        Domain::Tets,
        vec![
            (Positions, Read),
            (Tets, Read),
            (RestVolumes, Read),
            (Partials, Write),
        ],
    )
}

impl Schedule {
    /// The same schedule with the `reactions` stage when `metrics` are taken per frame: once
    /// per frame after the last step it sums the forces the pins, the floor, the colliders
    /// and the clamps exerted in that step from what `integrate` leaves for it (and, with
    /// the finite elements, their elastic forces at the pinned nodes).
    pub fn with_reactions(mut self, metrics: bool) -> Self {
        use Access::{Read, Write};
        use BufferId::*;
        if !metrics {
            return self;
        }
        let mut bindings = vec![
            (Positions, Read),
            (ReactionInputs, Read),
            (NodeClamps, Read),
            (ReactionPartials, Write),
        ];
        if self.runs(PassKind::Elastic) {
            bindings.extend([
                (Tets, Read),
                (ElasticTets, Read),
                (NodeTetOffsets, Read),
                (NodeTetItems, Read),
            ]);
        }
        let reactions = stage(PassKind::Reactions, Repeat::Frame, Domain::Nodes, bindings);
        let at = super::before(&self.stages, PassKind::Reactions);
        self.stages.insert(at, reactions);
        self
    }

    /// The same schedule with the `contact_measure` stage when `metrics` are taken per frame
    /// and the frame has kinematic colliders ([`Self::with_colliders`]) or body contact
    /// ([`Self::with_body_contact`]): once per frame after `check`, it reads the end-of-frame
    /// positions, the colliders' touching flags and poses and the body contacts, and adds
    /// into the status's contact words.
    pub fn with_contact_measure(mut self, metrics: bool) -> Self {
        use Access::{Read, ReadWrite};
        use BufferId::*;
        let colliders = self.colliders > 0;
        let bodies = self.runs(PassKind::ContactFind);
        if !metrics || !(colliders || bodies) {
            return self;
        }
        let mut bindings = vec![(Positions, Read)];
        if colliders {
            bindings.extend([
                (ColliderContacts, Read),
                (Colliders, Read),
                (ColliderGrids, Read),
                (ColliderPoses, Read),
            ]);
        }
        if bodies {
            bindings.push((Contacts, Read));
        }
        bindings.push((Status, ReadWrite));
        let measure = stage(
            PassKind::ContactMeasure,
            Repeat::Frame,
            Domain::Nodes,
            bindings,
        );
        let at = super::before(&self.stages, PassKind::ContactMeasure);
        self.stages.insert(at, measure);
        self
    }
}
