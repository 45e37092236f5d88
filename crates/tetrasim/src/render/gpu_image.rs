//! A device-local 2D image with its view and memory (the render target's attachments).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result, VkContext};
use crate::gpu::Context;

/// A device-local image with its view and memory, freed on drop.
pub struct GpuImage {
    ctx: Arc<Context>,
    /// The image.
    pub raw: vk::Image,
    /// A view of the whole image.
    pub view: vk::ImageView,
    allocation: Option<Allocation>,
}

impl GpuImage {
    /// A 2D image of `format`, `samples` per pixel, for `usage`; `aspect` names the view's.
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        samples: vk::SampleCountFlags,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self> {
        let device = ctx.device();
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let raw = unsafe { device.create_image(&info, None) }.vk("vkCreateImage")?;
        let mut image = GpuImage {
            ctx: ctx.clone(),
            raw,
            view: vk::ImageView::null(),
            allocation: None,
        };
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_image_memory_requirements(raw) };
        let allocation = ctx.allocator()?.allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = allocation.map_err(|e| {
            Error::Gpu(format!(
                "allocating image `{name}` ({}x{}): {e}",
                extent.width, extent.height
            ))
        })?;
        // SAFETY: the allocation satisfies the image's requirements and is unbound.
        unsafe { device.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindImageMemory")?;
        image.allocation = Some(allocation);
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(range(aspect));
        // SAFETY: the image is bound to memory; the create info outlives the call.
        image.view =
            unsafe { device.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        ctx.set_name(raw, name);
        ctx.set_name(image.view, name);
        Ok(image)
    }
}

impl Drop for GpuImage {
    /// Frees the view, image and memory. The GPU must be done with them (owners wait first).
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: owners wait for the GPU before dropping; null handles are skipped.
        unsafe {
            if self.view != vk::ImageView::null() {
                device.destroy_image_view(self.view, None);
            }
            device.destroy_image(self.raw, None);
        }
        if let (Some(allocation), Ok(mut allocator)) =
            (self.allocation.take(), self.ctx.allocator())
        {
            let _ = allocator.free(allocation);
        }
    }
}

fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .level_count(1)
        .layer_count(1)
}
