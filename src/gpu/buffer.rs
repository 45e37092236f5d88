//! Named GPU buffers: device-local storage filled through a staging upload, and host-visible
//! readback buffers. One name serves the allocator and the debug label.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::commands::{self, Access};
use super::context::Context;
use crate::error::{Error, Result, VkContext};

/// A buffer and its memory, freed on drop (it keeps its context alive until then).
pub struct Buffer {
    ctx: Arc<Context>,
    /// The Vulkan handle.
    pub raw: vk::Buffer,
    allocation: Option<Allocation>,
    /// Size [bytes].
    pub size: u64,
    /// Debug name (also the allocation's name).
    pub name: String,
}

impl Buffer {
    /// A buffer of `size` bytes (at least 4) in `location`.
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self> {
        let size = size.max(4);
        let device = ctx.device();
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info.
        let raw = unsafe { device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        let allocated = ctx.allocator().and_then(|mut a| {
            a.allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| {
                Error::Gpu(format!(
                    "allocating buffer `{name}` ({size} bytes, {location:?}): {e}"
                ))
            })
        });
        let allocation = match allocated {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: the buffer is unused and unbound.
                unsafe { device.destroy_buffer(raw, None) };
                return Err(e);
            }
        };
        let buffer = Buffer {
            ctx: ctx.clone(),
            raw,
            allocation: Some(allocation),
            size,
            name: name.to_string(),
        };
        let bound = match &buffer.allocation {
            // SAFETY: the allocation satisfies the buffer's requirements and is unbound.
            Some(a) => unsafe { device.bind_buffer_memory(raw, a.memory(), a.offset()) }
                .vk("vkBindBufferMemory"),
            None => Ok(()),
        };
        bound?;
        ctx.set_name(raw, name);
        Ok(buffer)
    }

    /// A device-local storage buffer holding `data`, uploaded through a staging buffer.
    pub fn with_data(ctx: &Arc<Context>, name: &str, data: &[u8]) -> Result<Self> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let buffer = Buffer::new(ctx, name, data.len() as u64, usage, MemoryLocation::GpuOnly)?;
        buffer.upload(data)?;
        Ok(buffer)
    }

    /// A host-visible buffer the GPU copies results into.
    pub fn readback(ctx: &Arc<Context>, name: &str, size: u64) -> Result<Self> {
        Buffer::new(
            ctx,
            name,
            size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )
    }

    /// Overwrites the start of this (device-local) buffer with `data` through a staging
    /// buffer; waits for the copy, then makes it visible to compute shaders.
    pub fn upload(&self, data: &[u8]) -> Result<()> {
        let ctx = &self.ctx;
        if data.len() as u64 > self.size {
            return Err(Error::Gpu(format!(
                "upload of {} bytes into buffer `{}` of {} bytes",
                data.len(),
                self.name,
                self.size
            )));
        }
        if data.is_empty() {
            return Ok(());
        }
        let mut staging = Buffer::new(
            ctx,
            &format!("{} (staging)", self.name),
            data.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.write(data)?;
        commands::one_shot(ctx, |cmd| {
            let region = [vk::BufferCopy::default().size(data.len() as u64)];
            // SAFETY: both buffers are alive and large enough; recording into `cmd`.
            unsafe {
                ctx.device()
                    .cmd_copy_buffer(cmd, staging.raw, self.raw, &region)
            };
            commands::barrier(ctx, cmd, &[self], Access::TRANSFER_WRITE, Access::COMPUTE);
        })
    }

    /// Writes `data` at the start of a host-visible buffer.
    pub fn write(&mut self, data: &[u8]) -> Result<()> {
        let name = &self.name;
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| Error::Gpu(format!("buffer `{name}` is not host-visible")))?;
        let target = slice.get_mut(..data.len()).ok_or_else(|| {
            Error::Gpu(format!(
                "writing {} bytes into buffer `{name}` of {} bytes",
                data.len(),
                self.size
            ))
        })?;
        target.copy_from_slice(data);
        Ok(())
    }

    /// The contents of a host-visible buffer (read after the GPU work that wrote it has
    /// finished and was made host-visible).
    pub fn mapped(&self) -> Result<&[u8]> {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .ok_or_else(|| Error::Gpu(format!("buffer `{}` is not host-visible", self.name)))
    }

    /// The whole buffer as a descriptor.
    pub fn descriptor(&self) -> vk::DescriptorBufferInfo {
        vk::DescriptorBufferInfo::default()
            .buffer(self.raw)
            .offset(0)
            .range(vk::WHOLE_SIZE)
    }
}

impl Drop for Buffer {
    /// Frees the buffer and its memory. The GPU must be done with it (owners wait first).
    fn drop(&mut self) {
        // SAFETY: owners wait for the GPU before dropping buffers.
        unsafe { self.ctx.device().destroy_buffer(self.raw, None) };
        if let (Some(allocation), Ok(mut allocator)) =
            (self.allocation.take(), self.ctx.allocator())
        {
            // A failed free only leaks; the allocator reports leaks at shutdown.
            let _ = allocator.free(allocation);
        }
    }
}
