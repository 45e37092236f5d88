//! Forces out on the GPU (`Backend::reactions`): the buffers the `reactions` pass uses, and
//! the host's sum of its per-workgroup partials (docs/GPU.md, "Forces out").

use glam::DVec3;

use crate::backend::Reactions;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::schedule::BufferId;

/// The reactions' buffers (the plan builds them all, or none).
pub(crate) const BUFFERS: [BufferId; 3] = [
    BufferId::ReactionInputs,
    BufferId::NodeClamps,
    BufferId::ReactionPartials,
];

/// `NodeClamps`: per node, 1 + the clamp that holds it, 0 where none does.
pub(crate) fn node_clamps(model: &Model) -> Vec<u32> {
    let clamp_of = crate::collider::clamp_of_nodes(&model.clamps, model.node_count());
    (0..model.node_count())
        .map(|i| clamp_of.get(i).copied().flatten().map_or(0, |c| c + 1))
        .collect()
}

/// The reactions of `bytes`, the partials `reactions` left (per workgroup: the pins' force
/// with the floor's normal force in w, then each of `colliders` colliders' and each of
/// `clamps` clamps'), added in f64 over `groups` workgroups.
pub(crate) fn sum(
    bytes: &[u8],
    groups: usize,
    colliders: usize,
    clamps: usize,
) -> Result<Reactions> {
    let row = 1 + colliders + clamps;
    let partials: &[[f32; 4]] = bytes
        .get(..16 * row * groups)
        .and_then(|b| bytemuck::try_cast_slice(b).ok())
        .ok_or_else(|| {
            Error::Gpu(format!(
                "reaction partials readback holds {} bytes, {groups} rows of {row} vec4 expected",
                bytes.len()
            ))
        })?;
    let v = |p: &[f32; 4]| DVec3::new(p[0].into(), p[1].into(), p[2].into());
    let mut out = Reactions::none(colliders, clamps);
    for sums in partials.chunks(row) {
        out.pin += v(&sums[0]);
        out.floor.y += f64::from(sums[0][3]);
        for (k, p) in sums[1..1 + colliders].iter().enumerate() {
            out.colliders[k] += v(p);
        }
        for (c, p) in sums[1 + colliders..].iter().enumerate() {
            out.clamps[c] += v(p);
        }
    }
    Ok(out)
}
