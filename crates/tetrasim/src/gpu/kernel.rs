//! A compute kernel: one pass's pipeline on a shared [`BindingLayout`] (one set layout,
//! pipeline layout, pool and descriptor set for every kernel of a backend, since all passes
//! use the one binding table of `gpu::layout::binding`). It knows its workgroup size
//! (specialization constant 0), so callers dispatch element counts.

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use super::descriptors::BindingLayout;
use super::layout::PushConstants;
use crate::error::{Error, Result, VkContext};

/// Looks up a compiled shader by key (`passes/integrate.comp`, `passes/volume.comp#cas`).
pub fn shader(key: &str) -> Result<&'static [u8]> {
    crate::shaders::SHADERS
        .iter()
        .find(|(k, _)| *k == key)
        .map(|(_, bytes)| *bytes)
        .ok_or_else(|| {
            Error::Gpu(format!(
                "shader `{key}` is not among the compiled shaders (see build.rs)"
            ))
        })
}

/// A compute pipeline on a shared binding layout, freed on drop.
pub struct Kernel {
    ctx: Arc<Context>,
    /// Pass name (as in the timing report).
    pub name: String,
    /// Invocations per workgroup.
    pub workgroup_size: u32,
    max_groups: u32,
    pipeline: vk::Pipeline,
    /// The shared layout and set; the Arc keeps it alive until after the pipeline (and
    /// every other kernel built on it) is freed.
    binding: Arc<BindingLayout>,
}

impl Kernel {
    /// Builds the pass `name` from the shader `key` on `binding` (set 0 of storage buffers
    /// and the [`PushConstants`] block, shared with the other kernels).
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        key: &str,
        binding: &Arc<BindingLayout>,
        workgroup_size: u32,
    ) -> Result<Self> {
        Self::with_constants(ctx, name, key, binding, workgroup_size, &[])
    }

    /// The shared layout for compute kernels: a storage buffer at each of `bindings` and
    /// the [`PushConstants`] block (write the buffers with [`BindingLayout::write`]).
    pub fn binding_layout(
        ctx: &Arc<Context>,
        name: &str,
        bindings: &[u32],
    ) -> Result<Arc<BindingLayout>> {
        BindingLayout::new(
            ctx,
            name,
            bindings,
            vk::ShaderStageFlags::COMPUTE,
            std::mem::size_of::<PushConstants>() as u32,
        )
        .map(Arc::new)
    }

    /// [`Kernel::new`] with 32-bit specialisation constants `constants[k]` at constant id
    /// `k + 1` (id 0 is the workgroup size).
    pub fn with_constants(
        ctx: &Arc<Context>,
        name: &str,
        key: &str,
        binding: &Arc<BindingLayout>,
        workgroup_size: u32,
        constants: &[u32],
    ) -> Result<Self> {
        let mut k = Kernel {
            ctx: ctx.clone(),
            name: name.to_string(),
            workgroup_size,
            max_groups: ctx.info().max_workgroup_count[0],
            pipeline: vk::Pipeline::null(),
            binding: binding.clone(),
        };
        k.build(ctx, key, constants)?;
        Ok(k)
    }

    fn build(&mut self, ctx: &Context, key: &str, constants: &[u32]) -> Result<()> {
        let device = ctx.device();
        let code = ash::util::read_spv(&mut std::io::Cursor::new(shader(key)?))
            .map_err(|e| Error::Gpu(format!("shader `{key}` is not valid SPIR-V: {e}")))?;
        let spec_values: Vec<u32> = std::iter::once(self.workgroup_size)
            .chain(constants.iter().copied())
            .collect();
        let spec_entries: Vec<_> = (0..spec_values.len() as u32)
            .map(|id| {
                vk::SpecializationMapEntry::default()
                    .constant_id(id)
                    .offset(4 * id)
                    .size(4)
            })
            .collect();
        let spec_data: Vec<u8> = spec_values.iter().flat_map(|v| v.to_ne_bytes()).collect();
        let spec = vk::SpecializationInfo::default()
            .map_entries(&spec_entries)
            .data(&spec_data);
        // SAFETY: valid device; every create info outlives its call; the pipeline is stored
        // in `self` as soon as it exists, so Drop frees it; the module is freed at once.
        unsafe {
            let module = device
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&code), None)
                .vk("vkCreateShaderModule")?;
            let stage = vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::COMPUTE)
                .module(module)
                .name(c"main")
                .specialization_info(&spec);
            let info = [vk::ComputePipelineCreateInfo::default()
                .stage(stage)
                .layout(self.binding.layout)];
            let pipelines = device.create_compute_pipelines(vk::PipelineCache::null(), &info, None);
            device.destroy_shader_module(module, None);
            self.pipeline = pipelines.map_err(|(_, e)| Error::Vulkan {
                call: "vkCreateComputePipelines",
                result: e,
            })?[0];
        }
        ctx.set_name(self.pipeline, &self.name);
        Ok(())
    }

    /// Workgroups needed for `elements` invocations.
    pub fn groups(&self, elements: u32) -> u32 {
        elements.div_ceil(self.workgroup_size)
    }

    /// Checks that `elements` fits in one dispatch on this device.
    pub fn check_elements(&self, elements: u32) -> Result<()> {
        if self.groups(elements) > self.max_groups {
            return Err(Error::Gpu(format!(
                "pass `{}`: {elements} elements need {} workgroups of {}, the device allows {}",
                self.name,
                self.groups(elements),
                self.workgroup_size,
                self.max_groups
            )));
        }
        Ok(())
    }

    /// Records binding, push constants and a dispatch covering `elements` invocations.
    pub fn record(&self, cmd: vk::CommandBuffer, push: &PushConstants, elements: u32) {
        let device = self.ctx.device();
        // SAFETY: `cmd` is recording; the pipeline is alive.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline) };
        self.binding.record(
            cmd,
            vk::PipelineBindPoint::COMPUTE,
            bytemuck::bytes_of(push),
        );
        // SAFETY: `cmd` is recording with the pipeline, set and push constants bound.
        unsafe { device.cmd_dispatch(cmd, self.groups(elements).max(1), 1, 1) };
    }
}

impl Drop for Kernel {
    /// Frees the pipeline; the shared layouts and set go with the last kernel's `binding`
    /// after it. The GPU must be done with the kernel (owners wait first).
    fn drop(&mut self) {
        if self.pipeline != vk::Pipeline::null() {
            // SAFETY: the caller guarantees no pending use.
            unsafe { self.ctx.device().destroy_pipeline(self.pipeline, None) };
        }
    }
}
