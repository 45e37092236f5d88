//! The finite elements' twin checks' scene and harness (tests/gpu_elastic_*_twin.rs): a
//! damped rubber block deformed and moving, a face of it pinned, a third of its nodes held
//! by a contact and its bottom on the floor, with `cpu-ref`'s rows of it in f64, and its
//! buffers on the GPU at the engine's binding numbers with what runs the passes on them.
#![allow(dead_code)]

use glam::DVec3;
use tetrasim::mesh::grid::box_tets;
use tetrasim::params::Method;
use tetrasim::physics::{
    correction_length, elastic_linearise, elastic_product, held_mass, CoarseSpace, ElasticLinear,
    RigidPart,
};
use tetrasim::problem::Problem;
use tetrasim::schedule::family::ElasticNodes;
use tetrasim::{Model, ModelBuilder, SimParams};

use crate::common::{material_params, noise3, unplaced};

mod gpu;
pub use gpu::{Gpu, WORKGROUP};

/// Planes of ElasticNodes (glsl/physics/newton.glsl).
pub const PLANES: usize = 14;
pub const AT: usize = 0;
pub const R: usize = 3;
pub const INVERSE_A: usize = 7;
pub const INVERSE_B: usize = 8;
pub const HELD: usize = 9;
pub const PHI: usize = 10;
pub const NORMAL: usize = 11;
pub const SUM: usize = 12;
pub const NODE: usize = 13;
pub const Y: usize = 1;
pub const P: usize = 5;
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
    /// The contacts' force on each node so far: the floor's (`force`'s w) and the colliders'.
    pub pushed: Vec<DVec3>,
    /// Each node's force increment of the last iteration (before the rigid correction).
    pub sum: Vec<DVec3>,
    /// The colliders' force on each node so far.
    pub contacts: Vec<DVec3>,
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
    // Moving at up to 1 cm/s, the bottom's nodes pushed by the floor (a tenth not yet).
    let velocity = (0..n).map(|i| noise3(13000 + i as u64) * 0.01).collect();
    let force: Vec<(DVec3, f64)> = (0..n)
        .map(|i| {
            let floor = match model.positions[i].y == 0.0 && i % 10 != 0 {
                true => 0.02 * (1.0 + noise3(17000 + i as u64).x),
                false => 0.0,
            };
            (noise3(19000 + i as u64) * 0.05 + DVec3::Y * floor, floor)
        })
        .collect();
    let sum = (0..n).map(|i| noise3(23000 + i as u64) * 0.01).collect();
    let pushed = force.iter().map(|&(_, floor)| DVec3::Y * floor).collect();
    Scene {
        contacts: vec![DVec3::ZERO; n],
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

/// cpu-ref's rigid-part correction on the increments `s.sum` at the first linearisation
/// (`elastic_group`'s last iteration): each free object's increments less its rigid part,
/// scaled by the correction's length where a contact holds it; and that length.
pub fn reference_correction(s: &Scene) -> (Vec<DVec3>, f64) {
    let (model, nodes, dt, at) = (&s.model, &s.nodes, s.params.dt, &s.first);
    let linear: Vec<ElasticLinear<DVec3>> = (model.tets.iter().zip(&nodes.tets))
        .map(|(tet, e)| elastic_linearise(e, tet.map(|k| at[k as usize])))
        .collect();
    let rows = reference_rows(s, at, &linear);
    let x = &model.positions;
    let w = &model.inv_mass;
    let moved = |i: usize| held_mass(nodes.mass[i], rows[i].2);
    let elastic = |i: usize| {
        let (f, floor) = s.force[i];
        f - s.params.gravity * model.mass[i] - DVec3::Y * floor - s.contacts[i] + s.sum[i]
    };
    let mut sum = s.sum.clone();
    let mut length = 1.0;
    for object in &nodes.free_objects {
        let part = RigidPart::of(object.clone().map(|i| (x[i], moved(i), elastic(i))));
        if object.clone().any(|i| rows[i].2 != DVec3::ZERO) {
            let n = model.node_count();
            let mut d = vec![DVec3::ZERO; n];
            for i in object.clone() {
                d[i] = -part.force(x[i], moved(i)) * (w[i] * dt * dt);
            }
            let corners: Vec<[DVec3; 4]> = (model.tets.iter().zip(&nodes.tets).zip(&linear))
                .map(|((tet, t), lin)| elastic_product(t, lin, tet.map(|k| d[k as usize])))
                .collect();
            let (mut gain, mut curvature) = (0.0, 0.0);
            for i in object.clone() {
                let corner = |item: usize| corners[item / 4][item % 4];
                let q = nodes.product(i, w[i], dt, d[i], rows[i].2, corner);
                gain += rows[i].0.dot(d[i]);
                curvature += d[i].dot(q);
            }
            length = correction_length(gain, curvature);
        }
        for i in object.clone() {
            sum[i] -= part.force(x[i], moved(i)) * length;
        }
    }
    (sum, length)
}
