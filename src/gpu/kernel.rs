//! A compute kernel: one pass's pipeline with its layouts and descriptor set, bound once to
//! the buffers it uses. It knows its workgroup size (specialization constant 0), so callers
//! dispatch element counts.

use std::sync::Arc;

use ash::vk;

use super::buffer::Buffer;
use super::context::Context;
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

/// A compute pipeline bound to its buffers, freed on drop.
pub struct Kernel {
    ctx: Arc<Context>,
    /// Pass name (as in the timing report).
    pub name: String,
    /// Invocations per workgroup.
    pub workgroup_size: u32,
    max_groups: u32,
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    set_layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
}

impl Kernel {
    /// Builds the pass `name` from the shader `key`, with `bindings` as storage buffers of
    /// set 0 and the [`PushConstants`] block.
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        key: &str,
        bindings: &[(u32, &Buffer)],
        workgroup_size: u32,
    ) -> Result<Self> {
        Self::with_constants(ctx, name, key, bindings, workgroup_size, &[])
    }

    /// [`Kernel::new`] with 32-bit specialisation constants `constants[k]` at constant id
    /// `k + 1` (id 0 is the workgroup size).
    pub fn with_constants(
        ctx: &Arc<Context>,
        name: &str,
        key: &str,
        bindings: &[(u32, &Buffer)],
        workgroup_size: u32,
        constants: &[u32],
    ) -> Result<Self> {
        let mut k = Kernel {
            ctx: ctx.clone(),
            name: name.to_string(),
            workgroup_size,
            max_groups: ctx.info().max_workgroup_count[0],
            pipeline: vk::Pipeline::null(),
            layout: vk::PipelineLayout::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
        };
        k.build(ctx, key, bindings, constants)?;
        Ok(k)
    }

    fn build(
        &mut self,
        ctx: &Context,
        key: &str,
        bindings: &[(u32, &Buffer)],
        constants: &[u32],
    ) -> Result<()> {
        let device = ctx.device();
        let layout_bindings: Vec<_> = bindings
            .iter()
            .map(|(b, _)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(*b)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let code = ash::util::read_spv(&mut std::io::Cursor::new(shader(key)?))
            .map_err(|e| Error::Gpu(format!("shader `{key}` is not valid SPIR-V: {e}")))?;
        let pool_sizes = [vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(bindings.len().max(1) as u32)];
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .size(std::mem::size_of::<PushConstants>() as u32)];
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
        // SAFETY: valid device; every create info outlives its call; handles are stored in
        // `self` as soon as they exist, so `destroy` frees them on any later error.
        unsafe {
            self.set_layout = device
                .create_descriptor_set_layout(
                    &vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings),
                    None,
                )
                .vk("vkCreateDescriptorSetLayout")?;
            let set_layouts = [self.set_layout];
            self.layout = device
                .create_pipeline_layout(
                    &vk::PipelineLayoutCreateInfo::default()
                        .set_layouts(&set_layouts)
                        .push_constant_ranges(&ranges),
                    None,
                )
                .vk("vkCreatePipelineLayout")?;
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
                .layout(self.layout)];
            let pipelines = device.create_compute_pipelines(vk::PipelineCache::null(), &info, None);
            device.destroy_shader_module(module, None);
            self.pipeline = pipelines.map_err(|(_, e)| Error::Vulkan {
                call: "vkCreateComputePipelines",
                result: e,
            })?[0];
            self.pool = device
                .create_descriptor_pool(
                    &vk::DescriptorPoolCreateInfo::default()
                        .max_sets(1)
                        .pool_sizes(&pool_sizes),
                    None,
                )
                .vk("vkCreateDescriptorPool")?;
            self.set = device
                .allocate_descriptor_sets(
                    &vk::DescriptorSetAllocateInfo::default()
                        .descriptor_pool(self.pool)
                        .set_layouts(&set_layouts),
                )
                .vk("vkAllocateDescriptorSets")?[0];
            let infos: Vec<[vk::DescriptorBufferInfo; 1]> =
                bindings.iter().map(|(_, buf)| [buf.descriptor()]).collect();
            let writes: Vec<_> = bindings
                .iter()
                .zip(&infos)
                .map(|((b, _), info)| {
                    vk::WriteDescriptorSet::default()
                        .dst_set(self.set)
                        .dst_binding(*b)
                        .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                        .buffer_info(info)
                })
                .collect();
            device.update_descriptor_sets(&writes, &[]);
        }
        ctx.set_name(self.pipeline, &self.name);
        ctx.set_name(self.layout, &self.name);
        ctx.set_name(self.set, &self.name);
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
        // SAFETY: `cmd` is recording; the pipeline, layout and set are alive.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout,
                0,
                &[self.set],
                &[],
            );
            device.cmd_push_constants(
                cmd,
                self.layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::bytes_of(push),
            );
            device.cmd_dispatch(cmd, self.groups(elements).max(1), 1, 1);
        }
    }
}

impl Drop for Kernel {
    /// Frees every handle. The GPU must be done with the kernel (owners wait first).
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: the caller guarantees no pending use; null handles are skipped.
        unsafe {
            if self.pool != vk::DescriptorPool::null() {
                device.destroy_descriptor_pool(self.pool, None);
            }
            if self.pipeline != vk::Pipeline::null() {
                device.destroy_pipeline(self.pipeline, None);
            }
            if self.layout != vk::PipelineLayout::null() {
                device.destroy_pipeline_layout(self.layout, None);
            }
            if self.set_layout != vk::DescriptorSetLayout::null() {
                device.destroy_descriptor_set_layout(self.set_layout, None);
            }
        }
    }
}
