//! GPU timestamps around named passes. A recorded command buffer writes one timestamp at
//! its start and one after every pass; the time between a pass's timestamp and the one
//! before it is that pass's GPU time (its dispatch plus the barrier that follows).

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use crate::error::{Error, Result, VkContext};

/// GPU time of one pass, averaged over the frames measured so far.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PassTime {
    /// Pass name (`spring_scatter`, `volume`, `integrate`, ...).
    pub name: String,
    /// GPU time per frame [ms], summed over all of the pass's dispatches in a frame.
    pub ms_per_frame: f64,
}

/// A timestamp query pool with the pass name of every slot, freed on drop.
pub struct Timer {
    ctx: Arc<Context>,
    pool: vk::QueryPool,
    capacity: u32,
    /// `labels[k]` names the pass that ends at query `k + 1`.
    labels: Vec<&'static str>,
    period_ns: f64,
    mask: u64,
    totals_ns: Vec<(&'static str, f64)>,
    frames: u32,
}

impl Timer {
    /// A pool for `passes` timestamped passes per submission; `None` when the device's
    /// queue has no timestamps.
    pub fn new(ctx: &Arc<Context>, passes: u32) -> Result<Option<Self>> {
        let info = ctx.info();
        if !info.timestamps {
            return Ok(None);
        }
        let capacity = passes + 1;
        let create = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(capacity);
        // SAFETY: valid device and create info.
        let pool =
            unsafe { ctx.device().create_query_pool(&create, None) }.vk("vkCreateQueryPool")?;
        ctx.set_name(pool, "pass timestamps");
        let mask = if info.timestamp_bits >= 64 {
            u64::MAX
        } else {
            (1u64 << info.timestamp_bits) - 1
        };
        Ok(Some(Timer {
            ctx: ctx.clone(),
            pool,
            capacity,
            labels: Vec::new(),
            period_ns: f64::from(info.timestamp_period_ns),
            mask,
            totals_ns: Vec::new(),
            frames: 0,
        }))
    }

    /// Records the pool reset and the first timestamp (call at the start of the buffer).
    pub fn record_start(&mut self, cmd: vk::CommandBuffer) {
        let ctx = &self.ctx;
        self.labels.clear();
        // SAFETY: `cmd` is recording, outside any render pass; the pool is alive.
        unsafe {
            ctx.device()
                .cmd_reset_query_pool(cmd, self.pool, 0, self.capacity);
            ctx.device().cmd_write_timestamp(
                cmd,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                self.pool,
                0,
            );
        }
    }

    /// Records the timestamp that ends pass `name`.
    pub fn record_mark(&mut self, cmd: vk::CommandBuffer, name: &'static str) -> Result<()> {
        let slot = self.labels.len() as u32 + 1;
        if slot >= self.capacity {
            return Err(Error::Gpu(format!(
                "timestamp pool of {} queries is full at pass `{name}`",
                self.capacity
            )));
        }
        self.labels.push(name);
        // SAFETY: as in `record_start`; `slot` is inside the pool.
        unsafe {
            self.ctx.device().cmd_write_timestamp(
                cmd,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                self.pool,
                slot,
            )
        };
        Ok(())
    }

    /// Reads the timestamps of the finished submission and adds them to the totals.
    pub fn collect(&mut self) -> Result<()> {
        let ctx = &self.ctx;
        let used = self.labels.len() + 1;
        let mut ticks = vec![0u64; used];
        // SAFETY: the submission that wrote these queries has finished (fence waited).
        unsafe {
            ctx.device().get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        for (k, name) in self.labels.iter().enumerate() {
            let delta = (ticks[k + 1] & self.mask).wrapping_sub(ticks[k] & self.mask) & self.mask;
            let ns = delta as f64 * self.period_ns;
            match self.totals_ns.iter_mut().find(|(n, _)| n == name) {
                Some((_, total)) => *total += ns,
                None => self.totals_ns.push((name, ns)),
            }
        }
        self.frames += 1;
        Ok(())
    }

    /// Submissions measured so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// The GPU time per frame of every pass over all frames `timers` collected (the
    /// timers of the frame slots that take turns, each timing its own frames), in the first
    /// timer's pass order.
    pub fn per_frame_of(timers: &[&Timer]) -> Vec<PassTime> {
        let frames: u32 = timers.iter().map(|t| t.frames).sum();
        let mut totals: Vec<(&'static str, f64)> = Vec::new();
        for (name, ns) in timers.iter().flat_map(|t| t.totals_ns.iter()) {
            match totals.iter_mut().find(|(n, _)| n == name) {
                Some((_, total)) => *total += ns,
                None => totals.push((name, *ns)),
            }
        }
        let frames = f64::from(frames.max(1));
        totals
            .into_iter()
            .map(|(name, ns)| PassTime {
                name: name.to_string(),
                ms_per_frame: ns / frames / 1e6,
            })
            .collect()
    }

    /// Forgets the totals (e.g. after warm-up frames).
    pub fn reset_totals(&mut self) {
        self.totals_ns.clear();
        self.frames = 0;
    }
}

impl Drop for Timer {
    /// Frees the pool (no submission using it may be pending).
    fn drop(&mut self) {
        // SAFETY: owners wait for their submissions before dropping the timer.
        unsafe { self.ctx.device().destroy_query_pool(self.pool, None) };
    }
}
