//! Physical devices: what each offers (limits, float atomics, timestamps) and how one is
//! picked (`--device NAME|INDEX`, default discrete > integrated > virtual > CPU).

use std::ffi::CStr;

use ash::vk;
use serde::{Deserialize, Serialize};

use super::memory::DeviceMemory;
use crate::error::{Error, Result, VkContext};

/// Lowest Vulkan version the engine accepts on a device.
pub const REQUIRED_API: u32 = vk::API_VERSION_1_2;

/// Which device to use.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub enum DeviceSelector {
    /// The best usable device: discrete > integrated > virtual > CPU.
    #[default]
    Auto,
    /// The device with this index in `tetrasim info`'s list.
    Index(usize),
    /// The first device whose name contains this text (case-insensitive).
    Name(String),
}

impl std::str::FromStr for DeviceSelector {
    type Err = std::convert::Infallible;
    /// A number is an index, `auto` or an empty string is [`DeviceSelector::Auto`], anything
    /// else a name fragment.
    fn from_str(s: &str) -> std::result::Result<Self, Self::Err> {
        let s = s.trim();
        Ok(if s.is_empty() || s.eq_ignore_ascii_case("auto") {
            DeviceSelector::Auto
        } else if let Ok(i) = s.parse() {
            DeviceSelector::Index(i)
        } else {
            DeviceSelector::Name(s.to_string())
        })
    }
}

/// Which float-atomic path the Vulkan engine uses for scatter passes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum AtomicsMode {
    /// `VK_EXT_shader_atomic_float` when the device has it, else compare-and-swap.
    #[default]
    Auto,
    /// Force `atomicAdd` on floats (error if unsupported).
    Ext,
    /// Force the integer compare-and-swap loop on the float's bits.
    Cas,
}

/// The float-atomic code path of the scatter passes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AtomicsPath {
    /// `atomicAdd` on float (`VK_EXT_shader_atomic_float`).
    Ext,
    /// Integer compare-and-swap loop on the float's bits.
    Cas,
}

impl AtomicsPath {
    /// `"ext"` or `"cas"`, as in the JSON report and the shader variant keys.
    pub fn name(self) -> &'static str {
        match self {
            AtomicsPath::Ext => "ext",
            AtomicsPath::Cas => "cas",
        }
    }
}

/// What the engine needs to know about one physical device.
#[derive(Debug, Clone, Serialize)]
pub struct DeviceInfo {
    /// Position in the loader's enumeration (what `--device INDEX` refers to).
    pub index: usize,
    /// Device name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// `discrete`, `integrated`, `virtual`, `cpu` or `other`.
    pub kind: &'static str,
    /// Driver name and version text (VkPhysicalDeviceDriverProperties).
    pub driver: String,
    /// Supported Vulkan version, `major.minor.patch`.
    pub api_version: String,
    /// `maxComputeWorkGroupSize`.
    pub max_workgroup_size: [u32; 3],
    /// `maxComputeWorkGroupInvocations`.
    pub max_workgroup_invocations: u32,
    /// `maxComputeWorkGroupCount`.
    pub max_workgroup_count: [u32; 3],
    /// `maxComputeSharedMemorySize` [bytes].
    pub max_shared_memory: u32,
    /// `maxPerStageDescriptorStorageBuffers`: the storage buffers one pass may bind.
    pub max_storage_buffers: u32,
    /// Subgroup size (invocations).
    pub subgroup_size: u32,
    /// Whether compute shaders have the subgroup operations the engine's reductions use
    /// (`VK_SUBGROUP_FEATURE_BASIC_BIT` and `SHUFFLE_BIT` in the compute stage;
    /// `glsl/common/workgroup_sum.glsl`).
    pub subgroup_shuffle: bool,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period_ns: f32,
    /// Whether the chosen compute queue supports timestamps (valid bits > 0).
    pub timestamps: bool,
    /// `shaderBufferFloat32AtomicAdd` of `VK_EXT_shader_atomic_float`.
    pub float_atomic_add: bool,
    /// Its memory heaps (and budgets where it reports them): what a plan is checked against
    /// before anything is allocated.
    pub memory: DeviceMemory,
    /// Whether that compute queue also supports graphics (needed by `tetrasim render`).
    pub graphics: bool,
    /// Sample counts that colour, depth and stencil attachments all support (rendering).
    #[serde(skip)]
    pub framebuffer_samples: vk::SampleCountFlags,
    /// A depth-stencil attachment format with optimal tiling (rendering), if any.
    #[serde(skip)]
    pub depth_stencil_format: Option<vk::Format>,
    /// Index of the queue family used for compute (None: the device has no compute queue).
    #[serde(skip)]
    pub compute_family: Option<u32>,
    /// Timestamp valid bits of that queue family.
    #[serde(skip)]
    pub timestamp_bits: u32,
    #[serde(skip)]
    pub(crate) api: u32,
}

impl DeviceInfo {
    /// Reads the device's properties, limits and features.
    pub(crate) fn query(
        instance: &ash::Instance,
        pd: vk::PhysicalDevice,
        index: usize,
    ) -> Result<Self> {
        // SAFETY: `pd` comes from `instance`, which is alive; every pNext struct outlives the call.
        unsafe {
            let extensions = instance
                .enumerate_device_extension_properties(pd)
                .vk("vkEnumerateDeviceExtensionProperties")?;
            let has_ext = |name: &CStr| {
                extensions
                    .iter()
                    .any(|e| e.extension_name_as_c_str() == Ok(name))
            };
            let mut driver = vk::PhysicalDeviceDriverProperties::default();
            let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
            let mut props2 = vk::PhysicalDeviceProperties2::default()
                .push_next(&mut driver)
                .push_next(&mut subgroup);
            instance.get_physical_device_properties2(pd, &mut props2);
            let props = props2.properties;
            let mut float_atomic_add = false;
            if has_ext(ash::ext::shader_atomic_float::NAME) {
                let mut atomic = vk::PhysicalDeviceShaderAtomicFloatFeaturesEXT::default();
                let mut features2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut atomic);
                instance.get_physical_device_features2(pd, &mut features2);
                float_atomic_add = atomic.shader_buffer_float32_atomic_add == vk::TRUE;
            }
            let families = instance.get_physical_device_queue_family_properties(pd);
            let compute = families
                .iter()
                .enumerate()
                .filter(|(_, f)| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
                // Timestamps first, then a family that also draws (the renderer shares the queue).
                .max_by_key(|(i, f)| {
                    (
                        f.timestamp_valid_bits > 0,
                        f.queue_flags.contains(vk::QueueFlags::GRAPHICS),
                        std::cmp::Reverse(*i),
                    )
                });
            let limits = props.limits;
            let text = |c: std::result::Result<&CStr, _>| {
                c.map(|c| c.to_string_lossy().into_owned())
                    .unwrap_or_default()
            };
            let kind = match props.device_type {
                vk::PhysicalDeviceType::DISCRETE_GPU => "discrete",
                vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated",
                vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual",
                vk::PhysicalDeviceType::CPU => "cpu",
                _ => "other",
            };
            let v = props.api_version;
            let depth_stencil_format = [
                vk::Format::D32_SFLOAT_S8_UINT,
                vk::Format::D24_UNORM_S8_UINT,
            ]
            .into_iter()
            .find(|&f| {
                instance
                    .get_physical_device_format_properties(pd, f)
                    .optimal_tiling_features
                    .contains(vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT)
            });
            Ok(DeviceInfo {
                index,
                name: text(props.device_name_as_c_str()),
                kind,
                driver: format!(
                    "{} {}",
                    text(driver.driver_name_as_c_str()),
                    text(driver.driver_info_as_c_str())
                )
                .trim()
                .to_string(),
                api_version: format!(
                    "{}.{}.{}",
                    vk::api_version_major(v),
                    vk::api_version_minor(v),
                    vk::api_version_patch(v)
                ),
                max_workgroup_size: limits.max_compute_work_group_size,
                max_workgroup_invocations: limits.max_compute_work_group_invocations,
                max_workgroup_count: limits.max_compute_work_group_count,
                max_shared_memory: limits.max_compute_shared_memory_size,
                max_storage_buffers: limits.max_per_stage_descriptor_storage_buffers,
                subgroup_size: subgroup.subgroup_size,
                subgroup_shuffle: subgroup
                    .supported_stages
                    .contains(vk::ShaderStageFlags::COMPUTE)
                    && subgroup.supported_operations.contains(
                        vk::SubgroupFeatureFlags::BASIC | vk::SubgroupFeatureFlags::SHUFFLE,
                    ),
                timestamp_period_ns: limits.timestamp_period,
                timestamps: compute.is_some_and(|(_, f)| f.timestamp_valid_bits > 0)
                    && limits.timestamp_period > 0.0,
                float_atomic_add,
                memory: DeviceMemory::query(instance, pd, has_ext(ash::ext::memory_budget::NAME)),
                graphics: compute
                    .is_some_and(|(_, f)| f.queue_flags.contains(vk::QueueFlags::GRAPHICS)),
                framebuffer_samples: limits.framebuffer_color_sample_counts
                    & limits.framebuffer_depth_sample_counts
                    & limits.framebuffer_stencil_sample_counts,
                depth_stencil_format,
                compute_family: compute.map(|(i, _)| i as u32),
                timestamp_bits: compute.map(|(_, f)| f.timestamp_valid_bits).unwrap_or(0),
                api: v,
            })
        }
    }

    /// Why the engine cannot run on this device, if it cannot.
    pub fn unusable_reason(&self) -> Option<String> {
        if self.api < REQUIRED_API {
            return Some(format!(
                "it supports Vulkan {} but the engine needs 1.2",
                self.api_version
            ));
        }
        if self.compute_family.is_none() {
            return Some("it has no compute queue".into());
        }
        if !self.subgroup_shuffle {
            return Some(
                "its compute shaders lack subgroup shuffles (VK_SUBGROUP_FEATURE_SHUFFLE_BIT), \
                 which the engine's reductions use"
                    .into(),
            );
        }
        None
    }

    /// Ranking for [`DeviceSelector::Auto`]: higher is preferred.
    fn preference(&self) -> u32 {
        match self.kind {
            "discrete" => 4,
            "integrated" => 3,
            "virtual" => 2,
            "cpu" => 1,
            _ => 0,
        }
    }

    /// The atomic path `mode` resolves to here; an error when `ext` is forced but missing.
    pub fn atomics_path(&self, mode: AtomicsMode) -> Result<AtomicsPath> {
        match mode {
            AtomicsMode::Auto if self.float_atomic_add => Ok(AtomicsPath::Ext),
            AtomicsMode::Auto | AtomicsMode::Cas => Ok(AtomicsPath::Cas),
            AtomicsMode::Ext if self.float_atomic_add => Ok(AtomicsPath::Ext),
            AtomicsMode::Ext => Err(Error::Gpu(format!(
                "--atomics ext: device {} `{}` lacks shaderBufferFloat32AtomicAdd (VK_EXT_shader_atomic_float); \
                 use --atomics cas or auto",
                self.index, self.name
            ))),
        }
    }

    /// The default workgroup size: the paper's 1024 invocations, limited by the device
    /// (`maxComputeWorkGroupInvocations`, `maxComputeWorkGroupSize[0]`) and rounded down to a
    /// power of two (the volume reduction needs one).
    pub fn default_workgroup_size(&self) -> u32 {
        let limit = 1024
            .min(self.max_workgroup_invocations)
            .min(self.max_workgroup_size[0])
            .max(1);
        1 << (31 - limit.leading_zeros())
    }

    /// Checks a requested workgroup size against the device limits.
    pub fn check_workgroup_size(&self, size: u32) -> Result<()> {
        let limit = self
            .max_workgroup_invocations
            .min(self.max_workgroup_size[0]);
        if !size.is_power_of_two()
            || size > limit
            || u64::from(size) * 8 > u64::from(self.max_shared_memory)
        {
            return Err(Error::param(
                "workgroup-size",
                format!("{size} must be a power of two <= {limit} (device `{}`) and fit the shared memory", self.name),
            ));
        }
        Ok(())
    }

    /// Checks that a workgroup of `size` invocations with block Gauss-Seidel's shared
    /// memory (48 bytes per block node) runs here; the error names `block_size` (`asked`).
    pub fn check_block_workgroup(&self, size: u32, asked: u32) -> Result<()> {
        let limit = self
            .max_workgroup_invocations
            .min(self.max_workgroup_size[0]);
        let shared = 48 * crate::model::MAX_BLOCK_NODES as u64;
        if size > limit || shared > u64::from(self.max_shared_memory) {
            return Err(Error::param(
                "block_size",
                format!(
                    "blocks of {asked} tets need workgroups of {size} invocations and {shared} \
                     bytes of shared memory; device `{}` allows {limit} and {} (use a \
                     smaller block_size)",
                    self.name, self.max_shared_memory
                ),
            ));
        }
        Ok(())
    }
}

impl std::fmt::Display for DeviceInfo {
    /// The `tetrasim info` block of one device.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let yes = |b: bool| if b { "yes" } else { "no" };
        let [x, y, z] = self.max_workgroup_size;
        writeln!(
            f,
            "device {}: {} [{}], Vulkan {}",
            self.index, self.name, self.kind, self.api_version
        )?;
        writeln!(f, "  driver: {}", self.driver)?;
        if let Some(why) = self.unusable_reason() {
            return writeln!(f, "  unusable: {why}");
        }
        writeln!(
            f,
            "  compute: max workgroup size {x} x {y} x {z}, max invocations {}, subgroup {}, shared memory {} B",
            self.max_workgroup_invocations, self.subgroup_size, self.max_shared_memory
        )?;
        writeln!(
            f,
            "  default workgroup size: {}",
            self.default_workgroup_size()
        )?;
        writeln!(
            f,
            "  memory: {} device-local on offer{}",
            super::memory::mib(self.memory.device_local_offered()),
            match self.memory.heaps.iter().any(|h| h.available.is_some()) {
                true => " (the driver's budget less what is in use)",
                false => "",
            }
        )?;
        writeln!(
            f,
            "  timestamps: {} (period {} ns)",
            yes(self.timestamps),
            self.timestamp_period_ns
        )?;
        let auto = self
            .atomics_path(AtomicsMode::Auto)
            .map(AtomicsPath::name)
            .unwrap_or("cas");
        let ext = if self.float_atomic_add {
            "ext"
        } else {
            "unsupported"
        };
        writeln!(
            f,
            "  shaderBufferFloat32AtomicAdd: {} -> atomics: auto = {auto}, ext = {ext}, cas = cas",
            yes(self.float_atomic_add)
        )
    }
}

/// Picks a device from `devices` (all of one instance) by `selector`.
pub fn select(devices: &[DeviceInfo], selector: &DeviceSelector) -> Result<usize> {
    let names = || {
        devices
            .iter()
            .map(|d| format!("{}: {} ({})", d.index, d.name, d.kind))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let usable = |d: &DeviceInfo| match d.unusable_reason() {
        None => Ok(d.index),
        Some(why) => Err(Error::Gpu(format!(
            "device {} `{}` cannot be used: {why}",
            d.index, d.name
        ))),
    };
    if devices.is_empty() {
        return Err(Error::Gpu(
            "no Vulkan device found (install a driver; lavapipe: mesa-vulkan-drivers)".into(),
        ));
    }
    match selector {
        DeviceSelector::Auto => devices
            .iter()
            .filter(|d| d.unusable_reason().is_none())
            .max_by_key(|d| (d.preference(), std::cmp::Reverse(d.index)))
            .map(|d| d.index)
            .ok_or_else(|| {
                Error::Gpu(format!(
                    "no Vulkan 1.2 device with a compute queue and subgroup shuffles among: {}",
                    names()
                ))
            }),
        DeviceSelector::Index(i) => {
            let d = devices.get(*i).ok_or_else(|| {
                Error::Gpu(format!(
                    "--device {i}: no such device; there are: {}",
                    names()
                ))
            })?;
            usable(d)
        }
        DeviceSelector::Name(text) => {
            let lower = text.to_lowercase();
            let d = devices
                .iter()
                .find(|d| d.name.to_lowercase().contains(&lower))
                .ok_or_else(|| {
                    Error::Gpu(format!(
                        "--device {text}: no device name contains it; there are: {}",
                        names()
                    ))
                })?;
            usable(d)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fake(index: usize, kind: &'static str, api: u32) -> DeviceInfo {
        DeviceInfo {
            index,
            name: format!("{kind} gpu {index}"),
            kind,
            driver: String::new(),
            api_version: String::new(),
            max_workgroup_size: [1024, 1024, 64],
            max_workgroup_invocations: 768,
            max_workgroup_count: [65535; 3],
            max_shared_memory: 32768,
            max_storage_buffers: 32,
            subgroup_size: 32,
            subgroup_shuffle: true,
            timestamp_period_ns: 1.0,
            timestamps: true,
            float_atomic_add: false,
            memory: DeviceMemory::default(),
            graphics: true,
            framebuffer_samples: vk::SampleCountFlags::TYPE_1,
            depth_stencil_format: None,
            compute_family: Some(0),
            timestamp_bits: 64,
            api,
        }
    }

    #[test]
    fn auto_prefers_discrete_then_integrated_and_skips_old_devices() {
        let devices = [
            fake(0, "cpu", REQUIRED_API),
            fake(1, "integrated", REQUIRED_API),
            fake(2, "discrete", vk::API_VERSION_1_1),
        ];
        assert_eq!(select(&devices, &DeviceSelector::Auto).unwrap(), 1);
        assert!(select(&devices, &DeviceSelector::Index(2))
            .unwrap_err()
            .to_string()
            .contains("needs 1.2"));
        assert_eq!(select(&devices, &"0".parse().unwrap()).unwrap(), 0);
        assert_eq!(select(&devices, &"INTEGRATED".parse().unwrap()).unwrap(), 1);
        assert!(select(&devices, &"nvidia".parse().unwrap()).is_err());
        assert!(select(&[], &DeviceSelector::Auto).is_err());
    }

    #[test]
    fn devices_without_subgroup_shuffles_are_skipped_with_the_reason() {
        let mut no_shuffle = fake(0, "discrete", REQUIRED_API);
        no_shuffle.subgroup_shuffle = false;
        let devices = [no_shuffle, fake(1, "cpu", REQUIRED_API)];
        assert_eq!(select(&devices, &DeviceSelector::Auto).unwrap(), 1);
        let refused = select(&devices, &DeviceSelector::Index(0))
            .unwrap_err()
            .to_string();
        assert!(refused.contains("subgroup shuffles"), "{refused}");
    }

    #[test]
    fn workgroup_default_is_a_power_of_two_within_limits() {
        let d = fake(0, "cpu", REQUIRED_API);
        assert_eq!(d.default_workgroup_size(), 512);
        assert!(d.check_workgroup_size(512).is_ok());
        assert!(d.check_workgroup_size(1024).is_err());
        assert!(d.check_workgroup_size(384).is_err());
        assert_eq!(d.atomics_path(AtomicsMode::Auto).unwrap(), AtomicsPath::Cas);
        assert!(d.atomics_path(AtomicsMode::Ext).is_err());
    }
}
