//! The render's own static GPU data, uploaded once from the [`Model`]: the surface triangles
//! (the index buffer), the surface nodes, node adjacency (to triangles, tets and springs) for
//! the `attrs` pass, and the per-node attribute buffer. The tets, rest volumes and springs it
//! compares against are the simulation's own buffers
//! ([`crate::backend::vulkan::DrawBuffers`], bound at each render), not copies.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::layout::binding;
use super::pipelines::Pipelines;
use crate::error::{Error, Result};
use crate::gpu::commands::{self, Access};
use crate::gpu::{Buffer, Context};
use crate::model::{adjacency, Model};

/// Buffers the render reads besides the simulation's ([`crate::backend::vulkan::DrawBuffers`]).
pub struct Geometry {
    /// 3 node indices per surface triangle; the index buffer and a storage buffer.
    pub triangles: Buffer,
    /// Indices to draw (3 per triangle).
    pub index_count: u32,
    /// Nodes on the surface.
    pub surface_node_count: u32,
    /// vec4 per node: normal and colour scalar (written by `attrs`).
    pub attrs: Buffer,
    /// Every other binding of the render set, with its binding number.
    rest: Vec<(u32, Buffer)>,
}

fn bytes<T: bytemuck::Pod>(v: &[T]) -> &[u8] {
    bytemuck::cast_slice(v)
}

impl Geometry {
    /// Uploads what the render needs of `model`.
    pub fn new(ctx: &Arc<Context>, model: &Model) -> Result<Self> {
        let n = model.node_count();
        if model.surface.is_empty() {
            return Err(Error::Mesh(
                "the model has no surface triangles to render".into(),
            ));
        }
        if let Some((f, tri)) = model
            .surface
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&v| v as usize >= n))
        {
            return Err(Error::Mesh(format!(
                "surface triangle {f} {tri:?} refers to a node beyond the {n} nodes"
            )));
        }
        let count = |what: &str, k: usize| {
            u32::try_from(k).map_err(|_| Error::Mesh(format!("{k} {what} exceed u32 indices")))
        };
        let index_count = count("surface indices", 3 * model.surface.len())?;
        let faces = adjacency(n, model.surface.iter().map(|t| t.as_slice()));
        let tets = adjacency(n, model.tets.iter().map(|t| t.as_slice()));
        let surface_nodes: Vec<u32> = (0..n as u32)
            .filter(|&i| faces.offsets[i as usize + 1] > faces.offsets[i as usize])
            .collect();

        let triangles = Buffer::new(
            ctx,
            "surface triangles",
            u64::from(index_count) * 4,
            vk::BufferUsageFlags::INDEX_BUFFER
                | vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        triangles.upload(bytes(&model.surface))?;
        let index_read = Access {
            stage: vk::PipelineStageFlags::VERTEX_INPUT,
            access: vk::AccessFlags::INDEX_READ,
        };
        commands::one_shot(ctx, |cmd| {
            commands::barrier(ctx, cmd, &[&triangles], Access::TRANSFER_WRITE, index_read);
        })?;
        let upload = |name: &str, data: &[u8]| Buffer::with_data(ctx, name, data);
        let rest = vec![
            (
                binding::SURFACE_NODES,
                upload("surface nodes", bytes(&surface_nodes))?,
            ),
            (
                binding::FACE_OFFSETS,
                upload("node-face offsets", bytes(&faces.offsets))?,
            ),
            (
                binding::FACE_ITEMS,
                upload("node-face items", bytes(&faces.items))?,
            ),
            (
                binding::TET_OFFSETS,
                upload("node-tet offsets", bytes(&tets.offsets))?,
            ),
            (
                binding::TET_ITEMS,
                upload("node-tet items", bytes(&tets.items))?,
            ),
            (
                binding::SPRING_OFFSETS,
                upload(
                    "render node-spring offsets",
                    bytes(&model.node_springs.offsets),
                )?,
            ),
            (
                binding::SPRING_ITEMS,
                upload("render node-spring items", bytes(&model.node_springs.items))?,
            ),
        ];
        let attrs = Buffer::new(
            ctx,
            "render node attributes",
            n as u64 * 16,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        Ok(Geometry {
            triangles,
            index_count,
            surface_node_count: count("surface nodes", surface_nodes.len())?,
            attrs,
            rest,
        })
    }

    /// Points the render set's bindings of the render's own data at these buffers.
    pub fn bind(&self, pipelines: &Pipelines) {
        pipelines.bind(binding::ATTRS, &self.attrs);
        pipelines.bind(binding::TRIANGLES, &self.triangles);
        for (b, buffer) in &self.rest {
            pipelines.bind(*b, buffer);
        }
    }
}
