//! Named GPU buffers: device-local storage filled through a staging upload, and host-visible
//! readback buffers. One name serves the allocator and the debug label. [`Uploads`] batches
//! many uploads into one staging buffer, one command buffer and one fence wait.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::commands::{self, Access, BufferHandle};
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

impl BufferHandle for Buffer {
    fn handle(&self) -> vk::Buffer {
        self.raw
    }
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

    /// A device-local storage buffer holding `data`, uploaded through a staging buffer
    /// (its own submit; see [`Uploads`] for many).
    pub fn with_data(ctx: &Arc<Context>, name: &str, data: &[u8]) -> Result<Self> {
        let buffer = Buffer::device(ctx, name, data.len() as u64)?;
        buffer.upload(data)?;
        Ok(buffer)
    }

    /// A device-local storage buffer of `size` bytes that can be copied into and out of,
    /// contents undefined.
    pub fn device(ctx: &Arc<Context>, name: &str, size: u64) -> Result<Self> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        Buffer::new(ctx, name, size, usage, MemoryLocation::GpuOnly)
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
    /// buffer; waits for the copy, then makes it visible to compute shaders. For several
    /// buffers, one [`Uploads`] batch costs one submit instead of one each.
    pub fn upload(&self, data: &[u8]) -> Result<()> {
        let mut uploads = Uploads::default();
        uploads.write(self, data)?;
        uploads.submit(&self.ctx)
    }

    /// Writes `data` at the start of a host-visible buffer.
    pub fn write(&mut self, data: &[u8]) -> Result<()> {
        self.write_at(0, data)
    }

    /// Writes `data` at byte `offset` of a host-visible buffer.
    pub fn write_at(&mut self, offset: usize, data: &[u8]) -> Result<()> {
        let name = &self.name;
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| Error::Gpu(format!("buffer `{name}` is not host-visible")))?;
        let target = slice.get_mut(offset..offset + data.len()).ok_or_else(|| {
            Error::Gpu(format!(
                "writing {} bytes at {offset} into buffer `{name}` of {} bytes",
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

    /// The context the buffer was made on.
    pub fn context(&self) -> &Arc<Context> {
        &self.ctx
    }

    /// The whole buffer as a descriptor.
    pub fn descriptor(&self) -> vk::DescriptorBufferInfo {
        vk::DescriptorBufferInfo::default()
            .buffer(self.raw)
            .offset(0)
            .range(vk::WHOLE_SIZE)
    }
}

/// Uploads into device-local buffers, batched: [`Uploads::write`] and [`Uploads::zero`]
/// only note what to copy; [`Uploads::submit`] copies every byte into one staging buffer,
/// records every copy (and fill) in one command buffer with one barrier after them, submits
/// it once and waits once.
#[derive(Default)]
pub struct Uploads {
    /// Every upload's bytes, each starting at a multiple of [`Uploads::ALIGN`].
    staging: Vec<u8>,
    /// `(destination, offset in staging, bytes)`; `None` offset: fill with zeros.
    copies: Vec<(vk::Buffer, Option<u64>, u64)>,
}

impl Uploads {
    /// Alignment of each upload in the staging buffer [bytes].
    const ALIGN: usize = 16;

    /// Notes `data` for the start of `buffer`. The buffer must stay alive until
    /// [`Uploads::submit`] returns.
    pub fn write(&mut self, buffer: &Buffer, data: &[u8]) -> Result<()> {
        check_fits(buffer, data.len() as u64)?;
        if data.is_empty() {
            return Ok(());
        }
        let offset = self.staging.len().next_multiple_of(Self::ALIGN);
        self.staging.resize(offset, 0);
        self.staging.extend_from_slice(data);
        self.copies
            .push((buffer.raw, Some(offset as u64), data.len() as u64));
        Ok(())
    }

    /// Notes zeros for the whole of `buffer` (a fill on the GPU, nothing staged). The buffer
    /// must stay alive until [`Uploads::submit`] returns.
    pub fn zero(&mut self, buffer: &Buffer) {
        self.copies.push((buffer.raw, None, buffer.size));
    }

    /// A device-local storage buffer of `data.len()` bytes whose contents are `data` once
    /// [`Uploads::submit`] returns.
    pub fn with_data(&mut self, ctx: &Arc<Context>, name: &str, data: &[u8]) -> Result<Buffer> {
        let buffer = Buffer::device(ctx, name, data.len() as u64)?;
        self.write(&buffer, data)?;
        Ok(buffer)
    }

    /// A device-local storage buffer of `size` bytes that holds zeros once
    /// [`Uploads::submit`] returns.
    pub fn zeroed(&mut self, ctx: &Arc<Context>, name: &str, size: u64) -> Result<Buffer> {
        let buffer = Buffer::device(ctx, name, size)?;
        self.zero(&buffer);
        Ok(buffer)
    }

    /// Copies everything noted, in one submit, and waits; the data is then visible to
    /// compute shaders. Every destination buffer must still be alive (see [`Self::write`]).
    pub fn submit(self, ctx: &Arc<Context>) -> Result<()> {
        if self.copies.is_empty() {
            return Ok(());
        }
        let staging = match self.staging.is_empty() {
            true => None,
            false => {
                let mut staging = Buffer::new(
                    ctx,
                    "uploads (staging)",
                    self.staging.len() as u64,
                    vk::BufferUsageFlags::TRANSFER_SRC,
                    MemoryLocation::CpuToGpu,
                )?;
                staging.write(&self.staging)?;
                Some(staging)
            }
        };
        let device = ctx.device();
        commands::one_shot(ctx, |cmd| {
            for &(dst, offset, size) in &self.copies {
                match (offset, &staging) {
                    (Some(offset), Some(staging)) => {
                        let region = [vk::BufferCopy::default()
                            .src_offset(offset)
                            .dst_offset(0)
                            .size(size)];
                        // SAFETY: `cmd` is recording; the staging buffer holds `size` bytes
                        // at `offset` (written above) and `dst`, alive per the contract of
                        // `write`, holds at least `size` bytes (checked there).
                        unsafe { device.cmd_copy_buffer(cmd, staging.raw, dst, &region) };
                    }
                    _ => {
                        // SAFETY: `cmd` is recording; `dst` is alive per the contract of
                        // `zero`, was made with TRANSFER_DST and is filled whole.
                        unsafe { device.cmd_fill_buffer(cmd, dst, 0, vk::WHOLE_SIZE, 0) };
                    }
                }
            }
            commands::memory_barrier(ctx, cmd, Access::TRANSFER_WRITE, Access::COMPUTE);
        })
    }
}

fn check_fits(buffer: &Buffer, bytes: u64) -> Result<()> {
    if bytes > buffer.size {
        return Err(Error::Gpu(format!(
            "upload of {bytes} bytes into buffer `{}` of {} bytes",
            buffer.name, buffer.size
        )));
    }
    Ok(())
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
