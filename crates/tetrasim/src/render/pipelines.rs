//! The render pipelines and their one descriptor set: the `attrs` compute pipeline and the
//! graphics pipelines `floor`, `shadow`, `surface`, `collider` and `legend`, all on one pipeline layout
//! (set 0 = every render buffer, one [`RenderPush`] block for every stage).

use std::sync::Arc;

use ash::vk;

use super::layout::{binding, RenderPush};
use crate::error::{Error, Result, VkContext};
use crate::gpu::kernel::shader;
use crate::gpu::{BindingLayout, Buffer, Context};

/// Stages that see the descriptor set and the push constants.
pub const STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::COMPUTE.as_raw()
        | vk::ShaderStageFlags::VERTEX.as_raw()
        | vk::ShaderStageFlags::FRAGMENT.as_raw(),
);

/// Workgroup size of `attrs.comp` (`local_size_x` there).
pub const ATTRS_WORKGROUP: u32 = 64;

/// How one graphics pipeline draws.
#[derive(Debug, Clone, Copy)]
struct Style {
    vert: &'static str,
    frag: &'static str,
    depth_test: bool,
    depth_write: bool,
    /// Darken blending (src alpha) with a stencil test that lets each pixel through once.
    shadow: bool,
}

/// Every render pipeline, the shared layout and the descriptor set. Freed on drop.
pub struct Pipelines {
    ctx: Arc<Context>,
    /// `attrs` (compute).
    pub attrs: vk::Pipeline,
    /// `floor`, `shadow`, `surface`, `legend` (graphics).
    pub floor: vk::Pipeline,
    /// The object's planar shadow.
    pub shadow: vk::Pipeline,
    /// The object's surface.
    pub surface: vk::Pipeline,
    /// The legend's colour bar.
    pub legend: vk::Pipeline,
    /// The kinematic colliders.
    pub collider: vk::Pipeline,
    /// The shared pipeline layout and its one descriptor set (binding 0 is re-pointed at
    /// each render's position buffer). Last, so that it is freed after the pipelines.
    pub binding: BindingLayout,
}

impl Pipelines {
    /// Builds every pipeline for `render_pass` with `samples` per pixel and an
    /// `extent`-sized static viewport.
    pub fn new(
        ctx: &Arc<Context>,
        render_pass: vk::RenderPass,
        samples: vk::SampleCountFlags,
        extent: vk::Extent2D,
    ) -> Result<Self> {
        let bindings: Vec<u32> = (0..binding::COUNT).collect();
        let binding = BindingLayout::new(
            ctx,
            "render",
            &bindings,
            STAGES,
            std::mem::size_of::<RenderPush>() as u32,
        )?;
        let mut p = Pipelines {
            ctx: ctx.clone(),
            attrs: vk::Pipeline::null(),
            floor: vk::Pipeline::null(),
            shadow: vk::Pipeline::null(),
            surface: vk::Pipeline::null(),
            legend: vk::Pipeline::null(),
            collider: vk::Pipeline::null(),
            binding,
        };
        p.attrs = p.compute("render/attrs.comp")?;
        let g = |p: &Pipelines, style| p.graphics(style, render_pass, samples, extent);
        p.floor = g(
            &p,
            Style {
                vert: "render/floor.vert",
                frag: "render/floor.frag",
                depth_test: true,
                depth_write: true,
                shadow: false,
            },
        )?;
        p.shadow = g(
            &p,
            Style {
                vert: "render/shadow.vert",
                frag: "render/shadow.frag",
                depth_test: true,
                depth_write: false,
                shadow: true,
            },
        )?;
        p.surface = g(
            &p,
            Style {
                vert: "render/surface.vert",
                frag: "render/surface.frag",
                depth_test: true,
                depth_write: true,
                shadow: false,
            },
        )?;
        p.legend = g(
            &p,
            Style {
                vert: "render/legend.vert",
                frag: "render/legend.frag",
                depth_test: false,
                depth_write: false,
                shadow: false,
            },
        )?;
        p.collider = g(
            &p,
            Style {
                vert: "render/collider.vert",
                frag: "render/collider.frag",
                depth_test: true,
                depth_write: true,
                shadow: false,
            },
        )?;
        for (handle, name) in [
            (p.attrs, "attrs"),
            (p.floor, "floor"),
            (p.shadow, "shadow"),
            (p.surface, "surface"),
            (p.legend, "legend"),
            (p.collider, "collider"),
        ] {
            ctx.set_name(handle, name);
        }
        Ok(p)
    }

    /// Points `binding` of the set at `buffer`. The GPU must not be using the set.
    pub fn bind(&self, binding: u32, buffer: &Buffer) {
        self.binding.bind(binding, buffer);
    }

    fn module(&self, key: &str) -> Result<vk::ShaderModule> {
        let code = ash::util::read_spv(&mut std::io::Cursor::new(shader(key)?))
            .map_err(|e| Error::Gpu(format!("shader `{key}` is not valid SPIR-V: {e}")))?;
        // SAFETY: valid device and SPIR-V words.
        unsafe {
            self.ctx
                .device()
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&code), None)
        }
        .vk("vkCreateShaderModule")
    }

    fn compute(&self, key: &str) -> Result<vk::Pipeline> {
        let module = self.module(key)?;
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main");
        let info = [vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(self.binding.layout)];
        // SAFETY: valid device, module and layout; the module is destroyed after creation.
        let created = unsafe {
            let r =
                self.ctx
                    .device()
                    .create_compute_pipelines(vk::PipelineCache::null(), &info, None);
            self.ctx.device().destroy_shader_module(module, None);
            r
        };
        created.map(|p| p[0]).map_err(|(_, e)| Error::Vulkan {
            call: "vkCreateComputePipelines",
            result: e,
        })
    }

    fn graphics(
        &self,
        style: Style,
        render_pass: vk::RenderPass,
        samples: vk::SampleCountFlags,
        extent: vk::Extent2D,
    ) -> Result<vk::Pipeline> {
        let vert = self.module(style.vert)?;
        let frag = match self.module(style.frag) {
            Ok(m) => m,
            Err(e) => {
                // SAFETY: the module is unused.
                unsafe { self.ctx.device().destroy_shader_module(vert, None) };
                return Err(e);
            }
        };
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vert)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(frag)
                .name(c"main"),
        ];
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewports = [vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: extent.width as f32,
            height: extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        }];
        let scissors = [vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent,
        }];
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewports(&viewports)
            .scissors(&scissors);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(samples);
        let stencil = vk::StencilOpState::default()
            .compare_op(vk::CompareOp::NOT_EQUAL)
            .pass_op(vk::StencilOp::REPLACE)
            .fail_op(vk::StencilOp::KEEP)
            .depth_fail_op(vk::StencilOp::KEEP)
            .compare_mask(0xff)
            .write_mask(0xff)
            .reference(1);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(style.depth_test)
            .depth_write_enable(style.depth_write)
            .depth_compare_op(vk::CompareOp::LESS_OR_EQUAL)
            .stencil_test_enable(style.shadow)
            .front(stencil)
            .back(stencil);
        let blend_attachment = [if style.shadow {
            vk::PipelineColorBlendAttachmentState::default()
                .blend_enable(true)
                .src_color_blend_factor(vk::BlendFactor::SRC_ALPHA)
                .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
                .color_blend_op(vk::BlendOp::ADD)
                .src_alpha_blend_factor(vk::BlendFactor::ZERO)
                .dst_alpha_blend_factor(vk::BlendFactor::ONE)
                .alpha_blend_op(vk::BlendOp::ADD)
                .color_write_mask(vk::ColorComponentFlags::RGBA)
        } else {
            vk::PipelineColorBlendAttachmentState::default()
                .blend_enable(false)
                .color_write_mask(vk::ColorComponentFlags::RGBA)
        }];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachment);
        let info = [vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .layout(self.binding.layout)
            .render_pass(render_pass)
            .subpass(0)];
        // SAFETY: valid device; every state struct outlives the call; modules freed after.
        let created = unsafe {
            let r =
                self.ctx
                    .device()
                    .create_graphics_pipelines(vk::PipelineCache::null(), &info, None);
            self.ctx.device().destroy_shader_module(vert, None);
            self.ctx.device().destroy_shader_module(frag, None);
            r
        };
        created.map(|p| p[0]).map_err(|(_, e)| Error::Vulkan {
            call: "vkCreateGraphicsPipelines",
            result: e,
        })
    }
}

impl Drop for Pipelines {
    /// Frees the pipelines; the layouts and set go with `binding` after them. The GPU must be
    /// done with them (owners wait first).
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: no pending use (the renderer waits for each render); null handles skipped.
        unsafe {
            for p in [
                self.attrs,
                self.floor,
                self.shadow,
                self.surface,
                self.legend,
                self.collider,
            ] {
                if p != vk::Pipeline::null() {
                    device.destroy_pipeline(p, None);
                }
            }
        }
    }
}
