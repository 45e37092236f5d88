//! The finite elements' rigid-part correction on the GPU (`elastic_rigid_part`,
//! `elastic_correction_product`, `elastic_correction_curvature`, `elastic_rigid_apply`)
//! equals cpu-ref's (`elastic_group`'s last iteration: `RigidPart` of each free object's
//! elastic forces, a held node weighing nothing, taken off whole where nothing holds the
//! body, and as far as it lowers the step's quadratic model, `correction_length`, where a
//! contact holds it), on the free rubber block of tests/elastic_twin. A brick of `vulkan`'s
//! finite elements (docs/GPU.md, "Finite elements on the GPU").

mod common;
mod elastic_twin;
mod gpu_support;

use elastic_twin::*;
use glam::DVec3;
use tetrasim::physics::{elastic_linearise, ElasticLinear};
use tetrasim::shaders::file;

#[test]
fn the_gpu_rigid_part_correction_equals_its_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let mut lengths = Vec::new();
    // Increments whose rigid part is large against the residual: on the held block the
    // model takes only part of the correction.
    for held in [false, true] {
        let mut s = scene_free(held);
        s.sum = s.sum.iter().map(|v| *v * 300.0 + DVec3::Y).collect();
        if held {
            // Nearly in balance: the residual a thousandth of the scene's.
            let linear: Vec<ElasticLinear<DVec3>> = (s.model.tets.iter().zip(&s.nodes.tets))
                .map(|(tet, e)| elastic_linearise(e, tet.map(|k| s.first[k as usize])))
                .collect();
            let rows = reference_rows(&s, &s.first, &linear);
            for (phi, row) in s.phi.iter_mut().zip(&rows) {
                *phi = f32_round(*phi + row.0 * 0.999);
            }
        }
        let (want, length) = reference_correction(&s);
        let gpu = Gpu::new(&s);
        let (n, t) = (s.model.node_count(), s.model.tets.len());
        let objects = s.model.objects.len() - 1;
        let kernels = [
            gpu.pass(file::PASSES_ELASTIC_LINEARISE_COMP, &[]),
            gpu.pass(file::PASSES_ELASTIC_ROWS_COMP, &[]),
            gpu.pass(file::PASSES_ELASTIC_RIGID_PART_COMP, &[]),
            gpu.pass(file::PASSES_ELASTIC_CORRECTION_PRODUCT_COMP, &[]),
            gpu.pass(file::PASSES_ELASTIC_CORRECTION_CURVATURE_COMP, &[]),
            gpu.pass(file::PASSES_ELASTIC_RIGID_APPLY_COMP, &[]),
        ];
        let groups = objects * WORKGROUP as usize;
        let passes: Vec<(&_, usize)> = kernels.iter().zip([t, n, groups, t, n, groups]).collect();
        let floats = gpu.run(&passes, passes.len(), |_| {});
        let (planes, _) = snapshot_of(&floats, n, 0);
        let scale = want.iter().map(|v| v.length()).fold(0.0, f64::max);
        let changed = (want.iter().zip(&s.sum))
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max);
        let mut worst = 0.0f64;
        for i in 0..n {
            let off = (xyz(planes[SUM * n + i]) - want[i]).length() / scale;
            assert!(
                off <= 1e-4,
                "held {held}, node {i}: {:?} on the GPU, {} by definition",
                planes[SUM * n + i],
                want[i]
            );
            worst = worst.max(off);
        }
        println!("held {held}: correction length {length:.4}, largest change {changed:.3e} N: within {worst:.1e}");
        assert!(
            changed > 1e-3 * scale,
            "held {held}: the correction changes nothing"
        );
        lengths.push(length);
    }
    assert!(lengths[0] == 1.0 && lengths[1] < 1.0, "lengths {lengths:?}");
}
