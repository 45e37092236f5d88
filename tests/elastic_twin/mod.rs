//! The finite elements' twin checks' scene and harness (tests/gpu_elastic_*_twin.rs): a
//! damped rubber block deformed and moving, a face of it pinned, a third of its nodes held
//! by a contact and its bottom on the floor, with `cpu-ref`'s rows of it in f64, and its
//! buffers on the GPU at the engine's binding numbers with what runs the passes on them.
#![allow(dead_code)]

use std::sync::Arc;

use ash::vk;
use bytemuck::Zeroable;
use glam::DVec3;
use tetrasim::backend::vulkan::CoarseIndex;
use tetrasim::gpu::commands::{barrier, Access};
use tetrasim::gpu::layout::{binding, PushConstants};
use tetrasim::gpu::{BindingLayout, Buffer, Context, Kernel};
use tetrasim::mesh::grid::box_tets;
use tetrasim::params::Method;
use tetrasim::physics::{elastic_linearise, CoarseSpace, ElasticLinear};
use tetrasim::problem::Problem;
use tetrasim::schedule::family::ElasticNodes;
use tetrasim::{Model, ModelBuilder, SimParams};

use crate::common::{material_params, noise3, unplaced};
use crate::gpu_support::twin;

/// Planes of ElasticNodes (glsl/physics/newton.glsl).
pub const PLANES: usize = 15;
pub const AT: usize = 0;
pub const R: usize = 3;
pub const INVERSE_A: usize = 7;
pub const INVERSE_B: usize = 8;
pub const HELD: usize = 9;
pub const PHI: usize = 10;
pub const NORMAL: usize = 11;
pub const SUM: usize = 12;
pub const PUSHED: usize = 13;
pub const NODE: usize = 14;
pub const Y: usize = 1;
pub const DX: usize = 2;
/// The state's word of `alpha`.
pub const ALPHA: usize = 2;

/// One node's row: residual, inverse block (xx yy zz xy xz yz), stiffening.
pub type Row = (DVec3, [f64; 6], DVec3);

pub fn vec4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

pub fn f32_round(v: DVec3) -> DVec3 {
    v.as_vec3().as_dvec3()
}

/// The block, its material and what the rows read: where the nodes end the step at the
/// first and the later linearisation, their elastic forces so far and contact normals.
pub struct Scene {
    pub model: Model,
    pub params: SimParams,
    pub nodes: ElasticNodes<f64>,
    pub first: Vec<DVec3>,
    pub later: Vec<DVec3>,
    pub phi: Vec<DVec3>,
    pub normal: Vec<DVec3>,
    /// The contacts' force on each node at the linearisation.
    pub pushed: Vec<DVec3>,
    /// Each node's force increment of the last iteration (before the rigid correction).
    pub sum: Vec<DVec3>,
    /// Each node's velocity, and its force so far with the floor's normal force (F, w).
    pub velocity: Vec<DVec3>,
    pub force: Vec<(DVec3, f64)>,
}

pub fn scene() -> Scene {
    scene_jittered(0.002, 0.0)
}

/// [`scene_jittered`] with no jitter, lifted off the floor, each node's elastic force so
/// far `load` [N] downward: a smooth load, whose steps the quadratic model predicts well.
pub fn scene_loaded(load: f64) -> Scene {
    let mut s = scene_jittered(0.0, 0.01);
    s.phi = vec![DVec3::new(0.0, -load, 0.0); s.phi.len()];
    s
}

/// [`scene`] with every node off its bent place by up to `jitter` [m], and where the nodes
/// end lifted by `lift` [m] (at 0 the bent bottom ends below the floor).
pub fn scene_jittered(jitter: f64, lift: f64) -> Scene {
    scene_of(jitter, lift, true)
}

/// The block free (nothing pinned), lifted 1 cm, a third of its nodes held by a contact
/// where `held`, none otherwise.
pub fn scene_free(held: bool) -> Scene {
    let mut s = scene_of(0.002, 0.01, false);
    if !held {
        s.normal = vec![DVec3::ZERO; s.normal.len()];
    }
    s
}

fn scene_of(jitter: f64, lift: f64, pinned: bool) -> Scene {
    let mesh = box_tets(DVec3::ZERO, 0.02, [6, 3, 3]);
    let mut builder = ModelBuilder::new(&mesh).placement(unplaced());
    if pinned {
        builder = builder.pinned_in_box(DVec3::splat(-1e-9), DVec3::new(1e-9, 1.0, 1.0));
    }
    let model = builder.build().unwrap();
    let params = SimParams {
        damping: Some(0.01),
        ..material_params(Method::NeoHookean, 1e5, 0.45, 1000.0)
    };
    let problem = Problem::new(&model, &params).unwrap();
    let nodes = ElasticNodes::<f64>::prepare(&problem);
    let n = model.node_count();
    // Bent and squeezed, every node off by up to `jitter` (2 mm in [`scene`]); the later linearisation moves half
    // the nodes by 1e-6 m (their tets keep their stiffness) and the rest by 3 mm.
    let first: Vec<DVec3> = (0..n)
        .map(|i| {
            let p = model.positions[i];
            let bent = p + DVec3::new(-0.1 * p.x * p.y, -0.3 * p.x * p.x, 0.05 * p.z * p.x);
            f32_round(bent + noise3(i as u64) * jitter + DVec3::Y * lift)
        })
        .collect();
    let later = (0..n)
        .map(|i| {
            let far = if model.positions[i].x < 0.06 {
                1e-6
            } else {
                3e-3
            };
            f32_round(first[i] + noise3(5000 + i as u64) * far)
        })
        .collect();
    let phi = (0..n)
        .map(|i| f32_round(noise3(9000 + i as u64) * 0.5))
        .collect();
    let normal = (0..n)
        .map(|i| match i % 3 {
            0 => DVec3::Y,
            _ => DVec3::ZERO,
        })
        .collect();
    // The held nodes pushed by 0.3 N along their contact, a tenth of them by nothing.
    let pushed = (0..n)
        .map(|i| match (i % 3, i % 30) {
            (0, 0) => DVec3::ZERO,
            (0, _) => DVec3::Y * 0.3,
            _ => DVec3::ZERO,
        })
        .collect();
    // Moving at up to 1 cm/s, the bottom's nodes pushed by the floor (a tenth not yet).
    let velocity = (0..n).map(|i| noise3(13000 + i as u64) * 0.01).collect();
    let force = (0..n)
        .map(|i| {
            let floor = match model.positions[i].y == 0.0 && i % 10 != 0 {
                true => 0.02 * (1.0 + noise3(17000 + i as u64).x),
                false => 0.0,
            };
            (noise3(19000 + i as u64) * 0.05 + DVec3::Y * floor, floor)
        })
        .collect();
    let sum = (0..n).map(|i| noise3(23000 + i as u64) * 0.01).collect();
    Scene {
        model,
        params,
        nodes,
        first,
        later,
        phi,
        normal,
        pushed,
        sum,
        velocity,
        force,
    }
}

/// The reference's rows at the nodes' ends `at` with the tets' stiffness `linear`.
pub fn reference_rows(s: &Scene, at: &[DVec3], linear: &[ElasticLinear<DVec3>]) -> Vec<Row> {
    let (model, nodes, dt) = (&s.model, &s.nodes, s.params.dt);
    let rates: Vec<[DVec3; 4]> = (0..model.tets.len())
        .map(|t| {
            let (start, end) = (|k| model.positions[k], |k| at[k]);
            nodes.rate_corners(t, model.tets[t], &linear[t], dt, start, end)
        })
        .collect();
    (0..model.node_count())
        .map(|i| {
            let (end, rate) = (|k| at[k], |item: usize| rates[item / 4][item % 4]);
            let w = model.inv_mass[i];
            nodes.newton_row(i, w, dt, s.phi[i], s.normal[i], &model.tets, end, rate)
        })
        .collect()
}

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
        let elastic: Vec<[f32; 4]> = (nodes.tets.iter().zip(&model.tets))
            .flat_map(|(e, tet)| {
                let g = |k: usize| DVec3::from_array(e.shape[k]);
                let beta = nodes.damping[tet[0] as usize].max(0.0);
                [
                    vec4(g(0), e.volume),
                    vec4(g(1), e.mu),
                    vec4(g(2), e.lambda),
                    [e.alpha as f32, beta as f32, 0.0, 0.0],
                ]
            })
            .collect();
        let upload = |name: &str, bytes: &[u8]| Buffer::with_data(&ctx, name, bytes).unwrap();
        let empty = |name: &str, bytes: usize| Buffer::device(&ctx, name, bytes as u64).unwrap();
        // The partials: 9 per workgroup of the widest pass (`elastic_potential`).
        let partials = n.max(t).div_ceil(WORKGROUP as usize);
        let state = vec![0u32; 16 + 9 * partials];
        // The coarse level at the first linearisation, its matrix's columns as the
        // reference assembles them (with the flags' slots after).
        let (_, columns) = coarse_level(s);
        let mut matrix: Vec<f32> = columns.iter().map(|&x| x as f32).collect();
        let unknowns = 6 * nodes.aggregates.len();
        matrix.extend(std::iter::repeat_n(0.0f32, unknowns));
        let aggregates = &nodes.aggregates;
        let mut lists = vec![0u32];
        for members in &aggregates.members {
            lists.push(lists.last().unwrap() + members.len() as u32);
        }
        lists.extend(aggregates.members.iter().flatten());
        lists.extend(&aggregates.of);
        let index = CoarseIndex::of(aggregates, model);
        let objects: Vec<u32> = (model.objects.windows(2))
            .flat_map(|w| {
                let free = model.inv_mass[w[0] as usize..w[1] as usize]
                    .iter()
                    .all(|&m| m > 0.0);
                let mut words = [0u32; 16];
                words[..3].copy_from_slice(&[w[0], w[1], u32::from(free)]);
                words
            })
            .collect();
        let buffers = vec![
            (
                binding::POSITIONS,
                upload("positions", bytemuck::cast_slice(&positions)),
            ),
            (
                binding::VELOCITIES,
                upload("velocities", bytemuck::cast_slice(&velocities)),
            ),
            (
                binding::FORCES,
                upload("forces", bytemuck::cast_slice(&forces)),
            ),
            (
                binding::TETS,
                upload("tets", bytemuck::cast_slice(&model.tets)),
            ),
            (
                binding::ELASTIC_TETS,
                upload("elastic tets", bytemuck::cast_slice(&elastic)),
            ),
            (
                binding::NODE_TET_OFFSETS,
                upload("offsets", bytemuck::cast_slice(&nodes.node_tets.offsets)),
            ),
            (
                binding::NODE_TET_ITEMS,
                upload("items", bytemuck::cast_slice(&nodes.node_tets.items)),
            ),
            (binding::ELASTIC_LINEAR, empty("linear", 96 * t)),
            (binding::ELASTIC_CORNERS, empty("corners", 64 * t)),
            (
                binding::ELASTIC_NODES,
                upload("nodes", bytemuck::cast_slice(&planes(s, &s.first))),
            ),
            (
                binding::COARSE_MATRIX,
                upload("coarse matrix", bytemuck::cast_slice(&matrix)),
            ),
            (
                binding::COARSE_VECTOR,
                empty("coarse vector", 4 * unknowns.max(1)),
            ),
            (
                binding::COARSE_AGGREGATES,
                upload("coarse aggregates", bytemuck::cast_slice(&lists)),
            ),
            (
                binding::COARSE_MODES,
                empty("coarse modes", 16 * aggregates.len().max(1)),
            ),
            (
                binding::COARSE_INDEX,
                upload("coarse index", bytemuck::cast_slice(&index.words())),
            ),
            (
                binding::COARSE_SCRATCH,
                empty("coarse scratch", 144 * index.scratch_rows(aggregates)),
            ),
            (
                binding::ELASTIC_STATE,
                upload("state", bytemuck::cast_slice(&state)),
            ),
            (
                binding::ELASTIC_OBJECTS,
                upload("objects", bytemuck::cast_slice(&objects)),
            ),
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

    /// Records `pass` over `elements` invocations, then a barrier on every buffer.
    pub fn dispatch(&self, cmd: vk::CommandBuffer, pass: &Kernel, elements: usize) {
        pass.record(cmd, &self.push, elements as u32);
        let all: Vec<&Buffer> = self.buffers.iter().map(|(_, b)| b).collect();
        barrier(&self.ctx, cmd, &all, Access::COMPUTE, Access::COMPUTE);
    }

    /// Records setting word `word` of buffer `number` to 0, between barriers.
    pub fn clear_word(&self, cmd: vk::CommandBuffer, number: u32, word: u64) {
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
                .cmd_fill_buffer(cmd, handle, 4 * word, 4, 0);
        }
        barrier(
            &self.ctx,
            cmd,
            &[buffer],
            Access::TRANSFER_WRITE,
            Access::COMPUTE,
        );
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

/// The coarse level of `s` at its first linearisation, assembled as `cpu-ref` assembles it
/// (the nodes' contact stiffening from its rows), and its matrix's columns.
pub fn coarse_level(s: &Scene) -> (CoarseSpace, Vec<f64>) {
    let (model, nodes, at) = (&s.model, &s.nodes, &s.first);
    let linear: Vec<ElasticLinear<DVec3>> = (model.tets.iter().zip(&nodes.tets))
        .map(|(tet, e)| elastic_linearise(e, tet.map(|k| at[k as usize])))
        .collect();
    let held: Vec<DVec3> = (reference_rows(s, at, &linear).iter())
        .map(|row| row.2)
        .collect();
    let mut coarse = nodes.coarse_space(at);
    let n = coarse.unknowns();
    let mut columns = vec![0.0; n * n];
    for (a, block) in columns.chunks_mut(6 * n).enumerate() {
        let dt = s.params.dt;
        nodes.coarse_columns(&coarse, a, &model.tets, at, &linear, &held, dt, block);
    }
    coarse.assemble(&columns);
    (coarse, columns)
}

/// The node planes of `s` with its nodes ending at `at`.
pub fn planes(s: &Scene, at: &[DVec3]) -> Vec<[f32; 4]> {
    let n = s.model.node_count();
    let mut out = vec![[0.0f32; 4]; PLANES * n];
    for i in 0..n {
        out[AT * n + i] = vec4(at[i], 0.0);
        out[PHI * n + i] = vec4(s.phi[i], 0.0);
        out[NORMAL * n + i] = vec4(s.normal[i], 0.0);
        out[PUSHED * n + i] = vec4(s.pushed[i], 0.0);
        let w = s.model.inv_mass[i] * s.params.dt * s.params.dt;
        out[Y * n + i] = vec4(at[i] - s.phi[i] * w, 0.0);
        out[NODE * n + i] = [s.nodes.reach[i] as f32, 0.0, 0.0, 0.0];
        out[SUM * n + i] = vec4(s.sum[i], 0.0);
    }
    out
}

/// The node planes and state words of snapshot `k` of `floats`.
pub fn snapshot_of(floats: &[f32], n: usize, k: usize) -> (&[[f32; 4]], &[f32]) {
    let size = PLANES * n * 4 + 16;
    let all = &floats[k * size..(k + 1) * size];
    (
        bytemuck::cast_slice(&all[..PLANES * n * 4]),
        &all[PLANES * n * 4..],
    )
}

pub fn xyz(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0].into(), v[1].into(), v[2].into())
}
