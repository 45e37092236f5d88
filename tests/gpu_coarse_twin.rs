//! The finite elements' coarse level on the GPU (passes `elastic_coarse_factor`, one
//! workgroup, `elastic_coarse_inverse`, a column per invocation, and `elastic_coarse_solve`,
//! the inverse's product, a row per invocation; f32) equals its definition,
//! `CoarseSpace::assemble` and `CoarseSpace::solve` in f64, on the coarse matrix of a bent
//! block of 4225 nodes at the largest coarse level (`MOST_AGGREGATES`, 64 aggregates, 384
//! unknowns), with the factor's workgroups of 128 and 256 invocations (the fewest and the most
//! the engine gives it, `coarse_factor_workgroup`): within
//! 1e-4 of the correction's size at the default step on rubber, within 1e-2 for a material of
//! 1 GPa at ten times the step, where the stiffness shapes the matrix (what an f32 factor of
//! it allows; the figures are printed). Before the factor and the inverse summed eight terms
//! per loop iteration (glsl/common/coarse_dot.glsl) this failed on lavapipe, which ends an
//! invocation after 65535 loop iterations: at 240 unknowns, the size it was written for,
//! their columns stayed under that; at 384 the factor left out the columns from 332 on (163
//! on with a workgroup of 64) and the solve was off by over a thousand times the correction. The
//! second brick of `vulkan`'s finite elements (docs/GPU.md, "Finite elements on the GPU").

mod common;
mod gpu_support;

use bytemuck::Zeroable;
use common::{material_params, unplaced};
use glam::DVec3;
use gpu_support::twin;
use tetrasim::backend::vulkan::plan::coarse_factor_workgroup;
use tetrasim::gpu::commands::{barrier, one_shot, Access};
use tetrasim::gpu::layout::{binding, PushConstants};
use tetrasim::gpu::{Buffer, Kernel};
use tetrasim::mesh::grid::box_tets;
use tetrasim::params::Method;
use tetrasim::physics::{elastic_linearise, MOST_AGGREGATES};
use tetrasim::problem::Problem;
use tetrasim::schedule::family::ElasticNodes;
use tetrasim::shaders::file;
use tetrasim::{ModelBuilder, SimParams};

/// The coarse matrix's columns (column-major, `n` x `n`) of a 1.2 m x 0.6 m x 0.6 m block of
/// rubber (E 1 MPa, nu 0.45) bent to a sag, and the reference's solutions of `rhs`.
fn reference(e: f64, dt: f64, rhs: &[Vec<f64>]) -> (usize, Vec<f64>, Vec<Vec<f64>>) {
    let mesh = box_tets(DVec3::ZERO, 0.05, [24, 12, 12]);
    let model = ModelBuilder::new(&mesh)
        .placement(unplaced())
        .build()
        .unwrap();
    let params = SimParams {
        dt,
        ..material_params(Method::NeoHookean, e, 0.45, 1100.0)
    };
    let problem = Problem::new(&model, &params).unwrap();
    let nodes = ElasticNodes::<f64>::prepare(&problem);
    let at: Vec<DVec3> = (model.positions.iter())
        .map(|p| *p - DVec3::Y * (0.05 * p.x * p.x))
        .collect();
    let linear: Vec<_> = (model.tets.iter().zip(&nodes.tets))
        .map(|(tet, t)| elastic_linearise(t, tet.map(|k| at[k as usize])))
        .collect();
    let held = vec![DVec3::ZERO; at.len()];
    let mut coarse = nodes.coarse_space(&at);
    let n = coarse.unknowns();
    let mut columns = vec![0.0; n * n];
    for (a, block) in columns.chunks_mut(6 * n).enumerate() {
        let dt = params.dt;
        nodes.coarse_columns(&coarse, a, &model.tets, &at, &linear, &held, dt, block);
    }
    coarse.assemble(&columns);
    let solved = (rhs.iter())
        .map(|b| {
            let mut u = b[..n].to_vec();
            coarse.solve(&mut u);
            u
        })
        .collect();
    (n, columns, solved)
}

/// The GPU's solutions of `rhs` with the matrix `columns` factored there by a workgroup of
/// `lanes`, validation on.
fn on_gpu(n: usize, columns: &[f64], rhs: &[Vec<f64>], lanes: u32) -> Vec<Vec<f64>> {
    let ctx = twin::context();
    // The factor in place, its flags, then the inverse.
    let mut matrix: Vec<f32> = columns.iter().map(|&x| x as f32).collect();
    matrix.extend(std::iter::repeat_n(0.0f32, n + n * n));
    let vectors: Vec<f32> = rhs
        .iter()
        .flat_map(|b| b[..n].iter().map(|&x| x as f32))
        .collect();
    let coarse = Buffer::with_data(&ctx, "coarse matrix", bytemuck::cast_slice(&matrix)).unwrap();
    let bytes = 4 * n as u64;
    // The right-hand side, then the solution.
    let vector = Buffer::device(&ctx, "coarse vector", 2 * bytes).unwrap();
    let staged = Buffer::with_data(&ctx, "coarse rhs", bytemuck::cast_slice(&vectors)).unwrap();
    let total = bytes * rhs.len() as u64;
    let readback = Buffer::readback(&ctx, "coarse readback", total).unwrap();
    // The solve's state at its start (step 0, iteration 0: the passes' gates open).
    let state = Buffer::with_data(&ctx, "elastic state", &[0u8; 64]).unwrap();
    let numbers = [
        binding::COARSE_MATRIX,
        binding::COARSE_VECTOR,
        binding::ELASTIC_STATE,
    ];
    let layout = Kernel::binding_layout(&ctx, "coarse twin", &numbers).unwrap();
    layout.write(&[
        (numbers[0], &coarse),
        (numbers[1], &vector),
        (numbers[2], &state),
    ]);
    let constants = [n as u32];
    let kernel = |key: &str, lanes| {
        Kernel::with_constants(&ctx, key, key, &layout, lanes, &constants).unwrap()
    };
    let factor = kernel(file::PASSES_ELASTIC_COARSE_FACTOR_COMP, lanes);
    let inverse = kernel(file::PASSES_ELASTIC_COARSE_INVERSE_COMP, 64);
    let solve = kernel(file::PASSES_ELASTIC_COARSE_SOLVE_COMP, 64);
    let push = PushConstants::zeroed();
    one_shot(&ctx, |cmd| {
        factor.record(cmd, &push, lanes);
        barrier(&ctx, cmd, &[&coarse], Access::COMPUTE, Access::COMPUTE);
        inverse.record(cmd, &push, n as u32);
        barrier(&ctx, cmd, &[&coarse], Access::COMPUTE, Access::COMPUTE);
        for k in 0..rhs.len() as u64 {
            twin::copy(&ctx, cmd, &staged, &vector, [k * bytes, 0], bytes);
            barrier(
                &ctx,
                cmd,
                &[&vector],
                Access::TRANSFER_WRITE,
                Access::COMPUTE,
            );
            solve.record(cmd, &push, n as u32);
            barrier(
                &ctx,
                cmd,
                &[&vector],
                Access::COMPUTE,
                Access::TRANSFER_READ,
            );
            twin::copy(&ctx, cmd, &vector, &readback, [bytes, k * bytes], bytes);
            barrier(
                &ctx,
                cmd,
                &[&vector],
                Access::TRANSFER_READ,
                Access::TRANSFER_WRITE,
            );
        }
        twin::to_host(&ctx, cmd, &readback);
    })
    .unwrap();
    let out = twin::floats(&ctx, &readback);
    out.chunks(n)
        .map(|u| u.iter().map(|&x| x.into()).collect())
        .collect()
}

#[test]
fn the_gpu_coarse_solve_equals_its_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // Right-hand sides of several scales: a residual's restriction, and single modes.
    let unknowns = 6 * MOST_AGGREGATES;
    let mut rhs: Vec<Vec<f64>> = (0..4u64)
        .map(|s| {
            (0..unknowns)
                .map(|i| common::noise(1000 * s + i as u64) * 10f64.powi(s as i32 - 2))
                .collect()
        })
        .collect();
    rhs.push(
        (0..unknowns)
            .map(|i| if i == 3 { 1.0 } else { 0.0 })
            .collect(),
    );
    // The default step on rubber, and a stiff material at ten times the step, where the
    // stiffness rather than the mass shapes the coarse matrix.
    for (e, dt, tolerance) in [(1e6, 1e-3, 1e-4), (1e9, 1e-2, 1e-2)] {
        let (n, columns, want) = reference(e, dt, &rhs);
        assert_eq!(n, unknowns, "coarse unknowns");
        // The fewest and the most invocations the engine gives the factor.
        for lanes in [
            coarse_factor_workgroup(1),
            coarse_factor_workgroup(u32::MAX),
        ] {
            let got = on_gpu(n, &columns, &rhs, lanes);
            let mut worst = 0.0f64;
            for (k, (got, want)) in got.iter().zip(&want).enumerate() {
                let size = want.iter().map(|x| x * x).sum::<f64>().sqrt();
                let error = (got.iter().zip(want))
                    .map(|(g, w)| (g - w).powi(2))
                    .sum::<f64>()
                    .sqrt();
                assert!(
                    size > 0.0 && error <= tolerance * size,
                    "E {e:e}, dt {dt:e}, factor of {lanes}, rhs {k}: off by {error:e} of {size:e}"
                );
                worst = worst.max(error / size);
            }
            println!(
                "E {e:e} Pa, dt {dt:e} s, {n} unknowns, factor of {lanes}: \
                 worst relative error {worst:.2e}"
            );
        }
    }
}
