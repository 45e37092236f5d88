//! Command buffers: a one-shot submit for uploads and readbacks, a reusable recorded
//! command buffer with its own pool and fence (the frame, recorded once and replayed), and
//! the barrier helpers every pass uses. Each [`Recorded`] owning its command pool means no
//! pool is shared between owners, so no pool needs a lock (see `gpu::context`).

use std::cell::Cell;
use std::marker::PhantomData;
use std::sync::Arc;

use ash::vk;

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

/// A Vulkan buffer handle a barrier can name (implemented by [`super::Buffer`]; commands do
/// not depend on how buffers are made).
pub trait BufferHandle {
    /// The raw handle.
    fn handle(&self) -> vk::Buffer;
}

/// Makes the writes of `from` to `buffers` available and visible to `to` (and orders all
/// work of `from`'s stage before `to`'s stage, which also covers write-after-read).
pub fn barrier<B: BufferHandle>(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    buffers: &[&B],
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
                .buffer(b.handle())
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

/// Makes every write of `from` available and visible to `to` (a global memory barrier, for
/// many buffers at once).
pub fn memory_barrier(ctx: &Context, cmd: vk::CommandBuffer, from: Access, to: Access) {
    let barrier = [vk::MemoryBarrier::default()
        .src_access_mask(from.access)
        .dst_access_mask(to.access)];
    // SAFETY: `cmd` is recording.
    unsafe {
        ctx.device().cmd_pipeline_barrier(
            cmd,
            from.stage,
            to.stage,
            vk::DependencyFlags::empty(),
            &barrier,
            &[],
            &[],
        );
    }
}

/// A command buffer with its own pool and fence, recorded once and submitted any number of
/// times. Dropping it waits for a pending submission.
pub struct Recorded {
    ctx: Arc<Context>,
    /// The command buffer (from `pool`; the pool must only be used through this owner).
    pub cmd: vk::CommandBuffer,
    pool: vk::CommandPool,
    fence: vk::Fence,
    pending: bool,
    /// `Send` but not `Sync`: recording into `cmd` (and `end`) needs its pool externally
    /// synchronised, so a `Recorded` is used from one thread at a time.
    _not_sync: PhantomData<Cell<()>>,
}

impl Recorded {
    /// Makes a pool with one command buffer and begins recording (`one_time`: submitted
    /// once).
    pub fn begin(ctx: &Arc<Context>, name: &str, one_time: bool) -> Result<Self> {
        let device = ctx.device();
        let pool_flags = match one_time {
            true => vk::CommandPoolCreateFlags::TRANSIENT,
            false => vk::CommandPoolCreateFlags::empty(),
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.queue_family()?)
            .flags(pool_flags);
        // SAFETY: valid device and create info.
        let pool =
            unsafe { device.create_command_pool(&pool_info, None) }.vk("vkCreateCommandPool")?;
        // From here on, Drop frees whatever exists (null handles are skipped).
        let mut recorded = Recorded {
            ctx: ctx.clone(),
            cmd: vk::CommandBuffer::null(),
            pool,
            fence: vk::Fence::null(),
            pending: false,
            _not_sync: PhantomData,
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: `pool` is this device's and used by this thread only (just made).
        recorded.cmd =
            unsafe { device.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers")?[0];
        // SAFETY: valid device.
        recorded.fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .vk("vkCreateFence")?;
        let (cmd, fence) = (recorded.cmd, recorded.fence);
        ctx.set_name(cmd, name);
        ctx.set_name(fence, name);
        let flags = if one_time {
            vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT
        } else {
            vk::CommandBufferUsageFlags::empty()
        };
        // SAFETY: a fresh command buffer, its pool owned by `recorded`.
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
        // SAFETY: the buffer is executable and not pending (waited above); the fence is not
        // pending, so it may be reset, and is then unsignalled; `self` (which owns both)
        // waits for the fence before freeing them.
        unsafe {
            ctx.device()
                .reset_fences(&[self.fence])
                .vk("vkResetFences")?;
            ctx.submit(&submit, self.fence)?;
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
    /// Waits for a pending submission, then frees the fence and the pool (with its command
    /// buffer).
    fn drop(&mut self) {
        if self.wait().is_err() {
            // The device is lost; wait for whatever can still finish.
            let _ = self.ctx.wait_idle();
        }
        // SAFETY: nothing is pending; the handles belong to this device and to `self` only;
        // null handles (a failed `begin`) are skipped.
        unsafe {
            if self.fence != vk::Fence::null() {
                self.ctx.device().destroy_fence(self.fence, None);
            }
            self.ctx.device().destroy_command_pool(self.pool, None);
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
