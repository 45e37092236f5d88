//! [`Renderer`]: draws a model at the positions in a GPU buffer (normally the simulation's
//! own position buffer) into the offscreen target and reads back only the finished image. The
//! model's tets, rest volumes and springs are the simulation's buffers too
//! ([`DrawBuffers`]): the renderer uploads only its surface and adjacency.
//!
//! One render is one command buffer, submitted and waited for:
//! ```text
//! barrier   positions: compute writes (the simulation) -> compute / vertex reads
//! attrs     per surface node: normal, V/V0 or strain            (compute)
//! barrier   attrs -> vertex reads
//! render pass (multisampled colour + depth-stencil, resolved):
//!     floor   grid quad                    shadow   planar projection, stencil once
//!     surface indexed triangles, lit       collider the colliders at the picture's time
//!     legend  colour bar (colour modes only)
//! copy      resolved image -> host-visible buffer
//! ```

use std::sync::Arc;

use ash::vk;

use super::camera::SceneFrame;
use super::colliders::{self, ColliderDraw};
use super::geometry::Geometry;
use super::image::Image;
use super::layout::{binding, RenderPush};
use super::legend::LegendLayout;
use super::pipelines::{Pipelines, ATTRS_WORKGROUP};
use super::style::{linear, BACKGROUND_RGB};
use super::target::Target;
use super::RenderOptions;
use crate::backend::vulkan::DrawBuffers;
use crate::error::{Error, Result};
use crate::gpu::commands::{self, Access};
use crate::gpu::Context;
use crate::mesh::bounds_of;
use crate::model::Model;

/// Direction towards the light (normalised at use): above, from the left and front.
const LIGHT: [f32; 3] = [-0.35, 1.0, 0.45];
/// Darkness of the shadow on the floor, in [0, 1].
const SHADOW: f32 = 0.35;

/// Draws one model; see the module doc. Field order is drop order: pipelines and target go
/// before the buffers; the context last.
pub struct Renderer {
    pipelines: Pipelines,
    target: Target,
    geometry: Geometry,
    colliders: ColliderDraw,
    frame: SceneFrame,
    options: RenderOptions,
    legend: LegendLayout,
    nodes: u32,
    tets: u64,
    springs: u64,
    ctx: Arc<Context>,
}

impl Renderer {
    /// A renderer of `model` on `ctx` (the simulation's context), with the camera fitted to
    /// the model's initial positions and its colliders' initial bounds (planes aside) unless
    /// `options.camera` is given.
    pub fn new(ctx: &Arc<Context>, model: &Model, options: &RenderOptions) -> Result<Self> {
        options.validate()?;
        let info = ctx.info();
        if !info.graphics {
            return Err(Error::Gpu(format!(
                "device `{}`: its compute queue cannot draw (no graphics support); rendering needs one",
                info.name
            )));
        }
        let (mut lo, mut hi) = bounds_of(&model.positions)
            .ok_or_else(|| Error::Mesh("the model has no nodes to render".into()))?;
        if let Some((clo, chi)) = colliders::bounds_at(&model.colliders, 0.0) {
            (lo, hi) = (lo.min(clo), hi.max(chi));
        }
        let aspect = options.width as f32 / options.height as f32;
        let frame = SceneFrame::fit(lo, hi, aspect, options.camera);
        let target = Target::new(ctx, options.width, options.height, options.samples)?;
        let pipelines = Pipelines::new(ctx, target.render_pass, target.samples, target.extent)?;
        let geometry = Geometry::new(ctx, model)?;
        geometry.bind(&pipelines);
        let colliders = ColliderDraw::new(ctx, &model.colliders, &frame)?;
        colliders.bind(&pipelines);
        Ok(Renderer {
            pipelines,
            target,
            geometry,
            colliders,
            frame,
            options: options.clone(),
            legend: LegendLayout::for_size(options.width, options.height),
            nodes: u32::try_from(model.node_count()).map_err(|_| {
                Error::Mesh(format!("{} nodes exceed u32 indices", model.node_count()))
            })?,
            tets: model.tets.len() as u64,
            springs: model.springs.len() as u64,
            ctx: ctx.clone(),
        })
    }

    /// The fitted scene (camera, floor, grid).
    pub fn scene(&self) -> &SceneFrame {
        &self.frame
    }

    /// Samples per pixel actually used (the device may allow fewer than asked for).
    pub fn samples(&self) -> u32 {
        self.target.samples.as_raw()
    }

    /// The options the renderer was made with.
    pub fn options(&self) -> &RenderOptions {
        &self.options
    }

    fn push(&self) -> RenderPush {
        let f = &self.frame;
        let aspect = self.options.width as f32 / self.options.height as f32;
        let light = glam::Vec3::from(LIGHT).normalize();
        let c = f.camera.eye;
        RenderPush {
            view_proj: f.view_proj(aspect).to_cols_array_2d(),
            eye: [c.x, c.y, c.z, f.contact_height],
            light: [light.x, light.y, light.z, f.floor_half_extent],
            floor_centre: [f.floor_centre.x, SHADOW, f.floor_centre.z, f.grid],
            legend: self.legend.packed(self.options.width, self.options.height),
            range: self.options.range(),
            mode: self.options.colour.shader_mode(),
        }
    }

    /// Renders the model at `source.positions` (vec4 per node, xyz in metres), with the
    /// tets, rest volumes and springs of `source` (normally all a simulation's:
    /// [`crate::backend::vulkan::VulkanBackend::draw_buffers`]), and returns the picture. `legend`
    /// adds the colour bar and its labels (colour modes only). The colliders are drawn where
    /// they are at `time` [s], the simulated time of the positions. Waits for the GPU; reads
    /// back only the image. Fails when a buffer is too short for the model the renderer was
    /// made for.
    pub fn render(&mut self, source: DrawBuffers<'_>, legend: bool, time: f64) -> Result<Image> {
        let needs = [
            (source.positions, u64::from(self.nodes), 16, "nodes"),
            (source.tets, self.tets, 16, "tets"),
            (source.rest_volumes, self.tets, 4, "tets"),
            (source.springs, self.springs, 16, "springs"),
        ];
        for (buffer, count, stride, what) in needs {
            let needed = count * stride;
            if buffer.size < needed {
                return Err(Error::Gpu(format!(
                    "buffer `{}` holds {} bytes; {count} {what} need {needed}",
                    buffer.name, buffer.size
                )));
            }
        }
        self.colliders.set_time(time)?;
        let positions = source.positions;
        self.pipelines.bind(binding::POSITIONS, positions);
        self.pipelines.bind(binding::TETS, source.tets);
        self.pipelines
            .bind(binding::REST_VOLUMES, source.rest_volumes);
        self.pipelines.bind(binding::SPRINGS, source.springs);
        let push = self.push();
        let legend = legend && self.options.colour != super::ColourMode::Flat;
        let ctx = &self.ctx;
        let p = &self.pipelines;
        let g = &self.geometry;
        let collider_vertices = self.colliders.vertex_count;
        let device = ctx.device();
        let simulated = Access {
            stage: vk::PipelineStageFlags::COMPUTE_SHADER,
            access: vk::AccessFlags::SHADER_WRITE,
        };
        let read = Access {
            stage: vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::VERTEX_SHADER,
            access: vk::AccessFlags::SHADER_READ,
        };
        let vertex_read = Access {
            stage: vk::PipelineStageFlags::VERTEX_SHADER,
            access: vk::AccessFlags::SHADER_READ,
        };
        commands::one_shot(ctx, |cmd| {
            commands::barrier(ctx, cmd, &[positions], simulated, read);
            // SAFETY: `cmd` is recording; every pipeline, set and buffer is alive and the
            // set's bindings all point at live buffers.
            unsafe {
                let bytes = bytemuck::bytes_of(&push);
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.attrs);
                p.binding.record(cmd, vk::PipelineBindPoint::COMPUTE, bytes);
                device.cmd_dispatch(
                    cmd,
                    g.surface_node_count.div_ceil(ATTRS_WORKGROUP).max(1),
                    1,
                    1,
                );
                commands::barrier(ctx, cmd, &[&g.attrs], Access::COMPUTE, vertex_read);

                self.target.begin(cmd, linear(BACKGROUND_RGB));
                p.binding
                    .record(cmd, vk::PipelineBindPoint::GRAPHICS, bytes);
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.floor);
                device.cmd_draw(cmd, 6, 1, 0, 0);
                device.cmd_bind_index_buffer(cmd, g.triangles.raw, 0, vk::IndexType::UINT32);
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.shadow);
                device.cmd_draw_indexed(cmd, g.index_count, 1, 0, 0, 0);
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.surface);
                device.cmd_draw_indexed(cmd, g.index_count, 1, 0, 0, 0);
                if collider_vertices > 0 {
                    device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.collider);
                    device.cmd_draw(cmd, collider_vertices, 1, 0, 0);
                }
                if legend {
                    device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.legend);
                    device.cmd_draw(cmd, 6, 1, 0, 0);
                }
            }
            self.target.end_and_copy(cmd);
        })?;
        let (w, h) = (self.options.width, self.options.height);
        let bytes = self.target.readback.mapped()?;
        let rgba = bytes
            .get(..w as usize * h as usize * 4)
            .ok_or_else(|| Error::Gpu(format!("render readback is shorter than {w}x{h} pixels")))?
            .to_vec();
        let mut image = Image {
            width: w,
            height: h,
            rgba,
        };
        if legend {
            self.legend
                .label(&mut image, self.options.colour, self.options.range());
        }
        Ok(image)
    }
}
