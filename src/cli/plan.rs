//! `tetrasim plan`: what the `vulkan` backend would build and do per frame for a scene (or
//! `run`'s flags): passes per time step, buffers and their sizes, total device memory and
//! the estimated bytes moved per frame. Printed from [`tetrasim::backend::vulkan::plan::EnginePlan`],
//! the same value the engine is built from.

use tetrasim::backend::vulkan::plan::EnginePlan;
use tetrasim::backend::vulkan::{EngineOptions, VulkanBackend, FRAMES_IN_FLIGHT};
use tetrasim::gpu::memory::mib;
use tetrasim::gpu::{device, list_devices, DeviceSelector};
use tetrasim::params::SimParams;
use tetrasim::problem::Problem;

use super::output_flags::{output_flags, refuse_given};
use super::RunArgs;

/// Workgroup size assumed when no Vulkan device can be asked (and none is given).
const FALLBACK_WORKGROUP: u32 = 256;

/// Prints the plan of every method the arguments select.
pub fn execute(args: RunArgs) -> anyhow::Result<()> {
    refuse_run_only_flags(&args)?;
    let (scene, methods) = args.scene_and_methods()?;
    let staged = args.stage(&scene)?;
    let options = EngineOptions {
        volume_on_demand: args.scene.is_some() && scene.output.json.is_none(),
        ..args.gpu.engine_options()
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
        let problem = Problem::new(&staged.model, &params)?;
        let plan = match &info {
            Some(info) => VulkanBackend::plan_for(info, &problem, &options)?,
            None => {
                let wg = args.gpu.workgroup_size.unwrap_or(FALLBACK_WORKGROUP);
                eprintln!("no Vulkan device: planning for workgroup size {wg}");
                let plan = EnginePlan::of_problem(&problem, wg, !options.volume_on_demand)?;
                match args.gpu.workgroup_size {
                    Some(_) => plan,
                    None => plan.size_workgroups(),
                }
            }
        };
        print!("{}", plan.render());
        if let Some(info) = &info {
            let depth = FRAMES_IN_FLIGHT;
            let fits =
                info.memory
                    .check(plan.memory_needs(depth), options.memory_limit, &info.name);
            println!(
                "device memory on offer {}: {}",
                mib(info.memory.device_local_offered()),
                match fits {
                    Ok(()) => "the plan fits".to_string(),
                    Err(e) => e.to_string(),
                }
            );
        }
        println!();
    }
    Ok(())
}

/// `run`'s flags that do nothing in a plan are refused, naming the flag.
fn refuse_run_only_flags(args: &RunArgs) -> tetrasim::Result<()> {
    if let Some(backend) = args.backend.as_deref().filter(|&b| b != "vulkan") {
        return Err(tetrasim::Error::param(
            "backend",
            format!("`plan` describes the `vulkan` backend, not `{backend}`"),
        ));
    }
    let mut given = output_flags(args).to_vec();
    given.extend([
        ("frames", args.solver.frames.is_some()),
        ("validation", args.gpu.validation),
        ("frames-in-flight", args.gpu.frames_in_flight.is_some()),
        ("quiet", args.quiet),
    ]);
    refuse_given(
        &given,
        "`plan` runs nothing and writes nothing; use it with `tetrasim run`",
    )
}
