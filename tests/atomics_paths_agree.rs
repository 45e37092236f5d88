//! The two float-atomic paths (`atomicAdd` on float and the integer CAS loop) give the same
//! simulation: forcing `cas` on a device that supports `ext` really runs the CAS shaders,
//! and positions agree up to the float rounding of a different summation order.

mod gpu_support;

use tetrasim::backend::vulkan::{AtomicsMode, EngineOptions};
use tetrasim::gpu::AtomicsPath;
use tetrasim::params::{Method, SimParams, Solver, SpringKind};
use tetrasim::Backend;

/// Largest position difference allowed between the paths after the run, as a fraction of
/// the bounding-box diagonal. Observed on lavapipe with 32-wide groups: up to 1.2e-7; the
/// atomics only change the order of f32 additions, whose rounding the dynamics carry along.
const TOLERANCE: f64 = 1e-5;

#[test]
fn ext_and_cas_paths_agree_for_every_scatter_method() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = gpu_support::box_model([6, 4, 4], 0.1);
    let diag = model.bounds_diagonal();
    // The default solver's methods, and Jacobi sweeps of implicit springs and volumes (the
    // spring_constraint and volume passes on the atomic path).
    let cases = [
        (Method::Mss, SpringKind::Explicit, Solver::GaussSeidel),
        (Method::Distance, SpringKind::Explicit, Solver::GaussSeidel),
        (Method::Volume, SpringKind::Explicit, Solver::GaussSeidel),
        (Method::Volume, SpringKind::Implicit, Solver::Jacobi),
    ];
    for (method, springs, solver) in cases {
        let run = |atomics| {
            let params = SimParams {
                method,
                springs,
                solver,
                ..SimParams::default()
            };
            // Small workgroups: many run at once, so the atomics really contend.
            let options = EngineOptions {
                workgroup_size: Some(32),
                atomics,
                ..EngineOptions::default()
            };
            let mut gpu = gpu_support::validated_with(&model, &params, options);
            for _ in 0..150 {
                gpu.step_frame().unwrap();
            }
            let state = gpu.state().unwrap();
            gpu_support::assert_no_validation_messages(&gpu);
            (gpu.atomics(), gpu.device().float_atomic_add, state)
        };
        let (cas_path, has_ext, cas) = run(AtomicsMode::Cas);
        assert_eq!(
            cas_path,
            AtomicsPath::Cas,
            "forcing cas must run the CAS shaders"
        );
        if !has_ext {
            println!("device lacks float atomics: only the CAS path is checked");
            continue;
        }
        let (ext_path, _, ext) = run(AtomicsMode::Ext);
        assert_eq!(ext_path, AtomicsPath::Ext);
        let worst = cas
            .positions
            .iter()
            .zip(&ext.positions)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        println!(
            "{method} ({springs} springs, {solver}): largest ext/cas difference {:.3e} of the diagonal",
            worst / diag
        );
        assert!(
            worst <= TOLERANCE * diag,
            "{method}: ext and cas differ by {worst} m (diagonal {diag} m)"
        );
        // The run must have moved: the nodes fell and hit the floor.
        let moved = model
            .positions
            .iter()
            .zip(&cas.positions)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(moved > 0.05, "{method}: nodes moved only {moved} m");
    }
}
