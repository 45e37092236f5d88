//! The finite elements' rigid-part correction on the GPU (`elastic_rigid#part`,
//! `elastic_product#correction`, `elastic_curvature#correction`, `elastic_rigid#apply`)
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
use gpu_support::twin;
use tetrasim::gpu::commands::one_shot;
use tetrasim::gpu::Buffer;
use tetrasim::physics::{
    correction_length, elastic_linearise, elastic_product, held_mass, ElasticLinear, RigidPart,
};
use tetrasim::shaders::file;

/// cpu-ref's rigid-part correction on the increments `s.sum` at the first linearisation
/// (`elastic_group`'s last iteration): each free object's increments less its rigid part,
/// scaled by the correction's length where a contact holds it; and that length.
fn reference_correction(s: &Scene) -> (Vec<DVec3>, f64) {
    let (model, nodes, dt, at) = (&s.model, &s.nodes, s.params.dt, &s.first);
    let linear: Vec<ElasticLinear<DVec3>> = (model.tets.iter().zip(&nodes.tets))
        .map(|(tet, e)| elastic_linearise(e, tet.map(|k| at[k as usize])))
        .collect();
    let rows = reference_rows(s, at, &linear);
    let x = &model.positions;
    let w = &model.inv_mass;
    let moved = |i: usize| held_mass(nodes.mass[i], rows[i].2);
    let elastic = |i: usize| {
        let (f, floor) = s.force[i];
        f - s.params.gravity * model.mass[i] - DVec3::Y * floor + s.sum[i]
    };
    let mut sum = s.sum.clone();
    let mut length = 1.0;
    for object in &nodes.free_objects {
        let part = RigidPart::of(object.clone().map(|i| (x[i], moved(i), elastic(i))));
        if object.clone().any(|i| rows[i].2 != DVec3::ZERO) {
            let n = model.node_count();
            let mut d = vec![DVec3::ZERO; n];
            for i in object.clone() {
                d[i] = -part.force(x[i], moved(i)) * (w[i] * dt * dt);
            }
            let corners: Vec<[DVec3; 4]> = (model.tets.iter().zip(&nodes.tets).zip(&linear))
                .map(|((tet, t), lin)| elastic_product(t, lin, tet.map(|k| d[k as usize])))
                .collect();
            let (mut gain, mut curvature) = (0.0, 0.0);
            for i in object.clone() {
                let corner = |item: usize| corners[item / 4][item % 4];
                let q = nodes.product(i, w[i], dt, d[i], rows[i].2, corner);
                gain += rows[i].0.dot(d[i]);
                curvature += d[i].dot(q);
            }
            length = correction_length(gain, curvature);
        }
        for i in object.clone() {
            sum[i] -= part.force(x[i], moved(i)) * length;
        }
    }
    (sum, length)
}

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
        let size = gpu.node_bytes + 64;
        let readback = Buffer::readback(&gpu.ctx, "readback", size).unwrap();
        let key = |name: &str, variant: &str| format!("{name}#{variant}");
        let rigid = file::PASSES_ELASTIC_RIGID_COMP;
        let passes = [
            (gpu.pass(file::PASSES_ELASTIC_LINEARISE_COMP, &[]), t),
            (gpu.pass(file::PASSES_ELASTIC_ROWS_COMP, &[]), n),
            (
                gpu.pass(&key(rigid, "part"), &[]),
                objects * WORKGROUP as usize,
            ),
            (
                gpu.pass(&key(file::PASSES_ELASTIC_PRODUCT_COMP, "correction"), &[]),
                t,
            ),
            (
                gpu.pass(&key(file::PASSES_ELASTIC_CURVATURE_COMP, "correction"), &[]),
                n,
            ),
            (
                gpu.pass(&key(rigid, "apply"), &[]),
                objects * WORKGROUP as usize,
            ),
        ];
        one_shot(&gpu.ctx, |cmd| {
            for (pass, elements) in &passes {
                gpu.dispatch(cmd, pass, *elements);
            }
            gpu.snapshot(cmd, &readback, 0);
            twin::to_host(&gpu.ctx, cmd, &readback);
        })
        .unwrap();
        let floats = twin::floats(&gpu.ctx, &readback);
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
