//! `tetrasim info`: the Vulkan devices and what the engine would do on each.

use tetrasim::gpu::{device, list_devices, DeviceSelector};

/// Prints every device, marking the one `--backend vulkan` picks by default.
pub fn execute() -> anyhow::Result<()> {
    let devices = list_devices()?;
    if devices.is_empty() {
        println!("no Vulkan device found (lavapipe: install mesa-vulkan-drivers)");
        return Ok(());
    }
    let chosen = device::select(&devices, &DeviceSelector::Auto).ok();
    for d in &devices {
        print!("{d}");
        if Some(d.index) == chosen {
            println!("  (default for --backend vulkan)");
        }
    }
    Ok(())
}
