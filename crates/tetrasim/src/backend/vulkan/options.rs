//! What the `vulkan` backend is asked to do besides the physics: the device, validation,
//! workgroup size, timing, volume read-back, frames in flight, float atomics and a memory
//! limit. The command line fills it from its GPU flags in one place
//! (`tetrasim_cli::cli::gpu_args`).

#[cfg(doc)]
use super::VulkanBackend;
use super::{AtomicsMode, DeviceSelector};
#[cfg(doc)]
use crate::backend::Backend;

/// GPU choices that are not physics: which device, validation, workgroup size, atomics.
#[derive(Debug, Clone, Default)]
pub struct EngineOptions {
    /// Which device to use (`--device NAME|INDEX`).
    pub device: DeviceSelector,
    /// Enable the Khronos validation layer and record its messages.
    pub validation: bool,
    /// Invocations per workgroup (a power of two); `None`: from the device limits.
    pub workgroup_size: Option<u32>,
    /// `false` (default): every frame measures the volume (`volume_sum` and the copy of
    /// its partials); `true`: only when [`Backend::volume`] asks, so a frame reads back
    /// nothing but the 16-byte divergence status.
    pub volume_on_demand: bool,
    /// `false` (default): a GPU timestamp after every pass ([`VulkanBackend::pass_times`]);
    /// `true`: none. A timestamp costs about 0.06 ms per pass on lavapipe (10 ms of a
    /// 30 ms bunny frame with the default solver's 175 passes), so wall-clock benchmarks run
    /// untimed and measure the pass breakdown in a separate run.
    pub untimed: bool,
    /// Frames that may be in flight at once (recorded frame slots), 1 to
    /// [`MAX_FRAMES_IN_FLIGHT`]; `None`: [`FRAMES_IN_FLIGHT`]. 1 waits for every frame
    /// before the next is submitted (`tetrasim run --frames-in-flight 1`, for comparisons).
    pub frames_in_flight: Option<u32>,
    /// Float atomics of the scatter passes (`--atomics`): `auto` takes
    /// `VK_EXT_shader_atomic_float` where the device has it.
    pub atomics: AtomicsMode,
    /// The most memory the backend may take [bytes] (`--device-memory MIB`), below what the
    /// device offers: the GPU's heaps on `vulkan`, the machine's memory on `cpu` and
    /// `cpu-ref` ([`crate::backend::cpu::memory`]); `None`: all it offers. A problem that
    /// needs more is refused before anything is allocated.
    pub memory_limit: Option<u64>,
}

/// Frames the `vulkan` backend has in flight by default (recorded frame slots): the next
/// frame runs while the host reads the last.
pub const FRAMES_IN_FLIGHT: u32 = 2;
/// The most frame slots [`EngineOptions::frames_in_flight`] may ask for.
pub const MAX_FRAMES_IN_FLIGHT: u32 = 8;
