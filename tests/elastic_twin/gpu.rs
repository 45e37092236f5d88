//! The twin scene's buffers on the GPU and what runs the passes on them.

use std::sync::Arc;

use ash::vk;
use bytemuck::Zeroable;
use glam::DVec3;
use tetrasim::backend::vulkan::{collider_data, collider_poses, ElasticData};
use tetrasim::collider::Collider;
use tetrasim::gpu::commands::{barrier, one_shot, Access};
use tetrasim::gpu::layout::{binding, PushConstants};
use tetrasim::gpu::{BindingLayout, Buffer, Context, Kernel};
use tetrasim::problem::Problem;

use super::{coarse_level, planes, vec4, Scene, PLANES};
use crate::gpu_support::twin;

/// The scene's buffers on the GPU, bound at the engine's binding numbers, and what runs the
/// passes on them.
pub struct Gpu {
    pub ctx: Arc<Context>,
    pub buffers: Vec<(u32, Buffer)>,
    pub layout: Arc<BindingLayout>,
    pub push: PushConstants,
    pub node_bytes: u64,
}

impl Gpu {
    /// The scene's nodes at its first linearisation, their planes filled from it.
    pub fn new(s: &Scene) -> Self {
        let ctx = twin::context();
        let (model, nodes) = (&s.model, &s.nodes);
        let (n, t) = (model.node_count(), model.tets.len());
        let positions: Vec<[f32; 4]> = (0..n)
            .map(|i| vec4(model.positions[i], model.inv_mass[i]))
            .collect();
        let velocities: Vec<[f32; 4]> =
            (0..n).map(|i| vec4(s.velocity[i], model.mass[i])).collect();
        let forces: Vec<[f32; 4]> = s.force.iter().map(|&(f, floor)| vec4(f, floor)).collect();
        // The engine's uploads of the finite elements' data (`ElasticData`).
        let data = ElasticData::prepare(&Problem::new(model, &s.params).unwrap());
        let upload = |name: &str, bytes: &[u8]| Buffer::with_data(&ctx, name, bytes).unwrap();
        let empty = |name: &str, bytes: usize| Buffer::device(&ctx, name, bytes as u64).unwrap();
        // The partials: 9 per workgroup of the widest pass (`elastic_potential`).
        let partials = n.max(t).div_ceil(WORKGROUP as usize);
        let state = vec![0u32; 16 + 9 * partials];
        // The coarse level at the first linearisation, its matrix's columns as the
        // reference assembles them (with the flags' slots and the inverse's after).
        let (_, columns) = coarse_level(s);
        let mut matrix: Vec<f32> = columns.iter().map(|&x| x as f32).collect();
        let unknowns = 6 * nodes.aggregates.len();
        matrix.extend(std::iter::repeat_n(0.0f32, unknowns + unknowns * unknowns));
        let aggregates = &nodes.aggregates;
        // The colliders at the step from t = 0 (a placeholder of each where there is none).
        let contacts: Vec<[f32; 4]> = s.contacts.iter().map(|&c| vec4(c, 0.0)).collect();
        let (mut colliders, mut grids) = collider_data(&model.colliders);
        let mut poses = collider_poses(&model.colliders, 0, 1, s.params.dt);
        if colliders.is_empty() {
            colliders = collider_data(&[Collider::sphere(DVec3::ZERO, 1.0)]).0;
            poses = collider_poses(&[Collider::sphere(DVec3::ZERO, 1.0)], 0, 1, 1.0);
        }
        grids.push(0.0);
        let up = |b: u32, name: &str, bytes: &[u8]| (b, upload(name, bytes));
        let buffers = vec![
            up(
                binding::POSITIONS,
                "positions",
                bytemuck::cast_slice(&positions),
            ),
            up(
                binding::VELOCITIES,
                "velocities",
                bytemuck::cast_slice(&velocities),
            ),
            up(binding::FORCES, "forces", bytemuck::cast_slice(&forces)),
            up(binding::TETS, "tets", bytemuck::cast_slice(&model.tets)),
            up(
                binding::ELASTIC_TETS,
                "elastic tets",
                bytemuck::cast_slice(&data.tets),
            ),
            up(
                binding::NODE_TET_OFFSETS,
                "offsets",
                bytemuck::cast_slice(&nodes.node_tets.offsets),
            ),
            up(
                binding::NODE_TET_ITEMS,
                "items",
                bytemuck::cast_slice(&nodes.node_tets.items),
            ),
            (binding::ELASTIC_LINEAR, empty("linear", 96 * t)),
            (binding::ELASTIC_CORNERS, empty("corners", 64 * t)),
            (binding::CONTRIBUTIONS, empty("contributions", 16 * n)),
            up(
                binding::ELASTIC_NODES,
                "nodes",
                bytemuck::cast_slice(&planes(s, &s.first)),
            ),
            up(
                binding::COARSE_MATRIX,
                "coarse matrix",
                bytemuck::cast_slice(&matrix),
            ),
            (
                binding::COARSE_VECTOR,
                empty("coarse vector", 8 * unknowns.max(1)),
            ),
            up(
                binding::COARSE_AGGREGATES,
                "coarse aggregates",
                bytemuck::cast_slice(&data.aggregates),
            ),
            (
                binding::COARSE_MODES,
                empty("coarse modes", 16 * aggregates.len().max(1)),
            ),
            up(
                binding::COARSE_INDEX,
                "coarse index",
                bytemuck::cast_slice(&data.index),
            ),
            (
                binding::COARSE_SCRATCH,
                empty("coarse scratch", 144 * data.counts.scratch_rows as usize),
            ),
            up(
                binding::ELASTIC_STATE,
                "state",
                bytemuck::cast_slice(&state),
            ),
            up(
                binding::ELASTIC_OBJECTS,
                "objects",
                bytemuck::cast_slice(&data.objects),
            ),
            up(
                binding::COLLIDER_CONTACTS,
                "collider contacts",
                bytemuck::cast_slice(&contacts),
            ),
            up(
                binding::COLLIDERS,
                "colliders",
                bytemuck::cast_slice(&colliders),
            ),
            up(
                binding::COLLIDER_GRIDS,
                "grids",
                bytemuck::cast_slice(&grids),
            ),
            up(
                binding::COLLIDER_POSES,
                "poses",
                bytemuck::cast_slice(&poses),
            ),
            (binding::GRAB_NODES, empty("grab nodes", 16)),
            (binding::GRAB_TARGETS, empty("grab targets", 16)),
        ];
        let numbers: Vec<u32> = buffers.iter().map(|(b, _)| *b).collect();
        let layout = Kernel::binding_layout(&ctx, "elastic twin", &numbers).unwrap();
        layout.write(&buffers.iter().map(|(b, buf)| (*b, buf)).collect::<Vec<_>>());
        let push = PushConstants {
            dt: s.params.dt as f32,
            gravity: s.params.gravity.as_vec3().to_array(),
            floor_on: 1,
            node_count: n as u32,
            tet_count: t as u32,
            ..PushConstants::zeroed()
        };
        let node_bytes = (PLANES * n * 16) as u64;
        Gpu {
            ctx,
            buffers,
            layout,
            push,
            node_bytes,
        }
    }

    /// The pass of shader `key` (a variant after `#`), its specialisation constants from
    /// id 1 on being `constants`.
    pub fn pass(&self, key: &str, constants: &[u32]) -> Kernel {
        Kernel::with_constants(&self.ctx, key, key, &self.layout, WORKGROUP, constants).unwrap()
    }

    pub fn buffer(&self, number: u32) -> &Buffer {
        &self.buffers.iter().find(|(b, _)| *b == number).unwrap().1
    }

    /// Records `pass` over `elements` invocations in iteration 0, then a barrier on every
    /// buffer.
    pub fn dispatch(&self, cmd: vk::CommandBuffer, pass: &Kernel, elements: usize) {
        self.dispatch_at(cmd, pass, elements, 0);
    }

    /// [`Self::dispatch`] in conjugate-gradient iteration `iteration` (the push constant
    /// the passes decide a linearisation by).
    pub fn dispatch_at(
        &self,
        cmd: vk::CommandBuffer,
        pass: &Kernel,
        elements: usize,
        iteration: u32,
    ) {
        let push = PushConstants {
            iteration,
            ..self.push
        };
        pass.record(cmd, &push, elements as u32);
        let all: Vec<&Buffer> = self.buffers.iter().map(|(_, b)| b).collect();
        barrier(&self.ctx, cmd, &all, Access::COMPUTE, Access::COMPUTE);
    }

    /// Records setting word `word` of buffer `number` to 0, between barriers.
    pub fn clear_word(&self, cmd: vk::CommandBuffer, number: u32, word: u64) {
        self.set_word(cmd, number, word, 0);
    }

    /// Records setting word `word` of buffer `number` to `value`, between barriers.
    pub fn set_word(&self, cmd: vk::CommandBuffer, number: u32, word: u64, value: u32) {
        let buffer = self.buffer(number);
        barrier(
            &self.ctx,
            cmd,
            &[buffer],
            Access::COMPUTE,
            Access::TRANSFER_WRITE,
        );
        // SAFETY: `cmd` is recording; the buffer is alive and holds the word.
        unsafe {
            let handle = tetrasim::gpu::commands::BufferHandle::handle(buffer);
            self.ctx
                .device()
                .cmd_fill_buffer(cmd, handle, 4 * word, 4, value);
        }
        barrier(
            &self.ctx,
            cmd,
            &[buffer],
            Access::TRANSFER_WRITE,
            Access::COMPUTE,
        );
    }

    /// Records setting every node's vec4 of plane `plane` to `(v, 0)`.
    pub fn set_plane(&self, cmd: vk::CommandBuffer, plane: usize, v: DVec3) {
        let n = self.push.node_count as usize;
        let values = vec![vec4(v, 0.0); n];
        let buffer = self.buffer(binding::ELASTIC_NODES);
        barrier(
            &self.ctx,
            cmd,
            &[buffer],
            Access::COMPUTE,
            Access::TRANSFER_WRITE,
        );
        // SAFETY: `cmd` is recording; the buffer is alive and holds the plane (at most
        // 65536 bytes, vkCmdUpdateBuffer's limit, for the scenes here).
        unsafe {
            let handle = tetrasim::gpu::commands::BufferHandle::handle(buffer);
            let at = (16 * plane * n) as u64;
            self.ctx
                .device()
                .cmd_update_buffer(cmd, handle, at, bytemuck::cast_slice(&values));
        }
        barrier(
            &self.ctx,
            cmd,
            &[buffer],
            Access::TRANSFER_WRITE,
            Access::COMPUTE,
        );
    }

    /// Runs `passes` (each over its element count) in one submission, `prepare` recorded
    /// after the first `at` of them; the node planes and state words after the last.
    pub fn run(
        &self,
        passes: &[(&Kernel, usize)],
        at: usize,
        prepare: impl Fn(vk::CommandBuffer),
    ) -> Vec<f32> {
        let readback = Buffer::readback(&self.ctx, "readback", self.node_bytes + 64).unwrap();
        one_shot(&self.ctx, |cmd| {
            for (k, (pass, elements)) in passes.iter().enumerate() {
                if k == at {
                    prepare(cmd);
                }
                self.dispatch(cmd, pass, *elements);
            }
            self.snapshot(cmd, &readback, 0);
            twin::to_host(&self.ctx, cmd, &readback);
        })
        .unwrap();
        twin::floats(&self.ctx, &readback)
    }

    /// Records copying the node planes (and, with `state`, the state's first 16 words after
    /// them) into `readback` at `at`.
    pub fn snapshot(&self, cmd: vk::CommandBuffer, readback: &Buffer, at: u64) {
        let all: Vec<&Buffer> = self.buffers.iter().map(|(_, b)| b).collect();
        barrier(&self.ctx, cmd, &all, Access::COMPUTE, Access::TRANSFER_READ);
        let nodes = self.buffer(binding::ELASTIC_NODES);
        twin::copy(&self.ctx, cmd, nodes, readback, [0, at], self.node_bytes);
        let state = self.buffer(binding::ELASTIC_STATE);
        twin::copy(
            &self.ctx,
            cmd,
            state,
            readback,
            [0, at + self.node_bytes],
            64,
        );
        barrier(&self.ctx, cmd, &all, Access::TRANSFER_READ, Access::COMPUTE);
    }
}

/// Invocations per workgroup of the passes here.
pub const WORKGROUP: u32 = 64;
