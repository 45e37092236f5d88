//! The offscreen target: a multisampled colour and depth-stencil image, the single-sample
//! image they resolve into, the render pass and framebuffer over them, and the host-visible
//! buffer the finished picture is copied into. Nothing here is presented: no window needed.

use std::sync::Arc;

use super::gpu_image::GpuImage;
use crate::error::{Error, Result, VkContext};
use crate::gpu::{Buffer, Context};
use ash::vk;

/// Colour format of the target: 8-bit sRGB, so shaders write linear colour.
pub const COLOUR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// Colour, depth-stencil and resolve images, their render pass and framebuffer, and the
/// readback buffer. Field order is drop order (framebuffer before render pass and images).
pub struct Target {
    ctx: Arc<Context>,
    /// The render pass (clear, draw, resolve, then ready to be copied).
    pub render_pass: vk::RenderPass,
    framebuffer: vk::Framebuffer,
    /// The single-sample image holding the finished picture (`TRANSFER_SRC_OPTIMAL` after the pass).
    pub resolved: GpuImage,
    _multisampled: Option<GpuImage>,
    _depth: GpuImage,
    /// Host-visible copy of `resolved`, `width * height * 4` bytes.
    pub readback: Buffer,
    /// Size [pixels].
    pub extent: vk::Extent2D,
    /// Samples per pixel.
    pub samples: vk::SampleCountFlags,
}

/// The largest of 4, 2, 1 samples that colour and depth attachments both support.
fn sample_count(ctx: &Context, want: u32) -> vk::SampleCountFlags {
    let limits = ctx.info().framebuffer_samples;
    [
        (4, vk::SampleCountFlags::TYPE_4),
        (2, vk::SampleCountFlags::TYPE_2),
    ]
    .into_iter()
    .find(|&(n, flag)| n <= want && limits.contains(flag))
    .map(|(_, flag)| flag)
    .unwrap_or(vk::SampleCountFlags::TYPE_1)
}

impl Target {
    /// A target of `width` x `height` pixels with up to `samples` samples per pixel.
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32, samples: u32) -> Result<Self> {
        let extent = vk::Extent2D { width, height };
        let samples = sample_count(ctx, samples);
        let multisampled = samples != vk::SampleCountFlags::TYPE_1;
        let depth_format = ctx.info().depth_stencil_format.ok_or_else(|| {
            Error::Gpu(format!(
                "device `{}` has no depth-stencil attachment format (D32_SFLOAT_S8_UINT or D24_UNORM_S8_UINT)",
                ctx.info().name
            ))
        })?;
        let resolved = GpuImage::new(
            ctx,
            "render target (resolved)",
            extent,
            COLOUR_FORMAT,
            vk::SampleCountFlags::TYPE_1,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
        )?;
        let msaa = match multisampled {
            true => Some(GpuImage::new(
                ctx,
                "render target (multisampled)",
                extent,
                COLOUR_FORMAT,
                samples,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                vk::ImageAspectFlags::COLOR,
            )?),
            false => None,
        };
        let depth = GpuImage::new(
            ctx,
            "render target (depth-stencil)",
            extent,
            depth_format,
            samples,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL,
        )?;
        let readback = Buffer::readback(
            ctx,
            "render target (readback)",
            u64::from(width) * u64::from(height) * 4,
        )?;
        let mut target = Target {
            ctx: ctx.clone(),
            render_pass: vk::RenderPass::null(),
            framebuffer: vk::Framebuffer::null(),
            resolved,
            _multisampled: msaa,
            _depth: depth,
            readback,
            extent,
            samples,
        };
        target.render_pass = create_render_pass(ctx, samples, depth_format)?;
        let mut views = Vec::new();
        if let Some(m) = &target._multisampled {
            views.push(m.view);
        } else {
            views.push(target.resolved.view);
        }
        views.push(target._depth.view);
        if multisampled {
            views.push(target.resolved.view);
        }
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(target.render_pass)
            .attachments(&views)
            .width(width)
            .height(height)
            .layers(1);
        // SAFETY: the views match the render pass's attachments; the create info outlives the call.
        target.framebuffer =
            unsafe { ctx.device().create_framebuffer(&info, None) }.vk("vkCreateFramebuffer")?;
        Ok(target)
    }

    /// Begins the render pass, clearing colour to `clear` (linear RGBA) and depth to 1.
    pub fn begin(&self, cmd: vk::CommandBuffer, clear: [f32; 4]) {
        let clears = [
            vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            },
            vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            },
        ];
        let n = if self.samples == vk::SampleCountFlags::TYPE_1 {
            2
        } else {
            3
        };
        let info = vk::RenderPassBeginInfo::default()
            .render_pass(self.render_pass)
            .framebuffer(self.framebuffer)
            .render_area(vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent: self.extent,
            })
            .clear_values(&clears[..n]);
        // SAFETY: `cmd` is recording outside a render pass; the framebuffer is alive.
        unsafe {
            self.ctx
                .device()
                .cmd_begin_render_pass(cmd, &info, vk::SubpassContents::INLINE)
        };
    }

    /// Ends the render pass and copies the resolved picture into [`Target::readback`],
    /// visible to the host once the submission's fence has signalled.
    pub fn end_and_copy(&self, cmd: vk::CommandBuffer) {
        let device = self.ctx.device();
        let region = [vk::BufferImageCopy::default()
            .image_subresource(
                vk::ImageSubresourceLayers::default()
                    .aspect_mask(vk::ImageAspectFlags::COLOR)
                    .layer_count(1),
            )
            .image_extent(vk::Extent3D {
                width: self.extent.width,
                height: self.extent.height,
                depth: 1,
            })];
        let to_host = [vk::BufferMemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
            .dst_access_mask(vk::AccessFlags::HOST_READ)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .buffer(self.readback.raw)
            .size(vk::WHOLE_SIZE)];
        // SAFETY: `cmd` is inside this target's render pass; the render pass leaves the
        // resolved image in TRANSFER_SRC_OPTIMAL and its external dependency orders the copy.
        unsafe {
            device.cmd_end_render_pass(cmd);
            device.cmd_copy_image_to_buffer(
                cmd,
                self.resolved.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                self.readback.raw,
                &region,
            );
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::HOST,
                vk::DependencyFlags::empty(),
                &[],
                &to_host,
                &[],
            );
        }
    }
}

impl Drop for Target {
    /// Frees the framebuffer and render pass; the images and buffer free themselves after.
    fn drop(&mut self) {
        // SAFETY: owners wait for the GPU first; null handles are skipped.
        unsafe {
            if self.framebuffer != vk::Framebuffer::null() {
                self.ctx
                    .device()
                    .destroy_framebuffer(self.framebuffer, None);
            }
            if self.render_pass != vk::RenderPass::null() {
                self.ctx
                    .device()
                    .destroy_render_pass(self.render_pass, None);
            }
        }
    }
}

/// Attachments: 0 colour (multisampled, or the final image when single-sampled), 1 depth-
/// stencil, 2 the resolve image (multisampled only). The final image ends in
/// TRANSFER_SRC_OPTIMAL, and an external dependency orders its copy after the pass.
fn create_render_pass(
    ctx: &Context,
    samples: vk::SampleCountFlags,
    depth_format: vk::Format,
) -> Result<vk::RenderPass> {
    let multisampled = samples != vk::SampleCountFlags::TYPE_1;
    let colour = vk::AttachmentDescription::default()
        .format(COLOUR_FORMAT)
        .samples(samples)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(if multisampled {
            vk::AttachmentStoreOp::DONT_CARE
        } else {
            vk::AttachmentStoreOp::STORE
        })
        .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
        .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(if multisampled {
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
        } else {
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL
        });
    let depth = vk::AttachmentDescription::default()
        .format(depth_format)
        .samples(samples)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .stencil_load_op(vk::AttachmentLoadOp::CLEAR)
        .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    let resolve = vk::AttachmentDescription::default()
        .format(COLOUR_FORMAT)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(vk::AttachmentLoadOp::DONT_CARE)
        .store_op(vk::AttachmentStoreOp::STORE)
        .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
        .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
    let attachments: Vec<_> = if multisampled {
        vec![colour, depth, resolve]
    } else {
        vec![colour, depth]
    };
    let colour_ref = [vk::AttachmentReference::default()
        .attachment(0)
        .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
    let depth_ref = vk::AttachmentReference::default()
        .attachment(1)
        .layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    let resolve_ref = [vk::AttachmentReference::default()
        .attachment(2)
        .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
    let mut subpass = vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&colour_ref)
        .depth_stencil_attachment(&depth_ref);
    if multisampled {
        subpass = subpass.resolve_attachments(&resolve_ref);
    }
    let subpasses = [subpass];
    let attachment_stages = vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
        | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS;
    let dependencies = [
        vk::SubpassDependency::default()
            .src_subpass(vk::SUBPASS_EXTERNAL)
            .dst_subpass(0)
            .src_stage_mask(attachment_stages | vk::PipelineStageFlags::TRANSFER)
            .dst_stage_mask(attachment_stages)
            .src_access_mask(vk::AccessFlags::TRANSFER_READ)
            .dst_access_mask(
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
        vk::SubpassDependency::default()
            .src_subpass(0)
            .dst_subpass(vk::SUBPASS_EXTERNAL)
            .src_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
            .dst_stage_mask(vk::PipelineStageFlags::TRANSFER)
            .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
            .dst_access_mask(vk::AccessFlags::TRANSFER_READ),
    ];
    let info = vk::RenderPassCreateInfo::default()
        .attachments(&attachments)
        .subpasses(&subpasses)
        .dependencies(&dependencies);
    // SAFETY: valid device; every array outlives the call.
    unsafe { ctx.device().create_render_pass(&info, None) }.vk("vkCreateRenderPass")
}
