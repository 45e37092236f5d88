//! The finite elements' Newton step on the GPU, pass by pass, equals its definition in f64
//! on a damped rubber block deformed and moving, a face of it pinned and a third of its
//! nodes held by a contact:
//! - the rows (`elastic_linearise` at iteration 0 and at a later one, `elastic_rows`) against
//!   `cpu-ref`'s
//!   linearisation (`elastic_linearise`, `elastic_relinearise`,
//!   `ElasticNodes::rate_corners` and `newton_row`): each node's residual, inverse diagonal block and contact stiffening,
//!   at a step's first linearisation and at a later one that keeps the stiffness of the tets
//!   that barely moved;
//! - ten conjugate-gradient iterations in the engine's order (`elastic_begin`,
//!   `elastic_product`, `elastic_curvature`, `elastic_alpha`, `elastic_potential`,
//!   `elastic_backtrack`, `elastic`, the preconditioner's
//!   `elastic_coarse_modes`, `elastic_coarse_factor`, `elastic_restrict`,
//!   `elastic_coarse_solve` and `elastic_prolong`, `elastic_direction`) against `cpu-ref`'s
//!   `conjugate_gradients` written out with the same functions (its product, increments,
//!   contact cut, backtracking on the f64 potential, floor check and two-level
//!   preconditioner, the coarse matrix assembled by the reference), on the first
//!   linearisation throughout: displacements, force increments, steps and the checked and
//!   relinearise flags;
//! - the start of a linearisation (`elastic_start`, with a floor) against `end_position`,
//!   `StepForces::elastic` and `collider::held_normal`;
//! - the coarse matrix's assembly (`elastic_coarse_modes`, `elastic_coarse_tets`,
//!   `elastic_coarse_nodes`, `elastic_coarse_gather`) against
//!   `ElasticNodes::coarse_columns`.
//!
//! Bricks of `vulkan`'s finite elements (docs/GPU.md, "Finite elements on the GPU").

mod common;
mod elastic_twin;
mod gpu_support;

use elastic_twin::*;
use glam::DVec3;
use gpu_support::twin;
use tetrasim::collider;
use tetrasim::gpu::commands::{barrier, one_shot, Access};
use tetrasim::gpu::layout::binding;
use tetrasim::gpu::Buffer;
use tetrasim::physics::{
    elastic_linearise, elastic_product_strain, elastic_relinearise, end_position, held_increment,
    ElasticLinear,
};
use tetrasim::schedule::family::backtrack;
use tetrasim::shaders::file;

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
    let rows = gpu.pass(file::PASSES_ELASTIC_ROWS_COMP, &[]);
    one_shot(&gpu.ctx, |cmd| {
        // The first linearisation at iteration 0; the later one at iteration 1 after a step
        // beyond the trust (RELINEARISE).
        for phase in 0..2u32 {
            if phase == 1 {
                gpu.set_word(cmd, binding::ELASTIC_STATE, 7, 1);
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
            gpu.dispatch_at(cmd, &linearise, t, phase);
            gpu.dispatch_at(cmd, &rows, n, phase);
            gpu.snapshot(cmd, &readback, u64::from(phase) * size);
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

/// One conjugate-gradient iteration of the reference: the nodes' displacements and force
/// increments after it, its step, whether it was checked against the potential and whether
/// the next iteration relinearises.
struct Iteration {
    dx: Vec<DVec3>,
    sum: Vec<DVec3>,
    alpha: f64,
    checked: bool,
    relinearise: bool,
}

/// The reference's conjugate-gradient iterations at the first linearisation
/// (block-Jacobi preconditioner; backtracking and the floor check as cpu-ref's
/// `conjugate_gradients`, its `potential` in f64), each saying whether the next would
/// relinearise, all kept on the first linearisation (as the passes here are run).
fn reference_iterations(s: &Scene) -> Vec<Iteration> {
    let (model, nodes, dt) = (&s.model, &s.nodes, s.params.dt);
    let at = &s.first;
    let linear: Vec<ElasticLinear<DVec3>> = (model.tets.iter().zip(&nodes.tets))
        .map(|(tet, e)| elastic_linearise(e, tet.map(|k| at[k as usize])))
        .collect();
    let rows = reference_rows(s, at, &linear);
    let n = model.node_count();
    let w = &model.inv_mass;
    let y: Vec<DVec3> = (0..n)
        .map(|i| at[i] - s.phi[i] * (w[i] * dt * dt))
        .collect();
    let held: Vec<DVec3> = rows.iter().map(|row| row.2).collect();
    let potential = |moves: &[DVec3]| nodes.potential(&model.tets, w, dt, at, moves, &y, &held);
    let (coarse, _) = coarse_level(s);
    let inverse: Vec<[f64; 6]> = rows.iter().map(|row| row.1).collect();
    let touching: Vec<bool> = rows.iter().map(|row| row.2 != DVec3::ZERO).collect();
    let precondition = |r: &[DVec3]| nodes.precondition(&coarse, at, r, &inverse, &touching);
    let mut r: Vec<DVec3> = rows.iter().map(|row| row.0).collect();
    let mut z = precondition(&r);
    let mut p = z.clone();
    let mut dx = vec![DVec3::ZERO; n];
    let dot = |a: &[DVec3], b: &[DVec3]| a.iter().zip(b).map(|(a, b)| a.dot(*b)).sum::<f64>();
    let mut rz = dot(&r, &z);
    let mut known = None;
    let mut out = Vec::new();
    for _ in 0..ITERATIONS {
        let (corners, strains): (Vec<[DVec3; 4]>, Vec<f64>) =
            (model.tets.iter().zip(&nodes.tets).zip(&linear))
                .map(|((tet, e), lin)| elastic_product_strain(e, lin, tet.map(|k| p[k as usize])))
                .unzip();
        let q: Vec<DVec3> = (0..n)
            .map(|i| {
                let corner = |item: usize| corners[item / 4][item % 4];
                nodes.product(i, w[i], dt, p[i], rows[i].2, corner)
            })
            .collect();
        let curvature = dot(&p, &q);
        let strain = strains.into_iter().fold(0.0, f64::max);
        let stepped = backtrack(rz / curvature, strain, curvature, known, |a| {
            let moves: Vec<DVec3> = (0..n).map(|k| dx[k] + p[k] * a).collect();
            potential(&moves)
        });
        known = stepped.potential;
        let mut relinearise = stepped.relinearise;
        let alpha = stepped.alpha.expect("a step that lowers the potential");
        if stepped.checked && !relinearise {
            relinearise = (0..n).any(|k| {
                let end = at[k] + dx[k] + p[k] * alpha;
                w[k] > 0.0 && rows[k].2 == DVec3::ZERO && end.y < 0.0
            });
        }
        let sum: Vec<DVec3> = (0..n)
            .map(|i| {
                let (h, d) = (rows[i].2, p[i] * alpha);
                dx[i] += d;
                r[i] -= q[i] * alpha;
                held_increment(nodes.increment(i, dt, h, p[i], alpha), h, d, s.pushed[i])
            })
            .collect();
        z = precondition(&r);
        let next = dot(&r, &z);
        let beta = next / rz;
        rz = next;
        p = (0..n).map(|i| z[i] + p[i] * beta).collect();
        out.push(Iteration {
            dx: dx.clone(),
            sum,
            alpha,
            checked: stepped.checked,
            relinearise,
        });
    }
    out
}

#[test]
fn the_gpu_conjugate_gradients_equal_their_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // Steps beyond the trust (halved, then relinearised: the jittered block's slivers), and
    // a smooth load's steps within it. Which checked steps keep the linearisation is
    // `the_gpu_backtracking_decides_as_its_definition`'s.
    let mut checked = 0;
    for (jitter, lift) in [(2e-3, 0.0), (8e-4, 0.01)] {
        let name = format!("jitter {jitter} m, lift {lift} m");
        checked += compare_iterations(&name, scene_jittered(jitter, lift));
    }
    for load in [1.0, 20.0] {
        checked += compare_iterations(&format!("load {load} N"), scene_loaded(load));
    }
    assert!(
        checked >= 4,
        "{checked} steps checked against the potential"
    );
}

/// The GPU's conjugate-gradient iterations on scene `s` (`name`) against the
/// reference's: the steps checked against the potential.
fn compare_iterations(name: &str, s: Scene) -> usize {
    let want = reference_iterations(&s);
    let gpu = Gpu::new(&s);
    let (n, t) = (s.model.node_count(), s.model.tets.len());
    let partials = n.div_ceil(WORKGROUP as usize) as u32;
    let widest = n.max(t);
    let potential_partials = widest.div_ceil(WORKGROUP as usize) as u32;
    let size = gpu.node_bytes + 64;
    let readback = Buffer::readback(&gpu.ctx, "readback", want.len() as u64 * size).unwrap();
    let aggregates = s.nodes.aggregates.len();
    let (unknowns, groups) = ((6 * aggregates) as u32, aggregates * WORKGROUP as usize);
    let coarse = [0, aggregates as u32];
    // The first linearisation's rows and the coarse level's modes and factor; then, as
    // the engine runs an iteration, the preconditioner (restriction per aggregate, the
    // coarse solve, the prolongation with the block-Jacobi term), r . z and beta (0 at the
    // linearisation), the direction, and the step.
    let passes = [
        (gpu.pass(file::PASSES_ELASTIC_LINEARISE_COMP, &[]), t),
        (gpu.pass(file::PASSES_ELASTIC_ROWS_COMP, &[]), n),
        (
            gpu.pass(file::PASSES_ELASTIC_COARSE_MODES_COMP, &coarse),
            groups,
        ),
        (
            gpu.pass(file::PASSES_ELASTIC_COARSE_FACTOR_COMP, &[unknowns]),
            1,
        ),
        (
            gpu.pass(file::PASSES_ELASTIC_COARSE_INVERSE_COMP, &[unknowns]),
            unknowns as usize,
        ),
    ];
    let iteration = [
        (
            gpu.pass(file::PASSES_ELASTIC_RESTRICT_COMP, &coarse),
            groups,
        ),
        (
            gpu.pass(file::PASSES_ELASTIC_COARSE_SOLVE_COMP, &[unknowns]),
            unknowns as usize,
        ),
        (gpu.pass(file::PASSES_ELASTIC_PROLONG_COMP, &coarse), n),
        (gpu.pass(file::PASSES_ELASTIC_BEGIN_COMP, &[partials]), 1),
        (gpu.pass(file::PASSES_ELASTIC_DIRECTION_COMP, &[]), n),
        (gpu.pass(file::PASSES_ELASTIC_PRODUCT_COMP, &[]), t),
        (gpu.pass(file::PASSES_ELASTIC_CURVATURE_COMP, &[]), n),
        (gpu.pass(file::PASSES_ELASTIC_ALPHA_COMP, &[partials]), 1),
        (gpu.pass(file::PASSES_ELASTIC_POTENTIAL_COMP, &[]), widest),
        (
            gpu.pass(file::PASSES_ELASTIC_BACKTRACK_COMP, &[potential_partials]),
            1,
        ),
        (gpu.pass(file::PASSES_ELASTIC_COMP, &[]), n),
    ];
    one_shot(&gpu.ctx, |cmd| {
        for (pass, elements) in &passes {
            gpu.dispatch(cmd, pass, *elements);
        }
        for k in 0..want.len() {
            for (pass, elements) in &iteration {
                gpu.dispatch_at(cmd, pass, *elements, k as u32);
            }
            gpu.snapshot(cmd, &readback, k as u64 * size);
            // The relinearisation flag read: the reference goes on with its linearisation.
            gpu.clear_word(cmd, binding::ELASTIC_STATE, 7);
        }
        twin::to_host(&gpu.ctx, cmd, &readback);
    })
    .unwrap();
    let floats = twin::floats(&gpu.ctx, &readback);
    let mut worst = 0.0f64;
    for (k, it) in want.iter().enumerate() {
        let (planes, state) = snapshot_of(&floats, n, k);
        let largest = |v: &[DVec3]| v.iter().map(|x| x.length()).fold(0.0, f64::max);
        let (dx_scale, sum_scale) = (largest(&it.dx), largest(&it.sum));
        let alpha = f64::from(state[ALPHA]);
        let mut off = (alpha - it.alpha).abs() / it.alpha.abs();
        for i in 0..n {
            off = off.max((xyz(planes[DX * n + i]) - it.dx[i]).length() / dx_scale);
            off = off.max((xyz(planes[SUM * n + i]) - it.sum[i]).length() / sum_scale);
        }
        assert!(
            off <= 1e-3,
            "iteration {k}: displacements, increments or alpha off by {off:e} of their size \
             (alpha {alpha} on the GPU, {} by definition)",
            it.alpha
        );
        let flags = state_flags(state);
        assert_eq!(
            flags,
            (it.checked, it.relinearise),
            "iteration {k}: checked, relinearise"
        );
        worst = worst.max(off);
    }
    let checked = want.iter().filter(|it| it.checked).count();
    println!(
        "{name}: {} iterations on {n} nodes ({aggregates} aggregates; {checked} checked \
         against the potential): within {worst:.2e} of the reference",
        want.len(),
    );
    checked
}

/// The state's CHECK and RELINEARISE flags.
fn state_flags(state: &[f32]) -> (bool, bool) {
    let word = |k: usize| state[k].to_bits() != 0;
    (word(6), word(7))
}

#[test]
fn the_gpu_start_of_a_linearisation_equals_its_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let s = scene();
    let (model, dt) = (&s.model, s.params.dt);
    let n = model.node_count();
    let gpu = Gpu::new(&s);
    let start = gpu.pass(file::PASSES_ELASTIC_START_COMP, &[]);
    let floats = gpu.run(&[(&start, n)], 1, |_| {});
    let (planes, _) = snapshot_of(&floats, n, 0);
    let (mut held, mut resting) = (0, 0);
    let mut worst = 0.0f64;
    for i in 0..n {
        let (f, floor) = s.force[i];
        let (x, v, w) = (model.positions[i], s.velocity[i], model.inv_mass[i]);
        let at = end_position(x, v, f, w, dt);
        let phi = f - s.params.gravity * model.mass[i] - DVec3::Y * floor;
        let y = at - phi * (w * dt * dt);
        let normal =
            collider::held_normal(Some(floor > 0.0), DVec3::ZERO, at, s.nodes.reach[i], &[]);
        // Relative to the value's size, at least 1 m or N.
        let close = |what: &str, got: [f32; 4], want: DVec3| {
            let off = (xyz(got) - want).length() / want.length().max(1.0);
            assert!(
                off <= 1e-6,
                "node {i}: {what} {:?} on the GPU, {want} by definition",
                got
            );
            off
        };
        worst = worst.max(close("end", planes[AT * n + i], at));
        worst = worst.max(close("inertial end", planes[Y * n + i], y));
        worst = worst.max(close("elastic force", planes[PHI * n + i], phi));
        assert_eq!(xyz(planes[NORMAL * n + i]), normal, "node {i}: held normal");
        assert_eq!(
            planes[NORMAL * n + i][3] > 0.0,
            floor > 0.0,
            "node {i}: touching"
        );
        held += usize::from(normal != DVec3::ZERO);
        resting += usize::from(normal != DVec3::ZERO && floor == 0.0);
    }
    println!("{n} nodes, {held} held by the floor ({resting} resting on it unpushed): within {worst:.1e} m or N");
    assert!(held >= 10 && resting >= 1, "{held} held, {resting} resting");
}

#[test]
fn the_gpu_coarse_matrix_equals_its_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let s = scene();
    let (_, want) = coarse_level(&s);
    let gpu = Gpu::new(&s);
    let (n, t) = (s.model.node_count(), s.model.tets.len());
    let aggregates = s.nodes.aggregates.len();
    let members: usize = s.nodes.aggregates.members.iter().map(Vec::len).sum();
    let unknowns = 6 * aggregates;
    let bytes = (4 * unknowns * unknowns) as u64;
    let readback = Buffer::readback(&gpu.ctx, "readback", bytes).unwrap();
    let coarse = [0, aggregates as u32];
    let groups = aggregates * WORKGROUP as usize;
    let passes = [
        (gpu.pass(file::PASSES_ELASTIC_LINEARISE_COMP, &[]), t),
        (gpu.pass(file::PASSES_ELASTIC_ROWS_COMP, &[]), n),
        (
            gpu.pass(file::PASSES_ELASTIC_COARSE_MODES_COMP, &coarse),
            groups,
        ),
        (gpu.pass(file::PASSES_ELASTIC_COARSE_TETS_COMP, &coarse), t),
        (
            gpu.pass(file::PASSES_ELASTIC_COARSE_NODES_COMP, &coarse),
            members,
        ),
        (
            gpu.pass(file::PASSES_ELASTIC_COARSE_GATHER_COMP, &coarse),
            aggregates * groups,
        ),
    ];
    one_shot(&gpu.ctx, |cmd| {
        for (pass, elements) in &passes {
            gpu.dispatch(cmd, pass, *elements);
        }
        let matrix = gpu.buffer(binding::COARSE_MATRIX);
        barrier(
            &gpu.ctx,
            cmd,
            &[matrix],
            Access::COMPUTE,
            Access::TRANSFER_READ,
        );
        twin::copy(&gpu.ctx, cmd, matrix, &readback, [0, 0], bytes);
        twin::to_host(&gpu.ctx, cmd, &readback);
    })
    .unwrap();
    let got = twin::floats(&gpu.ctx, &readback);
    let largest = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut worst = 0.0f64;
    for (e, (&g, &w)) in got.iter().zip(&want).enumerate() {
        let off = (f64::from(g) - w).abs() / largest;
        assert!(
            off <= 1e-5,
            "entry (row {}, column {}): {g} on the GPU, {w} by definition",
            e % unknowns,
            e / unknowns
        );
        worst = worst.max(off);
    }
    let coupled = (0..aggregates * aggregates)
        .filter(|&blk| {
            let (a, b) = (blk / aggregates, blk % aggregates);
            a != b && (0..36).any(|e| want[(6 * a + e / 6) * unknowns + 6 * b + e % 6] != 0.0)
        })
        .count();
    println!(
        "{unknowns} coarse unknowns ({coupled} off-diagonal blocks coupled): the GPU's matrix \
         within {worst:.1e} of its largest entry"
    );
    assert!(
        aggregates >= 2 && coupled >= 2,
        "{aggregates} aggregates, {coupled} coupled blocks"
    );
}
