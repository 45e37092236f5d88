//! The finite elements' Newton step on the GPU, pass by pass, equals its definition in f64
//! on a damped rubber block deformed and moving, a face of it pinned and a third of its
//! nodes held by a contact:
//! - the rows (`elastic_linearise`, its `later` variant, `elastic_rows`) against `cpu-ref`'s
//!   linearisation (`elastic_linearise`, `elastic_relinearise`, `ElasticNodes::rate_corners`
//!   and `newton_row`): each node's residual, inverse diagonal block and contact stiffening,
//!   at a step's first linearisation and at a later one that keeps the stiffness of the tets
//!   that barely moved;
//! - ten conjugate-gradient iterations (`elastic_update#start`, `elastic_scalars`,
//!   `elastic_product`, `elastic_curvature`, `elastic_update`, `elastic_direction`) against
//!   `cpu-ref`'s `conjugate_gradients` written out with the same functions (its product,
//!   increments and contact cut), block-Jacobi preconditioned and without backtracking,
//!   which the passes do not have yet: displacements, force increments and steps.
//!
//! Bricks of `vulkan`'s finite elements (docs/GPU.md, "Finite elements on the GPU").

mod common;
mod gpu_support;

use std::sync::Arc;

use ash::vk;
use bytemuck::Zeroable;
use common::{material_params, noise3, unplaced};
use glam::DVec3;
use gpu_support::twin;
use tetrasim::gpu::commands::{barrier, one_shot, Access};
use tetrasim::gpu::layout::{binding, PushConstants};
use tetrasim::gpu::{BindingLayout, Buffer, Context, Kernel};
use tetrasim::mesh::grid::box_tets;
use tetrasim::params::Method;
use tetrasim::physics::{
    elastic_linearise, elastic_product_strain, elastic_relinearise, held_increment, sym3_apply,
    ElasticLinear,
};
use tetrasim::problem::Problem;
use tetrasim::schedule::family::ElasticNodes;
use tetrasim::shaders::file;
use tetrasim::{Model, ModelBuilder, SimParams};

/// Planes of ElasticNodes (glsl/physics/newton.glsl).
const PLANES: usize = 14;
const AT: usize = 0;
const R: usize = 3;
const INVERSE_A: usize = 7;
const INVERSE_B: usize = 8;
const HELD: usize = 9;
const PHI: usize = 10;
const NORMAL: usize = 11;
const SUM: usize = 12;
const PUSHED: usize = 13;
const DX: usize = 2;
/// The state's word of `alpha`.
const ALPHA: usize = 2;

/// One node's row: residual, inverse block (xx yy zz xy xz yz), stiffening.
type Row = (DVec3, [f64; 6], DVec3);

fn vec4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

fn f32_round(v: DVec3) -> DVec3 {
    v.as_vec3().as_dvec3()
}

/// The block, its material and what the rows read: where the nodes end the step at the
/// first and the later linearisation, their elastic forces so far and contact normals.
struct Scene {
    model: Model,
    params: SimParams,
    nodes: ElasticNodes<f64>,
    first: Vec<DVec3>,
    later: Vec<DVec3>,
    phi: Vec<DVec3>,
    normal: Vec<DVec3>,
    /// The contacts' force on each node at the linearisation.
    pushed: Vec<DVec3>,
}

fn scene() -> Scene {
    let mesh = box_tets(DVec3::ZERO, 0.02, [6, 3, 3]);
    let model = ModelBuilder::new(&mesh)
        .placement(unplaced())
        .pinned_in_box(DVec3::splat(-1e-9), DVec3::new(1e-9, 1.0, 1.0))
        .build()
        .unwrap();
    let params = SimParams {
        damping: Some(0.01),
        ..material_params(Method::NeoHookean, 1e5, 0.45, 1000.0)
    };
    let problem = Problem::new(&model, &params).unwrap();
    let nodes = ElasticNodes::<f64>::prepare(&problem);
    let n = model.node_count();
    // Bent and squeezed, every node off by up to 2 mm; the later linearisation moves half
    // the nodes by 1e-6 m (their tets keep their stiffness) and the rest by 3 mm.
    let first: Vec<DVec3> = (0..n)
        .map(|i| {
            let p = model.positions[i];
            let bent = p + DVec3::new(-0.1 * p.x * p.y, -0.3 * p.x * p.x, 0.05 * p.z * p.x);
            f32_round(bent + noise3(i as u64) * 0.002)
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
    Scene {
        model,
        params,
        nodes,
        first,
        later,
        phi,
        normal,
        pushed,
    }
}

/// The reference's rows at the nodes' ends `at` with the tets' stiffness `linear`.
fn reference_rows(s: &Scene, at: &[DVec3], linear: &[ElasticLinear<DVec3>]) -> Vec<Row> {
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
struct Gpu {
    ctx: Arc<Context>,
    buffers: Vec<(u32, Buffer)>,
    layout: Arc<BindingLayout>,
    push: PushConstants,
    node_bytes: u64,
}

impl Gpu {
    /// The scene's nodes at its first linearisation, their planes filled from it.
    fn new(s: &Scene) -> Self {
        let ctx = twin::context();
        let (model, nodes) = (&s.model, &s.nodes);
        let (n, t) = (model.node_count(), model.tets.len());
        let positions: Vec<[f32; 4]> = (0..n)
            .map(|i| vec4(model.positions[i], model.inv_mass[i]))
            .collect();
        let velocities: Vec<[f32; 4]> = (0..n).map(|i| vec4(DVec3::ZERO, model.mass[i])).collect();
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
        let partials = n.div_ceil(WORKGROUP as usize);
        let state = vec![0u32; 16 + partials];
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
                binding::ELASTIC_STATE,
                upload("state", bytemuck::cast_slice(&state)),
            ),
        ];
        let numbers: Vec<u32> = buffers.iter().map(|(b, _)| *b).collect();
        let layout = Kernel::binding_layout(&ctx, "elastic twin", &numbers).unwrap();
        layout.write(&buffers.iter().map(|(b, buf)| (*b, buf)).collect::<Vec<_>>());
        let push = PushConstants {
            dt: s.params.dt as f32,
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
    fn pass(&self, key: &str, constants: &[u32]) -> Kernel {
        Kernel::with_constants(&self.ctx, key, key, &self.layout, WORKGROUP, constants).unwrap()
    }

    fn buffer(&self, number: u32) -> &Buffer {
        &self.buffers.iter().find(|(b, _)| *b == number).unwrap().1
    }

    /// Records `pass` over `elements` invocations, then a barrier on every buffer.
    fn dispatch(&self, cmd: vk::CommandBuffer, pass: &Kernel, elements: usize) {
        pass.record(cmd, &self.push, elements as u32);
        let all: Vec<&Buffer> = self.buffers.iter().map(|(_, b)| b).collect();
        barrier(&self.ctx, cmd, &all, Access::COMPUTE, Access::COMPUTE);
    }

    /// Records copying the node planes (and, with `state`, the state's first 16 words after
    /// them) into `readback` at `at`.
    fn snapshot(&self, cmd: vk::CommandBuffer, readback: &Buffer, at: u64) {
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
const WORKGROUP: u32 = 64;

/// The node planes of `s` with its nodes ending at `at`.
fn planes(s: &Scene, at: &[DVec3]) -> Vec<[f32; 4]> {
    let n = s.model.node_count();
    let mut out = vec![[0.0f32; 4]; PLANES * n];
    for i in 0..n {
        out[AT * n + i] = vec4(at[i], 0.0);
        out[PHI * n + i] = vec4(s.phi[i], 0.0);
        out[NORMAL * n + i] = vec4(s.normal[i], 0.0);
        out[PUSHED * n + i] = vec4(s.pushed[i], 0.0);
    }
    out
}

/// The node planes and state words of snapshot `k` of `floats`.
fn snapshot_of(floats: &[f32], n: usize, k: usize) -> (&[[f32; 4]], &[f32]) {
    let size = PLANES * n * 4 + 16;
    let all = &floats[k * size..(k + 1) * size];
    (
        bytemuck::cast_slice(&all[..PLANES * n * 4]),
        &all[PLANES * n * 4..],
    )
}

fn xyz(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0].into(), v[1].into(), v[2].into())
}

/// The GPU's rows at the first linearisation, then at the later one.
fn on_gpu(s: &Scene) -> [Vec<Row>; 2] {
    let gpu = Gpu::new(s);
    let (n, t) = (s.model.node_count(), s.model.tets.len());
    let later = Buffer::with_data(
        &gpu.ctx,
        "later nodes",
        bytemuck::cast_slice(&planes(s, &s.later)),
    )
    .unwrap();
    let size = gpu.node_bytes + 64;
    let readback = Buffer::readback(&gpu.ctx, "readback", 2 * size).unwrap();
    let linearise = gpu.pass(file::PASSES_ELASTIC_LINEARISE_COMP, &[]);
    let relinearise = gpu.pass(
        &format!("{}#later", file::PASSES_ELASTIC_LINEARISE_COMP),
        &[],
    );
    let rows = gpu.pass(file::PASSES_ELASTIC_ROWS_COMP, &[]);
    one_shot(&gpu.ctx, |cmd| {
        for (phase, pass) in [&linearise, &relinearise].into_iter().enumerate() {
            if phase == 1 {
                // The later linearisation's ends, over the first's (its stiffness stays).
                let nodes = gpu.buffer(binding::ELASTIC_NODES);
                barrier(
                    &gpu.ctx,
                    cmd,
                    &[nodes],
                    Access::COMPUTE,
                    Access::TRANSFER_WRITE,
                );
                twin::copy(&gpu.ctx, cmd, &later, nodes, [0, 0], gpu.node_bytes);
                barrier(
                    &gpu.ctx,
                    cmd,
                    &[nodes],
                    Access::TRANSFER_WRITE,
                    Access::COMPUTE,
                );
            }
            gpu.dispatch(cmd, pass, t);
            gpu.dispatch(cmd, &rows, n);
            gpu.snapshot(cmd, &readback, phase as u64 * size);
        }
        twin::to_host(&gpu.ctx, cmd, &readback);
    })
    .unwrap();
    let floats = twin::floats(&gpu.ctx, &readback);
    let rows_of = |phase: usize| -> Vec<Row> {
        let (planes, _) = snapshot_of(&floats, n, phase);
        let plane = |k: usize, i: usize| planes[k * n + i].map(f64::from);
        (0..n)
            .map(|i| {
                let (a, b) = (plane(INVERSE_A, i), plane(INVERSE_B, i));
                let inverse = [a[0], a[1], a[2], a[3], b[0], b[1]];
                (xyz(planes[R * n + i]), inverse, xyz(planes[HELD * n + i]))
            })
            .collect()
    };
    [rows_of(0), rows_of(1)]
}

/// Asserts `got` within `tolerance` of `want`, relative to the largest of its kind.
fn compare(phase: &str, got: &[Row], want: &[Row], tolerance: f64) {
    let largest = |f: &dyn Fn(&Row) -> f64| want.iter().map(f).fold(0.0, f64::max);
    let r_scale = largest(&|w| w.0.length());
    let inverse_scale = largest(&|w| w.1.iter().fold(0.0, |m: f64, x| m.max(x.abs())));
    let h_scale = largest(&|w| w.2.length());
    assert!(r_scale > 0.0 && inverse_scale > 0.0 && h_scale > 0.0);
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        let r = (g.0 - w.0).length() / r_scale;
        let inverse = (0..6).map(|k| (g.1[k] - w.1[k]).abs()).fold(0.0, f64::max) / inverse_scale;
        let h = (g.2 - w.2).length() / h_scale;
        assert!(
            r <= tolerance && inverse <= tolerance && h <= tolerance,
            "{phase}, node {i}: residual {} against {} ({r:e}), inverse {:?} against {:?} \
             ({inverse:e}), stiffening {} against {} ({h:e})",
            g.0,
            w.0,
            g.1,
            w.1,
            g.2,
            w.2
        );
    }
}

#[test]
fn the_gpu_newton_rows_equal_their_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let s = scene();
    let (model, nodes) = (&s.model, &s.nodes);
    let linear_at = |at: &[DVec3]| -> Vec<ElasticLinear<DVec3>> {
        (model.tets.iter().zip(&nodes.tets))
            .map(|(tet, e)| elastic_linearise(e, tet.map(|k| at[k as usize])))
            .collect()
    };
    let first = linear_at(&s.first);
    let later: Vec<_> = (model.tets.iter().zip(&nodes.tets).zip(&first))
        .map(|((tet, e), kept)| elastic_relinearise(e, tet.map(|k| s.later[k as usize]), kept))
        .collect();
    let kept = later.iter().zip(&first).filter(|(a, b)| a == b).count();
    assert!(
        kept > 20 && kept + 20 < model.tets.len(),
        "{kept} of {} tets keep their stiffness",
        model.tets.len()
    );
    let want = [
        reference_rows(&s, &s.first, &first),
        reference_rows(&s, &s.later, &later),
    ];
    let got = on_gpu(&s);
    compare("first linearisation", &got[0], &want[0], 1e-4);
    compare("later linearisation", &got[1], &want[1], 1e-4);
    let held = want[0].iter().filter(|w| w.2 != DVec3::ZERO).count();
    let pinned = want[0].iter().filter(|w| w.1 == [0.0; 6]).count();
    println!(
        "{} nodes, {} tets ({kept} keep their stiffness later), {held} held, {pinned} pinned: rows within 1e-4",
        model.node_count(),
        model.tets.len()
    );
    assert!(held > 20 && pinned > 10, "{held} held, {pinned} pinned");
}

/// Conjugate-gradient iterations compared (the default step's count).
const ITERATIONS: usize = 10;

/// After each of the reference's conjugate-gradient iterations at the first linearisation
/// (block-Jacobi preconditioner, no backtracking: the passes so far): the nodes'
/// displacements, force increments and the step `alpha`.
fn reference_iterations(s: &Scene) -> Vec<(Vec<DVec3>, Vec<DVec3>, f64)> {
    let (model, nodes, dt) = (&s.model, &s.nodes, s.params.dt);
    let linear: Vec<ElasticLinear<DVec3>> = (model.tets.iter().zip(&nodes.tets))
        .map(|(tet, e)| elastic_linearise(e, tet.map(|k| s.first[k as usize])))
        .collect();
    let rows = reference_rows(s, &s.first, &linear);
    let n = model.node_count();
    let apply = |m: &[f64; 6], v: DVec3| sym3_apply(*m, v);
    let mut r: Vec<DVec3> = rows.iter().map(|row| row.0).collect();
    let mut z: Vec<DVec3> = (0..n).map(|i| apply(&rows[i].1, r[i])).collect();
    let mut p = z.clone();
    let mut dx = vec![DVec3::ZERO; n];
    let dot = |a: &[DVec3], b: &[DVec3]| a.iter().zip(b).map(|(a, b)| a.dot(*b)).sum::<f64>();
    let mut rz = dot(&r, &z);
    let mut out = Vec::new();
    for _ in 0..ITERATIONS {
        let corners: Vec<[DVec3; 4]> = (model.tets.iter().zip(&nodes.tets).zip(&linear))
            .map(|((tet, e), lin)| elastic_product_strain(e, lin, tet.map(|k| p[k as usize])).0)
            .collect();
        let q: Vec<DVec3> = (0..n)
            .map(|i| {
                let corner = |item: usize| corners[item / 4][item % 4];
                nodes.product(i, model.inv_mass[i], dt, p[i], rows[i].2, corner)
            })
            .collect();
        let alpha = rz / dot(&p, &q);
        let sum: Vec<DVec3> = (0..n)
            .map(|i| {
                let (h, d) = (rows[i].2, p[i] * alpha);
                dx[i] += d;
                r[i] -= q[i] * alpha;
                held_increment(nodes.increment(i, dt, h, p[i], alpha), h, d, s.pushed[i])
            })
            .collect();
        z = (0..n).map(|i| apply(&rows[i].1, r[i])).collect();
        let next = dot(&r, &z);
        let beta = next / rz;
        rz = next;
        p = (0..n).map(|i| z[i] + p[i] * beta).collect();
        out.push((dx.clone(), sum, alpha));
    }
    out
}

#[test]
fn the_gpu_conjugate_gradients_equal_their_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let s = scene();
    let want = reference_iterations(&s);
    let gpu = Gpu::new(&s);
    let (n, t) = (s.model.node_count(), s.model.tets.len());
    let partials = n.div_ceil(WORKGROUP as usize) as u32;
    let size = gpu.node_bytes + 64;
    let readback = Buffer::readback(&gpu.ctx, "readback", ITERATIONS as u64 * size).unwrap();
    let key = |name: &str, variant: &str| format!("{name}#{variant}");
    let scalars = file::PASSES_ELASTIC_SCALARS_COMP;
    let passes = [
        gpu.pass(file::PASSES_ELASTIC_LINEARISE_COMP, &[]),
        gpu.pass(file::PASSES_ELASTIC_ROWS_COMP, &[]),
        gpu.pass(&key(file::PASSES_ELASTIC_UPDATE_COMP, "start"), &[]),
        gpu.pass(&key(scalars, "start"), &[partials]),
    ];
    let iteration = [
        (gpu.pass(file::PASSES_ELASTIC_PRODUCT_COMP, &[]), t),
        (gpu.pass(file::PASSES_ELASTIC_CURVATURE_COMP, &[]), n),
        (gpu.pass(&key(scalars, "alpha"), &[partials]), 1),
        (gpu.pass(file::PASSES_ELASTIC_UPDATE_COMP, &[]), n),
        (gpu.pass(&key(scalars, "beta"), &[partials]), 1),
        (gpu.pass(file::PASSES_ELASTIC_DIRECTION_COMP, &[]), n),
    ];
    one_shot(&gpu.ctx, |cmd| {
        for (pass, elements) in passes.iter().zip([t, n, n, 1]) {
            gpu.dispatch(cmd, pass, elements);
        }
        for k in 0..ITERATIONS {
            for (pass, elements) in &iteration {
                gpu.dispatch(cmd, pass, *elements);
            }
            gpu.snapshot(cmd, &readback, k as u64 * size);
        }
        twin::to_host(&gpu.ctx, cmd, &readback);
    })
    .unwrap();
    let floats = twin::floats(&gpu.ctx, &readback);
    let mut worst = 0.0f64;
    for (k, (dx, sum, alpha)) in want.iter().enumerate() {
        let (planes, state) = snapshot_of(&floats, n, k);
        let largest = |v: &[DVec3]| v.iter().map(|x| x.length()).fold(0.0, f64::max);
        let (dx_scale, sum_scale) = (largest(dx), largest(sum));
        let mut off = (f64::from(state[ALPHA]) - alpha).abs() / alpha.abs();
        for i in 0..n {
            off = off.max((xyz(planes[DX * n + i]) - dx[i]).length() / dx_scale);
            off = off.max((xyz(planes[SUM * n + i]) - sum[i]).length() / sum_scale);
        }
        assert!(
            off <= 1e-3,
            "iteration {k}: displacements, increments or alpha off by {off:e} of their size \
             (alpha {} on the GPU, {alpha} by definition)",
            state[ALPHA]
        );
        worst = worst.max(off);
    }
    println!("{ITERATIONS} iterations on {n} nodes: within {worst:.2e} of the reference");
}
