//! Checks a run makes before it writes anything: on `vulkan`, that each method's plan fits
//! the device's memory ([`VulkanBackend::preflight`]); on `cpu` and `cpu-ref`, that the
//! machine has the memory the problem needs ([`tetrasim::backend::cpu::memory`]). A scene
//! too large is refused with both sizes and leaves no output folder or record behind.

use tetrasim::backend::cpu::memory;
use tetrasim::backend::vulkan::{EngineOptions, VulkanBackend};
use tetrasim::gpu::memory::mib;
use tetrasim::gpu::{device, list_devices};
use tetrasim::metrics::RunRecord;
use tetrasim::params::{Method, SimParams};
use tetrasim::problem::Problem;
use tetrasim::{Error, Model, Result};

/// Refuses what the backend would refuse before allocating: on `vulkan` a method it does
/// not run or a plan larger than the device's memory, on the CPU backends a problem larger
/// than the machine's available memory (either at most `gpu.memory_limit`); and, on any
/// backend, records of `frames` frames (one per method, held until the run ends) larger
/// than the machine's available memory.
pub fn preflight(
    backend: &str,
    model: &Model,
    params: &SimParams,
    methods: &[Method],
    frames: u32,
    gpu: &EngineOptions,
) -> Result<()> {
    let record = RunRecord::memory_needs(model, frames) * methods.len() as u64;
    if let Some(offers) = memory::machine_offers().filter(|&o| record > o) {
        return Err(Error::Memory(format!(
            "the records of a run of {frames} frames ({} method{}) need up to {} of memory, \
             the machine offers {} (available now): run fewer frames",
            methods.len(),
            if methods.len() == 1 { "" } else { "s" },
            mib(record),
            mib(offers)
        )));
    }
    if backend != "vulkan" {
        for &method in methods {
            let params = SimParams {
                method,
                ..params.clone()
            };
            memory::check(backend, &Problem::new(model, &params)?, gpu.memory_limit)?;
        }
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
