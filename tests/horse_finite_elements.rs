//! The real-size horse of finite elements (issue 51's scene): the horse scan at its real
//! size (about 18 cm) meshed with its full surface (TetGen `-pY`: 24228 nodes, 85638 tets,
//! slivers included), soft tissue (E 0.1 MPa, nu 0.45, 1050 kg/m^3), dropped 0.1 m,
//! `neo-hookean` at its default settings on `cpu` for 300 frames (the impact is at frame
//! 143). The issue's bars: at most 2 % average local volume error, at most 1 % of the tets
//! inverted at the worst frame, and here the volume within 0.1 % of the rest volume on
//! average (the issue asks at least 99.9 %; a swelling fails too). Measured (docs/PHYSICS.md,
//! "The coarse level kept for ten steps"): 0.33 %, 0.43 %, 100.00 %. The volume's bar fails
//! with either of the changes it guards switched off (measured with the rest as now): with
//! every checked CG step starting a new Newton step ("Keeping the linearisation where the
//! model holds") 100.19 %, with the whole rigid-part correction on a body the floor holds
//! ("The correction's length") 100.46 %. Its cost (1.2 to 1.3 times the springs') is
//! measured beside the springs' in docs/PHYSICS.md, not here.
//!
//! The same drop runs on `vulkan` (lavapipe, the validation layer on, any message failing
//! it) against the same bars: measured 0.28 %, 0.40 %, 99.98 % (docs/GPU.md, "The horse on
//! `vulkan`"). Before the coarse factor and inverse kept within lavapipe's loop limit the
//! run diverged at frame 259, which the GPU tests' small scenes had not shown: their coarse
//! levels are a few aggregates, the horse's the most (64).
//!
//! Needs `../shared/meshes/horse.ply`; without it the test fails under `CI=true`.

mod gpu_support;
#[path = "common/prep.rs"]
mod prep_fixtures;

use prep_fixtures::scan;
use tetrasim::metrics::RunRecord;
use tetrasim::params::{MassMode, Method, Placement};
use tetrasim::prep::{prep_file, PrepOptions};
use tetrasim::problem::Problem;
use tetrasim::sim::Simulation;
use tetrasim::{Model, ModelBuilder, SimParams};
use tetrasim_cli::runner::{run, RunOptions};

const FRAMES: u32 = 300;

/// The horse dropped 0.1 m and its soft tissue, `neo-hookean` at its defaults (None without
/// the scan, which fails under `CI=true`).
fn horse_drop() -> Option<(Model, SimParams)> {
    let path = scan("horse.ply")?;
    let options = PrepOptions {
        quality: None,
        preserve_surface: true,
        ..PrepOptions::default()
    };
    let mesh = prep_file(&path, &options, &mut |_| {}).unwrap().mesh;
    let params = SimParams {
        method: Method::NeoHookean,
        youngs_modulus: Some(1e5),
        poisson_ratio: Some(0.45),
        mass: MassMode::Density { density: 1050.0 },
        ..SimParams::default()
    };
    let placement = Placement {
        fit_size: None,
        drop_height: Some(0.1),
    };
    let model = (ModelBuilder::new(&mesh).placement(placement))
        .material(&params)
        .build()
        .unwrap();
    assert!(model.tets.len() > 80_000, "{} tets", model.tets.len());
    Some((model, params))
}

/// The issue's bars for the horse on the run `r` of `model`.
fn assert_bars(model: &Model, r: &RunRecord) {
    print!(
        "{}",
        tetrasim::metrics::table(std::slice::from_ref(r), false)
    );
    assert!(!r.diverged, "{:?}", r.divergence);
    assert_eq!(r.frames_run, FRAMES);
    let inverted = 100.0 * f64::from(r.max_inverted_tets) / model.tets.len() as f64;
    assert!(
        r.avg_local_error_pct <= 2.0,
        "average local error {:.3} %",
        r.avg_local_error_pct
    );
    assert!(inverted <= 1.0, "{inverted:.3} % of the tets inverted");
    assert!(
        (r.avg_volume_pct - 100.0).abs() <= 0.1,
        "average volume {:.3} %",
        r.avg_volume_pct
    );
}

#[test]
fn the_real_size_horse_of_finite_elements_meets_the_issues_bars() {
    let Some((model, params)) = horse_drop() else {
        return;
    };
    let options = RunOptions {
        backend: "cpu".into(),
        frames: FRAMES,
        mesh_label: "horse (real size)".into(),
        progress: false,
        output: None,
        gpu: Default::default(),
        checkpoint: Default::default(),
    };
    assert_bars(&model, &run(&model, &params, &options).unwrap());
}

#[test]
fn the_real_size_horse_of_finite_elements_meets_the_issues_bars_on_vulkan() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let Some((model, params)) = horse_drop() else {
        return;
    };
    let mut gpu = gpu_support::validated(&model, &params);
    let problem = Problem::new(&model, &params).unwrap();
    let mut record = RunRecord::new(&problem, "horse (real size)", FRAMES, "vulkan");
    let mut sim = Simulation::new(&model, &params);
    sim.advance_frames(&mut gpu, FRAMES, &|_| true, &mut |_| {})
        .unwrap();
    sim.fill_record(&mut record);
    gpu_support::assert_no_validation_messages(&gpu);
    assert_bars(&model, &record);
}
