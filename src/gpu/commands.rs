//! Command buffers: a one-shot submit for uploads and readbacks, a reusable recorded
//! command buffer with its fence (the frame, recorded once and replayed), and the one
//! barrier helper every pass uses.

use std::sync::Arc;

use ash::vk;

use super::buffer::Buffer;
use super::context::Context;
use crate::error::{Result, VkContext};

/// One side of a buffer barrier: pipeline stage and memory access.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Access {
    /// Pipeline stage.
    pub stage: vk::PipelineStageFlags,
    /// Memory access.
    pub access: vk::AccessFlags,
}

impl Access {
    /// Compute shaders reading and writing storage buffers.
    pub const COMPUTE: Access = Access {
        stage: vk::PipelineStageFlags::COMPUTE_SHADER,
        access: vk::AccessFlags::from_raw(
            vk::AccessFlags::SHADER_READ.as_raw() | vk::AccessFlags::SHADER_WRITE.as_raw(),
        ),
    };
    /// A copy reading the buffer.
    pub const TRANSFER_READ: Access = Access {
        stage: vk::PipelineStageFlags::TRANSFER,
        access: vk::AccessFlags::TRANSFER_READ,
    };
    /// A copy writing the buffer.
    pub const TRANSFER_WRITE: Access = Access {
        stage: vk::PipelineStageFlags::TRANSFER,
        access: vk::AccessFlags::TRANSFER_WRITE,
    };
    /// The host reading mapped memory after a fence wait.
    pub const HOST_READ: Access = Access {
        stage: vk::PipelineStageFlags::HOST,
        access: vk::AccessFlags::HOST_READ,
    };
}

/// Makes the writes of `from` to `buffers` available and visible to `to` (and orders all
/// work of `from`'s stage before `to`'s stage, which also covers write-after-read).
pub fn barrier(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    buffers: &[&Buffer],
    from: Access,
    to: Access,
) {
    let barriers: Vec<vk::BufferMemoryBarrier> = buffers
        .iter()
        .map(|b| {
            vk::BufferMemoryBarrier::default()
                .src_access_mask(from.access)
                .dst_access_mask(to.access)
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .buffer(b.raw)
                .offset(0)
                .size(vk::WHOLE_SIZE)
        })
        .collect();
    // SAFETY: `cmd` is recording; the buffers are alive.
    unsafe {
        ctx.device().cmd_pipeline_barrier(
            cmd,
            from.stage,
            to.stage,
            vk::DependencyFlags::empty(),
            &[],
            &barriers,
            &[],
        );
    }
}

/// A command buffer with its own fence, recorded once and submitted any number of times.
/// Dropping it waits for a pending submission.
pub struct Recorded {
    ctx: Arc<Context>,
    /// The command buffer.
    pub cmd: vk::CommandBuffer,
    fence: vk::Fence,
    pending: bool,
}

impl Recorded {
    /// Allocates the command buffer and begins recording (`one_time`: submitted once).
    pub fn begin(ctx: &Arc<Context>, name: &str, one_time: bool) -> Result<Self> {
        let device = ctx.device();
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(ctx.command_pool())
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: valid pool of this device.
        let cmd =
            unsafe { device.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers")?[0];
        // SAFETY: valid device.
        let fence = match unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) } {
            Ok(f) => f,
            Err(e) => {
                // SAFETY: the command buffer was never submitted.
                unsafe { device.free_command_buffers(ctx.command_pool(), &[cmd]) };
                return Err(crate::Error::Vulkan {
                    call: "vkCreateFence",
                    result: e,
                });
            }
        };
        let recorded = Recorded {
            ctx: ctx.clone(),
            cmd,
            fence,
            pending: false,
        };
        ctx.set_name(cmd, name);
        ctx.set_name(fence, name);
        let flags = if one_time {
            vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT
        } else {
            vk::CommandBufferUsageFlags::empty()
        };
        // SAFETY: a fresh command buffer from a resettable pool.
        unsafe {
            device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default().flags(flags))
        }
        .vk("vkBeginCommandBuffer")?;
        Ok(recorded)
    }

    /// Ends recording.
    pub fn end(&self) -> Result<()> {
        // SAFETY: the command buffer is recording.
        unsafe { self.ctx.device().end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")
    }

    /// Submits to the context's queue; call [`Recorded::wait`] before submitting again.
    pub fn submit(&mut self) -> Result<()> {
        self.wait()?;
        let ctx = &self.ctx;
        let cmds = [self.cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: the buffer is executable and not pending (waited above); the fence is unsignalled.
        unsafe {
            ctx.device()
                .reset_fences(&[self.fence])
                .vk("vkResetFences")?;
            ctx.device()
                .queue_submit(ctx.queue(), &submit, self.fence)
                .vk("vkQueueSubmit")?;
        }
        self.pending = true;
        Ok(())
    }

    /// Waits until the last submission has finished; returns whether one was pending.
    pub fn wait(&mut self) -> Result<bool> {
        if !self.pending {
            return Ok(false);
        }
        // SAFETY: the fence belongs to this device.
        unsafe {
            self.ctx
                .device()
                .wait_for_fences(&[self.fence], true, u64::MAX)
        }
        .vk("vkWaitForFences")?;
        self.pending = false;
        Ok(true)
    }
}

impl Drop for Recorded {
    /// Waits for a pending submission, then frees the command buffer and fence.
    fn drop(&mut self) {
        if self.wait().is_err() {
            // The device is lost; wait for whatever can still finish.
            // SAFETY: valid device.
            let _ = unsafe { self.ctx.device().device_wait_idle() };
        }
        // SAFETY: nothing is pending; both handles belong to this device.
        unsafe {
            self.ctx.device().destroy_fence(self.fence, None);
            self.ctx
                .device()
                .free_command_buffers(self.ctx.command_pool(), &[self.cmd]);
        }
    }
}

/// Records commands with `record`, submits them once and waits for them.
pub fn one_shot(ctx: &Arc<Context>, record: impl FnOnce(vk::CommandBuffer)) -> Result<()> {
    let mut recorded = Recorded::begin(ctx, "one-shot", true)?;
    record(recorded.cmd);
    recorded.end()?;
    recorded.submit()?;
    recorded.wait().map(|_| ())
}
