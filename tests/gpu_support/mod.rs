//! Fixtures of the GPU tests: skip only when no Vulkan device exists at all, small meshes,
//! and backends with the validation layer on.
#![allow(dead_code)]

// Tests with both `common` and `gpu_support` load this file twice; it holds one function.
#[allow(clippy::duplicate_mod)]
#[path = "../common/skip.rs"]
mod skip;

pub mod twin;

use glam::DVec3;
use tetrasim::backend::vulkan::{EngineOptions, VulkanBackend};
use tetrasim::backend::ContactSample;
use tetrasim::mesh::grid::box_tets;
use tetrasim::params::{Placement, SimParams};
use tetrasim::{Model, ModelBuilder};

/// Whether a Vulkan device exists; prints why the test is skipped when not.
pub fn vulkan_available() -> bool {
    match tetrasim::gpu::list_devices() {
        Ok(devices) if !devices.is_empty() => true,
        Ok(_) => {
            skip::skipped("no Vulkan device (install mesa-vulkan-drivers for lavapipe)");
            false
        }
        Err(e) => {
            skip::skipped(&format!("Vulkan is unavailable: {e}"));
            false
        }
    }
}

/// A box of `cells` cubes of edge `h` [m] placed per the `seed` preset (largest side 1 m,
/// lowest node 0.1 m above the floor).
pub fn box_model(cells: [usize; 3], h: f64) -> Model {
    let mesh = box_tets(DVec3::ZERO, h, cells);
    ModelBuilder::new(&mesh)
        .placement(Placement::default())
        .build()
        .unwrap()
}

/// A backend with the validation layer on; panics on any error.
pub fn validated(model: &Model, params: &SimParams) -> VulkanBackend {
    validated_with(model, params, EngineOptions::default())
}

/// [`validated`] with other engine options (workgroup size, atomics); validation is on.
pub fn validated_with(model: &Model, params: &SimParams, options: EngineOptions) -> VulkanBackend {
    let options = EngineOptions {
        validation: true,
        ..options
    };
    VulkanBackend::new(model, params, &options).unwrap()
}

/// Asserts that the validation layer reported nothing.
pub fn assert_no_validation_messages(backend: &VulkanBackend) {
    let messages = backend.validation_messages();
    assert!(
        messages.is_empty(),
        "{} validation messages:\n{}",
        messages.len(),
        messages.join("\n")
    );
}

/// Runs `f` on each backend for `model` and `params`: `cpu-ref`, `cpu`, and `vulkan` (with
/// the validation layer on, which must stay silent) when a Vulkan device exists. Without one
/// the `vulkan` case is skipped with a message, and fails under `CI=true`.
pub fn for_each_backend(
    model: &Model,
    params: &SimParams,
    mut f: impl FnMut(&str, &mut dyn tetrasim::Backend),
) {
    use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
    f(
        "cpu-ref",
        &mut ReferenceBackend::new(model, params).unwrap(),
    );
    f("cpu", &mut ParallelBackend::new(model, params).unwrap());
    if vulkan_available() {
        let mut gpu = validated(model, params);
        f("vulkan", &mut gpu);
        assert_no_validation_messages(&gpu);
    }
}

/// `model` with every node moved by up to `amount` [m] per axis and given a velocity of up
/// to `speed` [m/s] per axis (deterministic), its rest data unchanged: a deformed, moving start
/// that every backend takes from the model.
pub fn jittered(model: &Model, amount: f64, speed: f64, seed: u64) -> Model {
    let mut out = model.clone();
    for (i, (x, v)) in out
        .positions
        .iter_mut()
        .zip(out.velocities.iter_mut())
        .enumerate()
    {
        let k = seed.wrapping_mul(1 << 20) + 2 * i as u64;
        *x += noise3(k) * amount;
        if out.inv_mass[i] > 0.0 {
            *v += noise3(k + 1) * speed;
        }
    }
    out
}

/// A deterministic pseudo-random vector with components in [-1, 1) (splitmix64).
pub fn noise3(i: u64) -> DVec3 {
    let f = |i: u64| {
        let mut z = i.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    DVec3::new(f(3 * i), f(3 * i + 1), f(3 * i + 2))
}

/// The bundled TetGen sphere (`meshes/sphere`: 823 nodes, 2857 tets).
pub fn bundled_sphere() -> tetrasim::TetMesh {
    let prefix = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere");
    tetrasim::mesh::io::read_tetgen(&prefix).unwrap()
}

/// Mass-weighted centre, linear momentum `sum m v` and angular momentum about the origin
/// `sum m x x v` of a state.
pub fn momenta(state: &tetrasim::State, mass: &[f64]) -> (DVec3, DVec3, DVec3) {
    let total: f64 = mass.iter().sum();
    let mut com = DVec3::ZERO;
    let mut p = DVec3::ZERO;
    let mut l = DVec3::ZERO;
    for ((x, v), &m) in state.positions.iter().zip(&state.velocities).zip(mass) {
        com += *x * m;
        p += *v * m;
        l += x.cross(*v) * m;
    }
    (com / total, p, l)
}

/// `../shared/meshes` beside the workspace root, or `None` after reporting it missing (a
/// failure under `CI=true`).
pub fn shared_meshes() -> Option<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes");
    if dir.is_dir() {
        Some(dir)
    } else {
        skip::skipped(&format!("{} is missing (the scans)", dir.display()));
        None
    }
}

/// The contact measures of a frame's sample (panics when there are none: every backend
/// measures contact on a scene with colliders, grabs or body contact).
pub fn contact_of(sample: &tetrasim::backend::VolumeSample, backend: &str) -> ContactSample {
    sample
        .contact
        .unwrap_or_else(|| panic!("{backend}: no contact measures in the frame's sample"))
}

/// The worst per-frame differences of two runs' contact series: pushed collider nodes,
/// pushing body contacts, deepest penetration [m].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactDifference {
    /// Largest |a - b| of `collider_nodes`.
    pub collider_nodes: u32,
    /// Largest |a - b| of `body_contacts`.
    pub body_contacts: u32,
    /// Largest |a - b| of `deepest_m` [m].
    pub deepest_m: f64,
}

/// [`ContactDifference`] of series `a` and `b` (one sample per frame, as long).
pub fn contact_difference(a: &[ContactSample], b: &[ContactSample]) -> ContactDifference {
    assert_eq!(a.len(), b.len(), "one contact sample per frame");
    let mut worst = ContactDifference::default();
    for (a, b) in a.iter().zip(b) {
        worst.collider_nodes = worst
            .collider_nodes
            .max(a.collider_nodes.abs_diff(b.collider_nodes));
        worst.body_contacts = worst
            .body_contacts
            .max(a.body_contacts.abs_diff(b.body_contacts));
        worst.deepest_m = worst.deepest_m.max((a.deepest_m - b.deepest_m).abs());
    }
    worst
}

/// The most pushed collider nodes, pushing body contacts and deepest penetration [m] of any
/// frame of `series`.
pub fn contact_peaks(series: &[ContactSample]) -> ContactSample {
    series.iter().fold(
        ContactSample {
            collider_nodes: 0,
            body_contacts: 0,
            deepest_m: 0.0,
        },
        |a, b| ContactSample {
            collider_nodes: a.collider_nodes.max(b.collider_nodes),
            body_contacts: a.body_contacts.max(b.body_contacts),
            deepest_m: a.deepest_m.max(b.deepest_m),
        },
    )
}
