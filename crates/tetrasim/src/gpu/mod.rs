//! Thin, owned wrappers over raw Vulkan (ash + gpu-allocator) for compute work: the
//! context (instance, device, queue, allocator), named buffers, kernels that know their
//! workgroup size, command recording with one barrier helper, timestamp timing, and the
//! data layouts shared with GLSL.

pub mod buffer;
pub mod commands;
pub mod context;
pub mod descriptors;
pub mod device;
pub mod kernel;
pub mod layout;
pub mod memory;
/// Test support only: the SPIR-V reader behind the shader-vs-host layout checks (not part of
/// the library's API, not compiled outside `cargo test`).
#[cfg(test)]
pub(crate) mod spirv;
pub mod timing;

pub use buffer::{Buffer, Uploads};
pub use context::{list_devices, live_contexts, Context, ContextOptions};
pub use descriptors::BindingLayout;
pub use device::{AtomicsMode, AtomicsPath, DeviceInfo, DeviceSelector};
pub use kernel::Kernel;
pub use memory::{DeviceMemory, MemoryNeeds};
pub use timing::{PassTime, Timer};
