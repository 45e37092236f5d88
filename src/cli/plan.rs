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
    refuse_run_only_flags(&args)?;
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
        volume_on_demand: args.scene.is_some() && scene.output.json.is_none(),
        untimed: false,
        frames_in_flight: None,
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

/// `run`'s flags that do nothing in a plan are refused, naming the flag.
fn refuse_run_only_flags(args: &RunArgs) -> crate::Result<()> {
    if let Some(backend) = args.backend.as_deref().filter(|&b| b != "vulkan") {
        return Err(crate::Error::param(
            "backend",
            format!("`plan` describes the `vulkan` backend, not `{backend}`"),
        ));
    }
    let given = [
        ("json", args.json.is_some()),
        ("out-dir", args.out_dir.is_some()),
        ("every", args.every.is_some()),
        ("format", args.format.is_some()),
        ("units", args.units.is_some()),
        ("frames", args.solver.frames.is_some()),
        ("validation", args.validation),
        ("frames-in-flight", args.frames_in_flight.is_some()),
        ("quiet", args.quiet),
    ];
    match given.iter().find(|(_, on)| *on) {
        Some((flag, _)) => Err(crate::Error::param(
            *flag,
            "`plan` runs nothing and writes nothing; use it with `tetrasim run`",
        )),
        None => Ok(()),
    }
}
