//! Checks a run makes before it writes anything: on `vulkan`, that each method's plan fits
//! the device's memory ([`VulkanBackend::preflight`]), so a scene too large for the device
//! is refused with both sizes and leaves no output folder or record behind.

use tetrasim::backend::vulkan::{EngineOptions, VulkanBackend};
use tetrasim::gpu::{device, list_devices};
use tetrasim::params::{Method, SimParams};
use tetrasim::problem::Problem;
use tetrasim::{Model, Result};

/// Refuses what the `vulkan` backend would refuse before allocating: a method it does not
/// run, or a plan larger than the device's memory (or `gpu.memory_limit`). Does nothing
/// for the other backends.
pub fn preflight(
    backend: &str,
    model: &Model,
    params: &SimParams,
    methods: &[Method],
    gpu: &EngineOptions,
) -> Result<()> {
    if backend != "vulkan" {
        return Ok(());
    }
    let devices = list_devices()?;
    let index = device::select(&devices, &gpu.device)?;
    let Some(info) = devices.iter().find(|d| d.index == index) else {
        return Ok(());
    };
    for &method in methods {
        let params = SimParams {
            method,
            ..params.clone()
        };
        VulkanBackend::preflight(info, &Problem::new(model, &params)?, gpu)?;
    }
    Ok(())
}
