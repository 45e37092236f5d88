//! `tetrasim plan`: what the `vulkan` backend would build and do per frame for a scene (or
//! `run`'s flags): passes per time step, buffers and their sizes, total device memory and
//! the estimated bytes moved per frame. Printed from [`crate::engine::plan::EnginePlan`],
//! the same value the engine is built from.

use crate::engine::plan::EnginePlan;
use crate::engine::{EngineOptions, VulkanBackend};
use crate::gpu::{device, list_devices, DeviceSelector};
use crate::launch::stage;
use crate::params::SimParams;

use super::RunArgs;

/// Workgroup size assumed when no Vulkan device can be asked (and none is given).
const FALLBACK_WORKGROUP: u32 = 256;

/// Prints the plan of every method the arguments select.
pub fn execute(args: RunArgs) -> anyhow::Result<()> {
    let (scene, methods) = args.scene_and_methods()?;
    let staged = stage(&scene)?;
    let options = EngineOptions {
        device: args
            .device
            .as_deref()
            .unwrap_or("auto")
            .parse()
            .unwrap_or_default(),
        validation: false,
        workgroup_size: args.workgroup_size,
        volume_on_demand: args.scene.is_some() && scene.output.metrics.is_none(),
        untimed: false,
    };
    let selector: DeviceSelector = options.device.clone();
    let info = list_devices().ok().and_then(|devices| {
        let index = device::select(&devices, &selector).ok()?;
        devices.into_iter().find(|d| d.index == index)
    });
    println!("{}", staged.label);
    for method in methods {
        let params = SimParams {
            method,
            ..staged.params.clone()
        };
        let plan = match &info {
            Some(info) => VulkanBackend::plan_for(info, &staged.model, &params, &options)?,
            None => {
                let wg = args.workgroup_size.unwrap_or(FALLBACK_WORKGROUP);
                eprintln!("no Vulkan device: planning for workgroup size {wg}");
                EnginePlan::for_model(&staged.model, &params, wg, !options.volume_on_demand)?
            }
        };
        print!("{}", plan.render());
        println!();
    }
    Ok(())
}
