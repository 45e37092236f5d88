//! One descriptor set of storage buffers with the pipeline layout around it: the set layout,
//! a pipeline layout with one push-constant range, a pool and the allocated set, shared by
//! compute kernels and the render pipelines and freed together on drop.

use std::sync::Arc;

use ash::vk;

use super::buffer::Buffer;
use super::context::Context;
use crate::error::{Result, VkContext};

/// Set 0 of storage buffers plus one push-constant block, as one owned pipeline layout.
pub struct BindingLayout {
    ctx: Arc<Context>,
    /// Stages that see the set and the push constants.
    pub stages: vk::ShaderStageFlags,
    /// The pipeline layout (set 0 + the push-constant range at offset 0).
    pub layout: vk::PipelineLayout,
    set_layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    /// The one descriptor set.
    pub set: vk::DescriptorSet,
}

impl BindingLayout {
    /// Creates set 0 with a storage buffer at each of `bindings`, seen by `stages`, and a
    /// push-constant range of `push_size` bytes; the set's bindings are not yet written
    /// (see [`BindingLayout::bind`]). `name` labels the layout and the set for debuggers.
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        bindings: &[u32],
        stages: vk::ShaderStageFlags,
        push_size: u32,
    ) -> Result<Self> {
        let mut this = BindingLayout {
            ctx: ctx.clone(),
            stages,
            layout: vk::PipelineLayout::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
        };
        let device = ctx.device();
        let layout_bindings: Vec<_> = bindings
            .iter()
            .map(|b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(*b)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .descriptor_count(1)
                    .stage_flags(stages)
            })
            .collect();
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(stages)
            .size(push_size)];
        let pool_sizes = [vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(bindings.len().max(1) as u32)];
        // SAFETY: valid device; every create info outlives its call; handles are stored in
        // `this` as soon as they exist, so Drop frees them on any later error.
        unsafe {
            this.set_layout = device
                .create_descriptor_set_layout(
                    &vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings),
                    None,
                )
                .vk("vkCreateDescriptorSetLayout")?;
            let set_layouts = [this.set_layout];
            this.layout = device
                .create_pipeline_layout(
                    &vk::PipelineLayoutCreateInfo::default()
                        .set_layouts(&set_layouts)
                        .push_constant_ranges(&ranges),
                    None,
                )
                .vk("vkCreatePipelineLayout")?;
            this.pool = device
                .create_descriptor_pool(
                    &vk::DescriptorPoolCreateInfo::default()
                        .max_sets(1)
                        .pool_sizes(&pool_sizes),
                    None,
                )
                .vk("vkCreateDescriptorPool")?;
            this.set = device
                .allocate_descriptor_sets(
                    &vk::DescriptorSetAllocateInfo::default()
                        .descriptor_pool(this.pool)
                        .set_layouts(&set_layouts),
                )
                .vk("vkAllocateDescriptorSets")?[0];
        }
        ctx.set_name(this.layout, name);
        ctx.set_name(this.set, name);
        Ok(this)
    }

    /// [`BindingLayout::new`] with each `(binding, buffer)` written into the set.
    pub fn with_buffers(
        ctx: &Arc<Context>,
        name: &str,
        bindings: &[(u32, &Buffer)],
        stages: vk::ShaderStageFlags,
        push_size: u32,
    ) -> Result<Self> {
        let numbers: Vec<u32> = bindings.iter().map(|(b, _)| *b).collect();
        let this = Self::new(ctx, name, &numbers, stages, push_size)?;
        this.write(bindings);
        Ok(this)
    }

    /// Points `binding` of the set at `buffer`. The GPU must not be using the set.
    pub fn bind(&self, binding: u32, buffer: &Buffer) {
        self.write(&[(binding, buffer)]);
    }

    /// Points each `(binding, buffer)` of the set at its buffer. The GPU must not be using
    /// the set.
    pub fn write(&self, bindings: &[(u32, &Buffer)]) {
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
        // SAFETY: the set is alive and not in use by pending work (owners wait first); every
        // buffer info outlives the call.
        unsafe { self.ctx.device().update_descriptor_sets(&writes, &[]) };
    }

    /// Records binding the set at `bind_point` and pushing `push` (at offset 0, at most the
    /// range's size in bytes) for every stage of the layout.
    pub fn record(&self, cmd: vk::CommandBuffer, bind_point: vk::PipelineBindPoint, push: &[u8]) {
        let device = self.ctx.device();
        // SAFETY: `cmd` is recording; the layout and set are alive.
        unsafe {
            device.cmd_bind_descriptor_sets(cmd, bind_point, self.layout, 0, &[self.set], &[]);
            device.cmd_push_constants(cmd, self.layout, self.stages, 0, push);
        }
    }
}

impl Drop for BindingLayout {
    /// Frees every handle. The GPU must be done with them, and pipelines built on the
    /// layout are destroyed first (owners hold this as their last field).
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: the caller guarantees no pending use; null handles are skipped.
        unsafe {
            if self.pool != vk::DescriptorPool::null() {
                device.destroy_descriptor_pool(self.pool, None);
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
