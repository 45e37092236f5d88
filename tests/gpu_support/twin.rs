//! The twin checks' harness: one or a few shaders run on buffers a test fills, with the
//! validation layer on, their results copied back to the host (tests/gpu_*_twin.rs).

use std::sync::Arc;

use ash::vk;
use tetrasim::gpu::commands::{barrier, Access, BufferHandle};
use tetrasim::gpu::{Buffer, Context, ContextOptions};

/// A context on the default device with the validation layer on.
pub fn context() -> Arc<Context> {
    let options = ContextOptions {
        validation: true,
        ..Default::default()
    };
    Arc::new(Context::new(&options).expect("a Vulkan device"))
}

/// Records copying `bytes` from `from` at `src` to `to` at `dst`.
pub fn copy(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    from: &Buffer,
    to: &Buffer,
    at: [u64; 2],
    bytes: u64,
) {
    let region = [vk::BufferCopy::default()
        .src_offset(at[0])
        .dst_offset(at[1])
        .size(bytes)];
    // SAFETY: `cmd` is recording; both buffers are alive and hold the region.
    unsafe {
        ctx.device()
            .cmd_copy_buffer(cmd, from.handle(), to.handle(), &region)
    };
}

/// Records making the copies into `readback` visible to the host.
pub fn to_host(ctx: &Context, cmd: vk::CommandBuffer, readback: &Buffer) {
    barrier(
        ctx,
        cmd,
        &[readback],
        Access::TRANSFER_WRITE,
        Access::HOST_READ,
    );
}

/// The floats of `readback` once the commands ran; fails on any validation message.
pub fn floats(ctx: &Context, readback: &Buffer) -> Vec<f32> {
    let messages = ctx.validation_messages();
    assert!(messages.is_empty(), "validation: {messages:?}");
    bytemuck::cast_slice(readback.mapped().unwrap()).to_vec()
}
