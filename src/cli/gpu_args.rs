//! The GPU flags, declared once for every command that can run the `vulkan` backend (`run`,
//! `plan`, `render`, `bench`, `tradeoff`, `scaling`) and turned into the engine's options
//! in one place, [`GpuArgs::engine_options`].

use tetrasim::backend::vulkan::{AtomicsMode, EngineOptions};

/// Device, validation, workgroup size, frames in flight and float atomics of the `vulkan`
/// backend, and the memory limit of every backend. Each but the last acts only on
/// `vulkan`: [`GpuArgs::first_given`] names the first one given, so a command can refuse
/// it on another backend.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct GpuArgs {
    /// GPU for the `vulkan` backend: an index or a name fragment from `tetrasim info`
    /// (default: discrete > integrated > virtual > CPU).
    #[arg(long)]
    pub device: Option<String>,
    /// GPU workgroup size (a power of two; default from the device limits, at most 1024).
    #[arg(long)]
    pub workgroup_size: Option<u32>,
    /// Turn on the Vulkan validation layer and print its messages.
    #[arg(long)]
    pub validation: bool,
    /// Frames the GPU may have in flight (1 to 8; default 2: the next frame runs while the
    /// last one's volume is read); 1 waits for every frame.
    #[arg(long, value_name = "N")]
    pub frames_in_flight: Option<u32>,
    /// Float atomics of the GPU scatter passes: auto, ext (atomicAdd on float) or cas.
    #[arg(long, value_enum)]
    pub atomics: Option<AtomicsMode>,
    /// The most memory the backend may take, in MiB (default: all the device offers: the
    /// GPU's memory on `vulkan`, the machine's available memory on `cpu` and `cpu-ref`); a
    /// scene that needs more is refused before anything is allocated.
    #[arg(long, value_name = "MIB", value_parser = positive_mib)]
    pub device_memory: Option<f64>,
}

/// Bytes per MiB.
const MIB: f64 = 1024.0 * 1024.0;

/// A memory size in MiB: a positive number.
fn positive_mib(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(mib) if mib.is_finite() && mib > 0.0 => Ok(mib),
        _ => Err(format!("`{text}` is not a positive number of MiB")),
    }
}

impl GpuArgs {
    /// The engine options these flags ask for (what they leave out keeps its default).
    pub fn engine_options(&self) -> EngineOptions {
        let defaults = EngineOptions::default();
        EngineOptions {
            device: match self.device.as_deref() {
                Some(name) => match name.parse() {
                    Ok(selector) => selector,
                    Err(never) => match never {},
                },
                None => defaults.device,
            },
            validation: self.validation,
            workgroup_size: self.workgroup_size,
            frames_in_flight: self.frames_in_flight,
            atomics: self.atomics.unwrap_or(defaults.atomics),
            memory_limit: self.device_memory.map(|mib| (mib * MIB) as u64),
            ..defaults
        }
    }

    /// The first `vulkan`-only flag given, by its name on the command line (`None`: all
    /// defaults; `--device-memory` acts on every backend).
    pub fn first_given(&self) -> Option<&'static str> {
        [
            ("device", self.device.is_some()),
            ("workgroup-size", self.workgroup_size.is_some()),
            ("validation", self.validation),
            ("frames-in-flight", self.frames_in_flight.is_some()),
            ("atomics", self.atomics.is_some()),
        ]
        .into_iter()
        .find_map(|(flag, given)| given.then_some(flag))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tetrasim::gpu::DeviceSelector;

    #[test]
    fn every_flag_reaches_the_engine_options() {
        let args = GpuArgs {
            device: Some("1".into()),
            workgroup_size: Some(64),
            validation: true,
            frames_in_flight: Some(3),
            atomics: Some(AtomicsMode::Cas),
            device_memory: Some(2.5),
        };
        let o = args.engine_options();
        assert_eq!(o.device, DeviceSelector::Index(1));
        assert_eq!(o.workgroup_size, Some(64));
        assert!(o.validation);
        assert_eq!(o.frames_in_flight, Some(3));
        assert_eq!(o.atomics, AtomicsMode::Cas);
        assert_eq!(o.memory_limit, Some(5 << 19));
        assert!(positive_mib("0").is_err() && positive_mib("nan").is_err());
        assert_eq!(args.first_given(), Some("device"));
        assert_eq!(GpuArgs::default().first_given(), None);
        let defaults = GpuArgs::default().engine_options();
        assert_eq!(defaults.device, DeviceSelector::Auto);
        assert_eq!(defaults.atomics, AtomicsMode::Auto);
    }
}
