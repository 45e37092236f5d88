//! The simulation's GPU buffers (the paper's Table 1 plus what each method needs), uploaded
//! once from the [`Model`]. Exactly the buffers of the [`EnginePlan`] are created, and each
//! one's size is checked against the plan.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::plan::{BufferId, EnginePlan};
use crate::gpu::layout::{vec4, GpuSpring};
use crate::gpu::{Buffer, Context};
use crate::model::Model;
use crate::params::SimParams;
use crate::{Error, Result};

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
    /// float per node: its constraint count `d_k` (`distance`, `volume`).
    pub degrees: Option<Buffer>,
    /// Node -> springs CSR offsets and items (`mss-node`).
    pub node_springs: Option<(Buffer, Buffer)>,
    /// One [`crate::gpu::layout::VolumePartial`] per volume_sum workgroup.
    pub partials: Buffer,
    /// Host-visible copy of `partials`: written at the end of every frame with per-frame
    /// metrics, else created on the first on-demand measurement.
    pub partials_readback: Option<Buffer>,
    /// Divergence status: `[flags, first bad node, speed limit (f32 bits), 0]`.
    pub status: Buffer,
    /// Host-visible copy of `status`, written at the end of every frame.
    pub status_readback: Buffer,
}

/// Initial `status`: no flags, no bad node (`u32::MAX`), the speed limit [m/s].
pub(crate) fn initial_status(speed_limit: f32) -> [u32; 4] {
    [0, u32::MAX, speed_limit.to_bits(), 0]
}

fn bytes<T: bytemuck::Pod>(v: &[T]) -> &[u8] {
    bytemuck::cast_slice(v)
}

fn floats(v: &[f64]) -> Vec<f32> {
    v.iter().map(|&x| x as f32).collect()
}

impl SimBuffers {
    /// Uploads `model` for `params` as `plan` says; `speed_limit` [m/s] goes into `status`.
    pub fn new(
        ctx: &Arc<Context>,
        model: &Model,
        params: &SimParams,
        plan: &EnginePlan,
        speed_limit: f32,
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
        let constrained = plan.has(BufferId::Degrees);
        // Per node: its constraint count d_k as a float; the shaders turn it into the A
        // scale and apply weight of `ConstraintCombine::node_factors` (push constant
        // `combine`).
        let degrees = constrained
            .then(|| model.constraint_degrees(params.method))
            .flatten()
            .map(|d| d.iter().map(|&c| c as f32).collect::<Vec<f32>>());
        let upload = |id: BufferId, data: &[u8]| Buffer::with_data(ctx, id.name(), data);
        let optional = |id: BufferId, data: &dyn Fn() -> Vec<u8>| -> Result<Option<Buffer>> {
            match plan.has(id) {
                true => Ok(Some(upload(id, &data())?)),
                false => Ok(None),
            }
        };
        let partials_size = plan.buffer(BufferId::Partials).map_or(0, |b| b.bytes);
        let status = initial_status(speed_limit);
        let buffers = SimBuffers {
            positions: upload(BufferId::Positions, bytes(&positions))?,
            velocities: upload(BufferId::Velocities, bytes(&velocities))?,
            forces: upload(BufferId::Forces, bytes(&forces))?,
            springs: upload(BufferId::Springs, bytes(&springs))?,
            tets: upload(BufferId::Tets, bytes(&model.tets))?,
            rest_volumes: optional(BufferId::RestVolumes, &|| {
                bytes(&floats(&model.rest_volume)).to_vec()
            })?,
            constraint_sum: optional(BufferId::ConstraintSum, &|| vec![0u8; n * 16])?,
            degrees: match degrees {
                Some(w) => Some(upload(BufferId::Degrees, bytes(&w))?),
                None => None,
            },
            node_springs: match (
                optional(BufferId::NodeSpringOffsets, &|| {
                    bytes(&model.node_springs.offsets).to_vec()
                })?,
                optional(BufferId::NodeSpringItems, &|| {
                    bytes(&model.node_springs.items).to_vec()
                })?,
            ) {
                (Some(o), Some(i)) => Some((o, i)),
                _ => None,
            },
            partials: Buffer::new(
                ctx,
                BufferId::Partials.name(),
                partials_size,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::GpuOnly,
            )?,
            partials_readback: match plan.metrics {
                true => Some(Buffer::readback(
                    ctx,
                    "volume partials (readback)",
                    partials_size,
                )?),
                false => None,
            },
            status: upload(BufferId::Status, bytes(&status))?,
            status_readback: Buffer::readback(ctx, "divergence status (readback)", 16)?,
        };
        buffers.check_against(plan)?;
        Ok(buffers)
    }

    /// The buffer `id`, if it was built.
    pub fn get(&self, id: BufferId) -> Option<&Buffer> {
        match id {
            BufferId::Positions => Some(&self.positions),
            BufferId::Velocities => Some(&self.velocities),
            BufferId::Forces => Some(&self.forces),
            BufferId::Springs => Some(&self.springs),
            BufferId::Tets => Some(&self.tets),
            BufferId::RestVolumes => self.rest_volumes.as_ref(),
            BufferId::ConstraintSum => self.constraint_sum.as_ref(),
            BufferId::Degrees => self.degrees.as_ref(),
            BufferId::NodeSpringOffsets => self.node_springs.as_ref().map(|b| &b.0),
            BufferId::NodeSpringItems => self.node_springs.as_ref().map(|b| &b.1),
            BufferId::Partials => Some(&self.partials),
            BufferId::Status => Some(&self.status),
        }
    }

    /// Device-local bytes of every buffer built (what the plan's total must equal).
    pub fn device_bytes(&self) -> u64 {
        ALL_BUFFERS
            .iter()
            .filter_map(|&id| self.get(id))
            .map(|b| b.size)
            .sum()
    }

    /// Fails when a buffer exists that the plan lacks, or the other way round, or when a
    /// size differs: the plan printed by `tetrasim plan` is then wrong.
    fn check_against(&self, plan: &EnginePlan) -> Result<()> {
        for id in ALL_BUFFERS {
            let built = self.get(id).map(|b| b.size);
            let planned = plan.buffer(id).map(|b| b.bytes);
            if built != planned {
                return Err(Error::Gpu(format!(
                    "engine plan mismatch for buffer `{}`: planned {planned:?} bytes, built {built:?}",
                    id.name()
                )));
            }
        }
        Ok(())
    }
}

/// Every buffer kind.
const ALL_BUFFERS: [BufferId; 12] = [
    BufferId::Positions,
    BufferId::Velocities,
    BufferId::Forces,
    BufferId::Springs,
    BufferId::Tets,
    BufferId::RestVolumes,
    BufferId::ConstraintSum,
    BufferId::Degrees,
    BufferId::NodeSpringOffsets,
    BufferId::NodeSpringItems,
    BufferId::Partials,
    BufferId::Status,
];
