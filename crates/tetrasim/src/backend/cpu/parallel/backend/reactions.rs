//! `cpu`'s forces out ([`Reactions`]): `integrate` keeps, per node, what each support did in
//! the step (a pinned node's total force, a collider's push and which collider, the floor's
//! normal force); [`ParallelBackend::reactions_now`] sums them in node order, in double
//! precision, as `cpu-ref` does.

use super::*;
use crate::backend::Reactions;

/// Per node, what the supports did in the last step (each vector empty when the model has
/// no such support).
#[derive(Debug, Clone, Default)]
pub(super) struct Supports {
    /// The pinned nodes.
    pinned: Vec<u32>,
    /// Per node: its total force in the step (written for pinned nodes only).
    pub(super) held: Vec<Vec3A>,
    /// Per node: the collider that pushed it last (`u32::MAX`: none) and the colliders'
    /// force on it.
    pub(super) pushed: Vec<(u32, Vec3A)>,
    /// Per node: the floor's normal force.
    pub(super) floor: Vec<f32>,
    colliders: usize,
    /// The model's clamp count and, per node, the clamp that holds it (each one's share of
    /// the pinned nodes' force).
    clamps: usize,
    clamp_of: Vec<Option<u32>>,
}

impl Supports {
    /// The supports of `model`, with or without the floor.
    pub(super) fn of(model: &Model, floor: bool) -> Self {
        let n = model.node_count();
        let pinned: Vec<u32> = (0..n as u32)
            .filter(|&i| model.inv_mass[i as usize] <= 0.0)
            .collect();
        Supports {
            held: vec![Vec3A::ZERO; if pinned.is_empty() { 0 } else { n }],
            pinned,
            pushed: match model.colliders.is_empty() {
                true => Vec::new(),
                false => vec![(u32::MAX, Vec3A::ZERO); n],
            },
            floor: vec![0.0; if floor { n } else { 0 }],
            colliders: model.colliders.len(),
            clamps: model.clamps.len(),
            clamp_of: crate::collider::clamp_of_nodes(&model.clamps, n),
        }
    }
}

impl ParallelBackend {
    /// The reactions of the last step. A pinned node's holding force is minus its total
    /// force; with finite elements, minus its outer forces and the energy's gradient at the
    /// step's end (the solve's increments leave pinned nodes out, as on `cpu-ref`).
    pub(super) fn reactions_now(&self) -> Reactions {
        let s = &self.supports;
        let mut out = Reactions::none(s.colliders, s.clamps);
        for &(c, force) in &s.pushed {
            out.add_collider(c as usize, force.as_dvec3());
        }
        out.floor = DVec3::Y * s.floor.iter().map(|&n| f64::from(n)).sum::<f64>();
        let elastic = self.sweeps.iter().find_map(|sweep| match &sweep.family {
            Family::Elastic(nodes) => Some(nodes),
            _ => None,
        });
        let pinned = s.pinned.iter().map(|&i| i as usize);
        out.add_pinned(pinned, &s.clamp_of, |i| {
            let held = s.held[i].as_dvec3();
            -match elastic {
                Some(nodes) => {
                    let x = &self.x;
                    held - nodes.gradient(i, &self.tets, &|k| x[k]).0.as_dvec3()
                }
                None => held,
            }
        });
        out
    }
}
