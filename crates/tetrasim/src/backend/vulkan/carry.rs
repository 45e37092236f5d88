//! What a checkpoint of the `vulkan` backend carries beyond the state
//! ([`crate::backend::Backend::carried`]): with the finite elements, the forces the next step
//! starts from (its warm start, in the forces buffer) and the coarse level (its modes, and its
//! matrix's factor and inverse), as the device holds them, so that a resumed run ends bit for
//! bit where the uninterrupted one does; the step counter is the checkpoint's step count.

use super::plan::BufferId;
use super::VulkanBackend;
use crate::backend::Carried;
use crate::error::{Error, Result};
use crate::gpu::commands::{self, Access};
use crate::gpu::{Buffer, Uploads};

/// The device buffers a `neo-hookean` checkpoint carries, by their keys (f32 values as f64,
/// exactly).
const CARRIED: [(&str, BufferId); 3] = [
    ("vulkan_forces", BufferId::Forces),
    ("vulkan_coarse_modes", BufferId::CoarseModes),
    ("vulkan_coarse_matrix", BufferId::CoarseMatrix),
];

/// The word of `ElasticState` that counts the steps (`ELASTIC_STATE_STEP`).
const STATE_STEP: usize = 8;

impl VulkanBackend {
    /// The finite elements' arrays of a checkpoint (none without them).
    pub(super) fn carried_arrays(&self) -> Result<Vec<(String, Vec<f64>)>> {
        if self.plan.elastic_counts().is_none() {
            return Ok(Vec::new());
        }
        CARRIED
            .iter()
            .map(|&(key, id)| {
                let values = self.read_words(id)?;
                let floats = values.iter().map(|&w| f64::from(f32::from_bits(w)));
                Ok((key.to_string(), floats.collect()))
            })
            .collect()
    }

    /// Puts the finite elements' carried arrays back on the device and sets the step counter
    /// to `carried.steps` (nothing without the finite elements).
    pub(super) fn restore_arrays(&mut self, carried: &Carried) -> Result<()> {
        if self.plan.elastic_counts().is_none() {
            return Ok(());
        }
        let mut uploads = Uploads::default();
        let mut words = Vec::new();
        for &(key, id) in &CARRIED {
            let buffer = self.buffer(id)?;
            let values = carried.array(key, (buffer.size / 4) as usize)?;
            words.push(
                values
                    .iter()
                    .map(|&v| (v as f32).to_bits())
                    .collect::<Vec<u32>>(),
            );
        }
        let mut state = self.read_words(BufferId::ElasticState)?;
        state[STATE_STEP] = u32::try_from(carried.steps).map_err(|_| {
            Error::param(
                "checkpoint",
                "its step count passes the GPU's 32-bit step counter",
            )
        })?;
        words.push(state);
        let ids = CARRIED
            .iter()
            .map(|&(_, id)| id)
            .chain([BufferId::ElasticState]);
        for (id, data) in ids.zip(&words) {
            uploads.write(self.buffer(id)?, bytemuck::cast_slice(data))?;
        }
        uploads.submit(&self.ctx)
    }

    /// Buffer `id`, which the plan builds.
    fn buffer(&self, id: BufferId) -> Result<&Buffer> {
        (self.buffers.get(id))
            .ok_or_else(|| Error::Gpu(format!("buffer `{}` is not built", id.name())))
    }

    /// The 32-bit words of buffer `id`, copied to the host (every frame finished first).
    fn read_words(&self, id: BufferId) -> Result<Vec<u32>> {
        let buffer = self.buffer(id)?;
        let readback = Buffer::readback(&self.ctx, "checkpoint (readback)", buffer.size)?;
        let ctx = &self.ctx;
        commands::one_shot(ctx, |cmd| {
            commands::barrier(ctx, cmd, &[buffer], Access::COMPUTE, Access::TRANSFER_READ);
            let region = [ash::vk::BufferCopy::default().size(buffer.size)];
            // SAFETY: `cmd` is recording; both buffers are alive and `size` long.
            unsafe {
                ctx.device()
                    .cmd_copy_buffer(cmd, buffer.raw, readback.raw, &region)
            };
            commands::barrier(
                ctx,
                cmd,
                &[&readback],
                Access::TRANSFER_WRITE,
                Access::HOST_READ,
            );
        })?;
        let bytes = readback.mapped()?;
        Ok(bytemuck::cast_slice::<u8, u32>(bytes).to_vec())
    }
}
