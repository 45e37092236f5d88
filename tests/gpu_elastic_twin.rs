//! The finite elements' stiffness on the GPU (glsl/physics/stiffness.glsl, run by the
//! twin check glsl/twins/stiffness.comp) equals its definition, src/physics/stiffness.rs in
//! f64, on tets stretched, sheared, compressed, flattened and inverted: the products of the
//! stiffness with corner moves (the projected volume term included), the strain of the
//! moves, the energy, and the stiffness kept or taken anew for a later linearisation. The
//! first brick of `vulkan`'s finite elements (docs/GPU.md, "Finite elements on the GPU").

mod gpu_support;

use bytemuck::Zeroable;
use glam::{DMat3, DVec3};
use gpu_support::twin;
use tetrasim::gpu::commands::{barrier, one_shot, Access};
use tetrasim::gpu::layout::PushConstants;
use tetrasim::gpu::{Buffer, Kernel};
use tetrasim::physics::{
    elastic_energy, elastic_linearise, elastic_product_strain, elastic_relinearise, lame,
    shape_gradients, singular_values, stable_neo_hookean, ElasticTet, KEPT_STIFFNESS_STRAIN,
};

/// vec4s per case in and out (glsl/twins/stiffness.comp).
const IN: usize = 16;
const OUT: usize = 10;

/// One case: a tet at rest, its material, where its corners are, how they move, and where
/// they are at a later linearisation.
struct Case {
    tet: ElasticTet<f64>,
    p: [DVec3; 4],
    d: [DVec3; 4],
    q: [DVec3; 4],
}

/// A deterministic number in [-1, 1).
fn noise(i: u64) -> f64 {
    let mut z = i.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (z ^ (z >> 31)) as f64 / u64::MAX as f64 * 2.0 - 1.0
}

fn noise3(i: u64) -> DVec3 {
    DVec3::new(noise(3 * i), noise(3 * i + 1), noise(3 * i + 2))
}

/// Values as f32 would hold them, so both sides start from the same numbers.
fn f32_round(v: DVec3) -> DVec3 {
    v.as_vec3().as_dvec3()
}

/// The deformations: rest, small strain, stretch, shear, compressions, near-flat, inverted.
fn deformation(kind: u64, seed: u64) -> DMat3 {
    let jitter = DMat3::from_cols(noise3(seed), noise3(seed + 1), noise3(seed + 2)) * 0.05;
    let base = match kind {
        0 => DMat3::IDENTITY,
        1 => DMat3::IDENTITY + jitter * 0.2,
        2 => DMat3::from_diagonal(DVec3::new(2.0, 0.8, 0.8)),
        3 => DMat3::from_cols(DVec3::X, DVec3::new(0.9, 1.0, 0.0), DVec3::Z),
        4 => DMat3::from_diagonal(DVec3::new(0.7, 0.7, 0.7)),
        5 => DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.02)),
        6 => DMat3::from_diagonal(DVec3::new(1.0, 1.0, -0.3)),
        7 => DMat3::from_diagonal(DVec3::new(0.5, 0.5, 0.5)),
        8 => DMat3::from_diagonal(DVec3::new(0.4, 1.0, 1.0)),
        9 => DMat3::from_diagonal(DVec3::new(1.5, 1.5, 0.3)),
        10 => DMat3::from_diagonal(DVec3::new(0.2, 0.3, 1.2)),
        _ => DMat3::from_diagonal(DVec3::new(-0.5, 0.6, 0.6)),
    };
    base + jitter
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for n in 0..240u64 {
        let kind = n % 12;
        let scale = 0.01 + 0.1 * (noise(1000 + n) + 1.0);
        let rest: [DVec3; 4] = std::array::from_fn(|k| {
            let corner = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z][k];
            f32_round((corner + noise3(100 * n + k as u64) * 0.2) * scale)
        });
        let Some(shape) = shape_gradients(rest) else {
            continue;
        };
        let e = 1e5 * 10f64.powf(noise(2000 + n) + 1.0);
        let nu = [0.3, 0.45, 0.49, 0.0][(n / 12 % 4) as usize];
        let (mu, lambda) = lame(e, nu);
        let (mu_s, lambda_s, alpha) = stable_neo_hookean(mu, lambda);
        let v0 = (rest[1] - rest[0]).dot((rest[2] - rest[0]).cross(rest[3] - rest[0])) / 6.0;
        let f32_of = |x: f64| x as f32 as f64;
        let tet = ElasticTet {
            shape: shape.map(|row| row.map(f32_of)),
            volume: f32_of(v0),
            mu: f32_of(mu_s),
            lambda: f32_of(lambda_s),
            alpha: f32_of(alpha),
        };
        let f = deformation(kind, 5000 + 3 * n);
        let shift = noise3(7000 + n);
        let p = rest.map(|x| f32_round(f * x + shift));
        let d: [DVec3; 4] =
            std::array::from_fn(|k| f32_round(noise3(9000 + 4 * n + k as u64) * scale * 0.01));
        // Half the later linearisations move within the kept stiffness's reach, half beyond.
        let far = if n % 2 == 0 { 1e-4 } else { 0.2 };
        let q: [DVec3; 4] = std::array::from_fn(|k| {
            f32_round(p[k] + noise3(11000 + 4 * n + k as u64) * scale * far)
        });
        out.push(Case { tet, p, d, q });
    }
    out
}

fn vec4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

fn pack(case: &Case) -> [[f32; 4]; IN] {
    let t = &case.tet;
    let g = |k: usize| DVec3::from_array(t.shape[k]);
    let mut out = [[0.0f32; 4]; IN];
    out[0] = vec4(g(0), t.volume);
    out[1] = vec4(g(1), t.mu);
    out[2] = vec4(g(2), t.lambda);
    out[3] = [t.alpha as f32, 0.0, 0.0, 0.0];
    for k in 0..4 {
        out[4 + k] = vec4(case.p[k], 0.0);
        out[8 + k] = vec4(case.d[k], 0.0);
        out[12 + k] = vec4(case.q[k], 0.0);
    }
    out
}

/// Runs the twin check on `cases` with the validation layer on; its results per case.
fn on_gpu(cases: &[[[f32; 4]; IN]]) -> Vec<[[f32; 4]; OUT]> {
    let ctx = twin::context();
    let bytes = (cases.len() * OUT * 16) as u64;
    let input = Buffer::with_data(&ctx, "twin cases", bytemuck::cast_slice(cases)).unwrap();
    let results = Buffer::device(&ctx, "twin results", bytes).unwrap();
    let readback = Buffer::readback(&ctx, "twin readback", bytes).unwrap();
    let binding = Kernel::binding_layout(&ctx, "stiffness twin", &[0, 1]).unwrap();
    binding.write(&[(0, &input), (1, &results)]);
    let key = tetrasim::shaders::file::TWINS_STIFFNESS_COMP;
    let kernel = Kernel::new(&ctx, "stiffness twin", key, &binding, 64).unwrap();
    let push = PushConstants {
        node_count: cases.len() as u32,
        ..PushConstants::zeroed()
    };
    one_shot(&ctx, |cmd| {
        kernel.record(cmd, &push, cases.len() as u32);
        barrier(
            &ctx,
            cmd,
            &[&results],
            Access::COMPUTE,
            Access::TRANSFER_READ,
        );
        twin::copy(&ctx, cmd, &results, &readback, [0, 0], bytes);
        twin::to_host(&ctx, cmd, &readback);
    })
    .unwrap();
    let floats = twin::floats(&ctx, &readback);
    bytemuck::cast_slice::<f32, [[f32; 4]; OUT]>(&floats).to_vec()
}

/// `mu_s (1 - s)` at `F` (columns `f`), `s = 1 / (I_C + 1)`: the twists' bound's numerator.
fn lin_shear(t: &ElasticTet<f64>, f: &[DVec3; 3]) -> f64 {
    let ic = f.iter().map(|c| c.length_squared()).sum::<f64>();
    t.mu * (1.0 - 1.0 / (ic + 1.0))
}

fn xyz(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0].into(), v[1].into(), v[2].into())
}

#[test]
fn the_gpu_stiffness_equals_its_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let cases = cases();
    let gpu = on_gpu(&cases.iter().map(pack).collect::<Vec<_>>());
    let (mut projected, mut scaled, mut kept, mut retaken) = (0, 0, 0, 0);
    let mut worst = 0.0f64;
    for (n, (case, out)) in cases.iter().zip(&gpu).enumerate() {
        let t = &case.tet;
        let lin = elastic_linearise(t, case.p);
        let (product, strain) = elastic_product_strain(t, &lin, case.d);
        let later = elastic_relinearise(t, case.q, &lin);
        let (later_product, _) = elastic_product_strain(t, &later, case.d);
        // The scale of each compared quantity: the stiffness's magnitude times the moves.
        let stiffness =
            t.volume * (t.mu + t.lambda) * t.shape.iter().flatten().map(|g| g * g).sum::<f64>();
        let moves = case.d.iter().map(|d| d.length()).fold(0.0, f64::max);
        let f_scale = 1.0
            + case
                .p
                .iter()
                .map(|p| (*p - case.p[0]).length())
                .fold(0.0, f64::max)
                * t.shape
                    .iter()
                    .flatten()
                    .map(|g| g.abs())
                    .fold(0.0, f64::max);
        let force = stiffness * moves * f_scale * f_scale;
        let check = |what: &str, got: f64, want: f64, scale: f64| {
            let error = (got - want).abs() / scale;
            assert!(
                error <= 1e-5,
                "case {n}: {what} {got:e} on the GPU, {want:e} by definition (error {error:e} of {scale:e})"
            );
            error
        };
        for k in 0..4 {
            for (c, (got, want)) in [
                (xyz(out[k]), product[k]),
                (xyz(out[5 + k]), later_product[k]),
            ]
            .into_iter()
            .enumerate()
            {
                for axis in 0..3 {
                    let what = ["product", "later product"][c];
                    worst = worst.max(check(what, got[axis], want[axis], force));
                }
            }
        }
        let energy_scale = t.volume * (t.mu + t.lambda) * f_scale.powi(4);
        let g_largest = t
            .shape
            .iter()
            .flatten()
            .map(|g| g.abs())
            .fold(0.0, f64::max);
        check(
            "energy",
            out[4][1].into(),
            elastic_energy(t, case.p),
            energy_scale,
        );
        check("strain", out[4][0].into(), strain, 4.0 * moves * g_largest);
        check(
            "energy at q",
            out[9][0].into(),
            elastic_energy(t, case.q),
            energy_scale,
        );
        let term_scale = t.volume * t.lambda * f_scale.powi(3);
        check(
            "volume term",
            out[4][2].into(),
            lin.volume_factor(),
            term_scale,
        );
        check(
            "later volume term",
            out[4][3].into(),
            later.volume_factor(),
            term_scale,
        );
        // Which cases exercise what: the projection (the term scaled back from its raw
        // value), a kept stiffness and one taken anew.
        let f = |p: &[DVec3; 4]| {
            let e = [p[1] - p[0], p[2] - p[0], p[3] - p[0]];
            let g = t.shape;
            [0, 1, 2].map(|k| e[0] * g[0][k] + e[1] * g[1][k] + e[2] * g[2][k])
        };
        let fp = f(&case.p);
        let raw = t.volume * t.lambda * (fp[0].dot(fp[1].cross(fp[2])) - t.alpha);
        if (lin.volume_factor() - raw).abs() > 1e-3 * raw.abs() {
            projected += 1;
        }
        // The scaling block's share (beyond the twists' bound): the term below that bound.
        let sigma = singular_values(fp);
        let bound = lin_shear(t, &fp) / sigma.iter().fold(0.0f64, |m, s| m.max(s.abs()));
        if lin.volume_factor().abs() < (1.0 - 1e-3) * (raw.abs().min(t.volume * bound)) {
            scaled += 1;
        }
        let fq = f(&case.q);
        let moved = (0..3)
            .map(|k| (fq[k] - fp[k]).length_squared())
            .sum::<f64>()
            .sqrt();
        if moved <= 0.5 * KEPT_STIFFNESS_STRAIN {
            kept += 1;
        } else if moved > 2.0 * KEPT_STIFFNESS_STRAIN {
            retaken += 1;
        }
    }
    println!(
        "{} cases: worst product error {worst:.2e} of its scale; {projected} with the volume term projected ({scaled} by the scaling block), {kept} kept, {retaken} retaken",
        cases.len()
    );
    assert!(cases.len() >= 100, "{} cases", cases.len());
    assert!(
        projected >= 20,
        "only {projected} cases project the volume term"
    );
    assert!(
        kept >= 20 && retaken >= 20,
        "kept {kept}, retaken {retaken}"
    );
}
