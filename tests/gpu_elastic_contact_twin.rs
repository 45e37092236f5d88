//! The finite elements' contacts with kinematic colliders on the GPU (`elastic_start`'s
//! `colliders` variant) equal their definition: on the pinned rubber block of
//! tests/elastic_twin under a sphere that touches one top node and pushes a few others,
//! each node's elastic force so far (the colliders' force is not elastic), push and held
//! normal (`collider::held_normal`: the push's direction, else the first collider the node
//! ends within `HELD_GAP` of in strain) and touching flag. A brick of `vulkan`'s finite
//! elements (docs/GPU.md, "Finite elements on the GPU").

mod common;
mod elastic_twin;
mod gpu_support;

use elastic_twin::*;
use glam::DVec3;
use tetrasim::collider::{self, Collider};
use tetrasim::gpu::layout::binding;
use tetrasim::physics::end_position;
use tetrasim::shaders::file;

/// The block under a sphere of 2 cm whose surface passes a micrometre under the top node
/// nearest the block's middle, three top nodes pushed down by it so far.
fn scene_under_a_sphere() -> (Scene, usize) {
    let mut s = scene();
    let model = &s.model;
    let top = (0..model.node_count())
        .filter(|&i| (model.positions[i].y - 0.06).abs() < 1e-9)
        .min_by(|&a, &b| {
            let middle = DVec3::new(0.06, 0.06, 0.03);
            let d = |i: usize| (model.positions[i] - middle).length();
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let (x, v, w) = (model.positions[top], s.velocity[top], model.inv_mass[top]);
    let at = end_position(x, v, s.force[top].0, w, s.params.dt);
    // A micrometre into it: exactly on the surface, `may_touch`'s reach (the radius plus
    // the contact thickness, 0 here) would let f32 and f64 disagree.
    let sphere = Collider::sphere(at + DVec3::Y * (0.02 - 1e-6), 0.02);
    s.model = s.model.clone().with_colliders(vec![sphere]).unwrap();
    let tops: Vec<usize> = (0..s.model.node_count())
        .filter(|&i| (s.model.positions[i].y - 0.06).abs() < 1e-9 && i != top)
        .take(3)
        .collect();
    for &i in &tops {
        s.contacts[i] = DVec3::new(0.01, -0.2, 0.0);
        s.force[i].0 += s.contacts[i];
    }
    (s, top)
}

#[test]
fn the_gpu_start_against_colliders_equals_its_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let (s, touched) = scene_under_a_sphere();
    let (model, dt) = (&s.model, s.params.dt);
    let n = model.node_count();
    let gpu = Gpu::new(&s);
    let key = format!("{}#colliders", file::PASSES_ELASTIC_START_COMP);
    let start = gpu.pass(&key, &[0, 1, 0]);
    let floats = gpu.run(&[(&start, n)], 1, |_| {});
    let (planes, _) = snapshot_of(&floats, n, 0);
    let colliders = collider::at_step(&model.colliders, 0, dt);
    let (mut pushed, mut resting) = (0, 0);
    for i in 0..n {
        let (f, floor) = s.force[i];
        let (x, v, w) = (model.positions[i], s.velocity[i], model.inv_mass[i]);
        let at = end_position(x, v, f, w, dt);
        let contact = s.contacts[i];
        let phi = f - s.params.gravity * model.mass[i] - DVec3::Y * floor - contact;
        let reach = s.nodes.reach[i];
        let normal = collider::held_normal(Some(floor > 0.0), contact, at, reach, &colliders);
        let close = |what: &str, got: [f32; 4], want: DVec3| {
            let off = (xyz(got) - want).length() / want.length().max(1.0);
            assert!(
                off <= 1e-6,
                "node {i}: {what} {got:?} on the GPU, {want} by definition"
            );
        };
        close("elastic force", planes[PHI * n + i], phi);
        close("held normal", planes[NORMAL * n + i], normal);
        let touching = floor > 0.0 || contact != DVec3::ZERO;
        assert_eq!(
            planes[NORMAL * n + i][3] > 0.0,
            touching,
            "node {i}: touching"
        );
        pushed += usize::from(contact != DVec3::ZERO && floor == 0.0);
        resting += usize::from(contact == DVec3::ZERO && floor == 0.0 && normal != DVec3::ZERO);
    }
    println!(
        "{pushed} nodes pushed by the sphere, {resting} resting on it unpushed (node {touched})"
    );
    assert!(
        pushed == 3 && resting >= 1,
        "{pushed} pushed, {resting} resting"
    );
}

#[test]
fn the_gpu_rigid_part_leaves_the_colliders_force_out() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // The free block, unheld, three of its nodes pushed by a collider so far.
    let mut s = scene_free(false);
    for i in [5, 40, 77] {
        s.contacts[i] = DVec3::new(0.3, 1.0, -0.2);
        s.force[i].0 += s.contacts[i];
    }
    let (want, _) = reference_correction(&s);
    let gpu = Gpu::new(&s);
    let n = s.model.node_count();
    let objects = s.model.objects.len() - 1;
    let part = format!("{}#colliders", file::PASSES_ELASTIC_RIGID_PART_COMP);
    let (part, apply) = (
        gpu.pass(&part, &[]),
        gpu.pass(file::PASSES_ELASTIC_RIGID_APPLY_COMP, &[]),
    );
    let groups = objects * WORKGROUP as usize;
    let floats = gpu.run(&[(&part, groups), (&apply, groups)], 2, |_| {});
    let (planes, _) = snapshot_of(&floats, n, 0);
    let scale = want.iter().map(|v| v.length()).fold(0.0, f64::max);
    for i in 0..n {
        let off = (xyz(planes[SUM * n + i]) - want[i]).length() / scale;
        assert!(
            off <= 1e-5,
            "node {i}: {:?} on the GPU, {} by definition",
            planes[SUM * n + i],
            want[i]
        );
    }
}

#[test]
fn a_free_node_ending_inside_a_collider_relinearises_on_the_gpu() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let (s, _) = scene_under_a_sphere();
    let n = s.model.node_count();
    let dt = s.params.dt;
    let colliders = collider::at_step(&s.model.colliders, 0, dt);
    // A checked step of 1 along a direction that moves every node by `lift`: lifted 1 mm
    // (off the floor), the nodes under the sphere end inside it; moved 10 cm aside too, none
    // ends inside it or the floor.
    let (up, aside) = (DVec3::Y * 1e-3, DVec3::new(0.0, 1e-3, 0.1));
    for (lift, inside) in [(up, true), (aside, false)] {
        let gpu = Gpu::new(&s);
        let key = format!("{}#colliders", file::PASSES_ELASTIC_START_COMP);
        let start = gpu.pass(&key, &[0, 1, 0]);
        let key = format!("{}#colliders", file::PASSES_ELASTIC_COMP);
        let update = gpu.pass(&key, &[0, 1, 0]);
        // After the start: the step of 1 (ALPHA) checked (CHECK), along `lift`.
        let floats = gpu.run(&[(&start, n), (&update, n)], 1, |cmd| {
            gpu.set_plane(cmd, P, lift);
            gpu.set_word(cmd, binding::ELASTIC_STATE, 2, 1.0f32.to_bits());
            gpu.set_word(cmd, binding::ELASTIC_STATE, 6, 1);
        });
        let (planes, state) = snapshot_of(&floats, n, 0);
        let want = (0..n).any(|k| {
            let end = xyz(planes[AT * n + k]) + lift;
            let free = s.model.inv_mass[k] > 0.0;
            collider::enters_unheld(free, DVec3::ZERO, true, &colliders, end)
        });
        assert_eq!(want, inside, "lift {lift}: the reference");
        assert_eq!(
            state[7].to_bits() != 0,
            want,
            "lift {lift}: relinearise on the GPU"
        );
    }
}
