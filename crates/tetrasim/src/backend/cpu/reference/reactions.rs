//! `cpu-ref`'s forces out: what the pins, the floor and the colliders exert on the bodies in
//! a step ([`Reactions`]).

use glam::DVec3;

use super::{Forces, ReferenceBackend};
use crate::backend::Reactions;
use crate::schedule::family::Family;

impl ReferenceBackend {
    /// The reactions of a step whose full solve found `forces`, the nodes now at the step's
    /// end. A pinned node's holding force is minus every other force on it: gravity, the
    /// springs', the constraints' and contact's from the solve; the finite elements' is
    /// minus the energy's gradient at the step's end (the solve's increments leave pinned
    /// nodes out).
    pub(super) fn reactions_of(&self, forces: &Forces) -> Reactions {
        let model = &self.problem.model;
        let mut out = Reactions::none(model.colliders.len(), model.clamps.len());
        let elastic = self.families.iter().find_map(|f| match f {
            Family::Elastic(nodes) => Some(nodes),
            _ => None,
        });
        for contact in &forces.contacts {
            if let Some(touch) = contact.touching {
                out.add_collider(touch.collider, contact.force);
            }
        }
        out.floor = DVec3::Y * forces.floor.iter().sum::<f64>();
        let pinned = (0..model.node_count()).filter(|&i| model.inv_mass[i] <= 0.0);
        out.add_pinned(pinned, &self.clamp_of, |i| {
            let outer = forces.gravity[i]
                + forces.springs[i]
                + DVec3::Y * forces.floor[i]
                + forces.contacts[i].force;
            let inner = match elastic {
                Some(nodes) => -nodes.gradient(i, &model.tets, &|k| self.x[k]).0,
                None => forces.constraints[i],
            };
            -(outer + inner)
        });
        out
    }
}
