//! Fixtures of the GPU tests: skip only when no Vulkan device exists at all, small meshes,
//! and backends with the validation layer on.
#![allow(dead_code)]

use glam::DVec3;
use tetrasim::engine::{EngineOptions, VulkanBackend};
use tetrasim::mesh::grid::box_tets;
use tetrasim::params::{Placement, SimParams};
use tetrasim::{Model, ModelBuilder};

/// Whether a Vulkan device exists; prints why the test is skipped when not.
pub fn vulkan_available() -> bool {
    match tetrasim::gpu::list_devices() {
        Ok(devices) if !devices.is_empty() => true,
        Ok(_) => {
            println!("SKIPPED: no Vulkan device (install mesa-vulkan-drivers for lavapipe)");
            false
        }
        Err(e) => {
            println!("SKIPPED: Vulkan is unavailable: {e}");
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
    validated_with(model, params, None)
}

/// [`validated`] with a given workgroup size (`None`: the device default).
pub fn validated_with(
    model: &Model,
    params: &SimParams,
    workgroup_size: Option<u32>,
) -> VulkanBackend {
    let options = EngineOptions {
        validation: true,
        workgroup_size,
        ..Default::default()
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
