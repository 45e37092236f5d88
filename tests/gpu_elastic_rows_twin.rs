//! The finite elements' Newton rows on the GPU (passes `elastic_linearise`, its `later`
//! variant, and `elastic_rows`) equal their definition, `cpu-ref`'s linearisation in f64
//! (`elastic_linearise`, `elastic_relinearise`, `ElasticNodes::rate_corners` and
//! `ElasticNodes::newton_row`), on a damped rubber block deformed and moving, a face of it
//! pinned and a third of its nodes held by a contact: each node's residual, inverse
//! diagonal block and contact stiffening, at a step's first linearisation and at a later
//! one that keeps the stiffness of the tets that barely moved. The third brick of `vulkan`'s
//! finite elements (docs/GPU.md, "Finite elements on the GPU").

mod common;
mod gpu_support;

use bytemuck::Zeroable;
use common::{material_params, noise3, unplaced};
use glam::DVec3;
use gpu_support::twin;
use tetrasim::gpu::commands::{barrier, one_shot, Access};
use tetrasim::gpu::layout::{binding, PushConstants};
use tetrasim::gpu::{Buffer, Kernel};
use tetrasim::mesh::grid::box_tets;
use tetrasim::params::Method;
use tetrasim::physics::{elastic_linearise, elastic_relinearise, ElasticLinear};
use tetrasim::problem::Problem;
use tetrasim::schedule::family::ElasticNodes;
use tetrasim::shaders::file;
use tetrasim::{Model, ModelBuilder, SimParams};

/// Planes of ElasticNodes (glsl/physics/newton.glsl).
const PLANES: usize = 12;
const AT: usize = 0;
const R: usize = 3;
const INVERSE_A: usize = 7;
const INVERSE_B: usize = 8;
const HELD: usize = 9;
const PHI: usize = 10;
const NORMAL: usize = 11;

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
    Scene {
        model,
        params,
        nodes,
        first,
        later,
        phi,
        normal,
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

/// The GPU's rows at the first linearisation, then at the later one.
fn on_gpu(s: &Scene) -> [Vec<Row>; 2] {
    let ctx = twin::context();
    let (model, nodes) = (&s.model, &s.nodes);
    let (n, t) = (model.node_count(), model.tets.len());
    let positions: Vec<[f32; 4]> = (0..n)
        .map(|i| vec4(model.positions[i], model.inv_mass[i]))
        .collect();
    let velocities: Vec<[f32; 4]> = (0..n).map(|i| vec4(DVec3::ZERO, model.mass[i])).collect();
    let tets: Vec<[u32; 4]> = model.tets.clone();
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
    let planes = |at: &[DVec3]| -> Vec<[f32; 4]> {
        let mut out = vec![[0.0f32; 4]; PLANES * n];
        for i in 0..n {
            out[AT * n + i] = vec4(at[i], 0.0);
            out[PHI * n + i] = vec4(s.phi[i], 0.0);
            out[NORMAL * n + i] = vec4(s.normal[i], 0.0);
        }
        out
    };
    let upload = |name: &str, bytes: &[u8]| Buffer::with_data(&ctx, name, bytes).unwrap();
    let node_bytes = (PLANES * n * 16) as u64;
    let buffers = [
        (
            binding::POSITIONS,
            upload("positions", bytemuck::cast_slice(&positions)),
        ),
        (
            binding::VELOCITIES,
            upload("velocities", bytemuck::cast_slice(&velocities)),
        ),
        (binding::TETS, upload("tets", bytemuck::cast_slice(&tets))),
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
        (
            binding::ELASTIC_LINEAR,
            Buffer::device(&ctx, "linear", (96 * t) as u64).unwrap(),
        ),
        (
            binding::ELASTIC_CORNERS,
            Buffer::device(&ctx, "corners", (64 * t) as u64).unwrap(),
        ),
        (
            binding::ELASTIC_NODES,
            upload("nodes", bytemuck::cast_slice(&planes(&s.first))),
        ),
    ];
    let later = upload("later nodes", bytemuck::cast_slice(&planes(&s.later)));
    let readback = Buffer::readback(&ctx, "readback", 2 * node_bytes).unwrap();
    let numbers: Vec<u32> = buffers.iter().map(|(b, _)| *b).collect();
    let layout = Kernel::binding_layout(&ctx, "rows twin", &numbers).unwrap();
    layout.write(&buffers.iter().map(|(b, buf)| (*b, buf)).collect::<Vec<_>>());
    let kernel = |name: &str, key: &str| Kernel::new(&ctx, name, key, &layout, 64).unwrap();
    let linearise = kernel("elastic_linearise", file::PASSES_ELASTIC_LINEARISE_COMP);
    let key = format!("{}#later", file::PASSES_ELASTIC_LINEARISE_COMP);
    let relinearise = kernel("elastic_linearise#later", &key);
    let rows = kernel("elastic_rows", file::PASSES_ELASTIC_ROWS_COMP);
    let push = PushConstants {
        dt: s.params.dt as f32,
        node_count: n as u32,
        tet_count: t as u32,
        ..PushConstants::zeroed()
    };
    let node_buffer = &buffers[8].1;
    let all: Vec<&Buffer> = buffers.iter().map(|(_, b)| b).collect();
    one_shot(&ctx, |cmd| {
        for (phase, pass) in [&linearise, &relinearise].into_iter().enumerate() {
            if phase == 1 {
                // The later linearisation's ends, over the first's (its stiffness stays).
                barrier(&ctx, cmd, &all, Access::COMPUTE, Access::TRANSFER_WRITE);
                twin::copy(&ctx, cmd, &later, node_buffer, [0, 0], node_bytes);
                barrier(&ctx, cmd, &all, Access::TRANSFER_WRITE, Access::COMPUTE);
            }
            pass.record(cmd, &push, t as u32);
            barrier(&ctx, cmd, &all, Access::COMPUTE, Access::COMPUTE);
            rows.record(cmd, &push, n as u32);
            barrier(&ctx, cmd, &all, Access::COMPUTE, Access::TRANSFER_READ);
            let at = [0, phase as u64 * node_bytes];
            twin::copy(&ctx, cmd, node_buffer, &readback, at, node_bytes);
        }
        twin::to_host(&ctx, cmd, &readback);
    })
    .unwrap();
    let floats = twin::floats(&ctx, &readback);
    let out: &[[f32; 4]] = bytemuck::cast_slice(&floats);
    let rows_of = |phase: usize| -> Vec<Row> {
        let plane = |k: usize, i: usize| out[phase * PLANES * n + k * n + i].map(f64::from);
        (0..n)
            .map(|i| {
                let (r, a, b, h) = (
                    plane(R, i),
                    plane(INVERSE_A, i),
                    plane(INVERSE_B, i),
                    plane(HELD, i),
                );
                let xyz = |v: [f64; 4]| DVec3::new(v[0], v[1], v[2]);
                (xyz(r), [a[0], a[1], a[2], a[3], b[0], b[1]], xyz(h))
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
