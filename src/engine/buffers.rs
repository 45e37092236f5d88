//! The simulation's GPU buffers (the paper's Table 1 plus what each method needs), uploaded
//! once from the [`Model`]. Only the buffers the method uses are created.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::gpu::layout::{vec4, GpuSpring, VolumePartial};
use crate::gpu::{Buffer, Context};
use crate::model::Model;
use crate::params::{ConstraintCombine, Method, SimParams};
use crate::Result;

/// Device-local state and rest data, plus the host-visible copy of the volume partials.
pub(crate) struct SimBuffers {
    /// vec4 per node: position [m], w = inverse mass [1/kg].
    pub positions: Buffer,
    /// vec4 per node: velocity [m/s], w = mass [kg].
    pub velocities: Buffer,
    /// vec4 per node: the step's force F [N] (starts as m g).
    pub forces: Buffer,
    /// One [`GpuSpring`] per spring.
    pub springs: Buffer,
    /// uvec4 per tet.
    pub tets: Buffer,
    /// float per tet: rest volume [m^3] (`volume` only).
    pub rest_volumes: Option<Buffer>,
    /// vec4 per node: one iteration's constraint sums (`distance`, `volume`).
    pub constraint_sum: Option<Buffer>,
    /// float per node: weight of the constraint sum (`distance`, `volume`).
    pub weights: Option<Buffer>,
    /// Node -> springs CSR offsets and items (`mss-node`).
    pub node_springs: Option<(Buffer, Buffer)>,
    /// One [`VolumePartial`] per volume_sum workgroup.
    pub partials: Buffer,
    /// Host-visible copy of `partials`, written at the end of every frame.
    pub partials_readback: Buffer,
}

fn bytes<T: bytemuck::Pod>(v: &[T]) -> &[u8] {
    bytemuck::cast_slice(v)
}

fn floats(v: &[f64]) -> Vec<f32> {
    v.iter().map(|&x| x as f32).collect()
}

impl SimBuffers {
    /// Uploads `model` for `params.method`; `partial_count` is the number of volume_sum
    /// workgroups.
    pub fn new(
        ctx: &Arc<Context>,
        model: &Model,
        params: &SimParams,
        partial_count: u32,
    ) -> Result<Self> {
        let n = model.node_count();
        let positions: Vec<[f32; 4]> = model
            .positions
            .iter()
            .zip(&model.inv_mass)
            .map(|(&p, &w)| vec4(p, w))
            .collect();
        let velocities: Vec<[f32; 4]> = model
            .velocities
            .iter()
            .zip(&model.mass)
            .map(|(&v, &m)| vec4(v, m))
            .collect();
        let forces: Vec<[f32; 4]> = model
            .mass
            .iter()
            .map(|&m| [0.0, -(params.gravity * m) as f32, 0.0, 0.0])
            .collect();
        let springs: Vec<GpuSpring> = model
            .springs
            .iter()
            .zip(&model.rest_length)
            .map(|(s, &l)| GpuSpring {
                a: s[0],
                b: s[1],
                rest: l as f32,
                pad: 0.0,
            })
            .collect();
        let constrained = matches!(params.method, Method::Distance | Method::Volume);
        let weights = constrained.then(|| {
            (0..n)
                .map(|i| {
                    let count = match params.method {
                        Method::Volume => model.tet_degree[i],
                        _ => model.spring_degree(i),
                    };
                    match (params.combine, count) {
                        (_, 0) => 0.0f32,
                        (ConstraintCombine::Average, c) => 1.0 / c as f32,
                        (ConstraintCombine::Sum, _) => 1.0,
                    }
                })
                .collect::<Vec<f32>>()
        });
        let partials_size = u64::from(partial_count) * std::mem::size_of::<VolumePartial>() as u64;
        Ok(SimBuffers {
            positions: Buffer::with_data(ctx, "positions", bytes(&positions))?,
            velocities: Buffer::with_data(ctx, "velocities", bytes(&velocities))?,
            forces: Buffer::with_data(ctx, "forces", bytes(&forces))?,
            springs: Buffer::with_data(ctx, "springs", bytes(&springs))?,
            tets: Buffer::with_data(ctx, "tets", bytes(&model.tets))?,
            rest_volumes: match params.method {
                Method::Volume => Some(Buffer::with_data(
                    ctx,
                    "rest volumes",
                    bytes(&floats(&model.rest_volume)),
                )?),
                _ => None,
            },
            constraint_sum: match constrained {
                true => Some(Buffer::with_data(
                    ctx,
                    "constraint sums",
                    &vec![0u8; n * 16],
                )?),
                false => None,
            },
            weights: match weights {
                Some(w) => Some(Buffer::with_data(ctx, "constraint weights", bytes(&w))?),
                None => None,
            },
            node_springs: match params.method {
                Method::MssNode => Some((
                    Buffer::with_data(
                        ctx,
                        "node-spring offsets",
                        bytes(&model.node_springs.offsets),
                    )?,
                    Buffer::with_data(ctx, "node-spring items", bytes(&model.node_springs.items))?,
                )),
                _ => None,
            },
            partials: Buffer::new(
                ctx,
                "volume partials",
                partials_size,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::GpuOnly,
            )?,
            partials_readback: Buffer::readback(ctx, "volume partials (readback)", partials_size)?,
        })
    }
}
