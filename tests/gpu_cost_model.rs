//! The cost model that `tetrasim plan` prints ("predicted GPU time per frame on NVIDIA
//! H200") agrees within 30 % with the frames measured on an H200
//! (`docs/data/gpu-nvidia-h200/`, made by `scripts/gpu-report.sh` on 2026-11-26): the default
//! solver, Jacobi and Chebyshev with the global constraint on bunny20k and horse86m, the
//! real-size horse with implicit springs, and (measured after the fit, in the third session's
//! call: `2026-11-26-fused/`) the default, 4 and 2 colour groups again; Chebyshev from the
//! build with the gather's lanes (`2026-11-27-lanes/`; the 2-group rows were measured before
//! them, 0.383 / 0.653 ms, and the lanes' build ran 0.361 / 0.561, predicted 0.374 / 0.581).
//! And Anderson (m = 5, with 8 and 16 groups) and 4 inversion sweeps, measured after the
//! fit (`2026-11-27-stiff/`): predicted 6 to 24 % slow.
//! So a change to the step can be judged where no GPU is lent. (`--workgroup-size 1024` on the horse is outside it: predicted 63 % too slow, the
//! model counts a 1024-wide workgroup's gathers as serial on its multiprocessor.)
//!
//! Needs `../shared/meshes` (the scans, meshed here as the bundle meshed them); without it
//! the test fails under `CI=true`.

#[path = "common/prep.rs"]
mod prep_fixtures;

use std::path::{Path, PathBuf};

use prep_fixtures::scan;
use tetrasim::backend::vulkan::plan::{gpu_profile, EnginePlan};
use tetrasim::params::{MassMode, Method, Solver, SpringKind};
use tetrasim::prep::{prep_file, PrepOptions};
use tetrasim::problem::Problem;
use tetrasim::{ModelBuilder, SimParams, TetMesh};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/data/gpu-nvidia-h200")
}

/// The measured ms per frame of `mesh` in a bench JSON of `data()`, with its node and tet
/// counts.
fn measured(file: &str, mesh: &str) -> (f64, usize, usize) {
    let text = std::fs::read_to_string(data().join(file)).unwrap();
    let records: serde_json::Value = serde_json::from_str(&text).unwrap();
    let record = records
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["mesh"].as_str().is_some_and(|m| m.ends_with(mesh)))
        .unwrap_or_else(|| panic!("{file} has no record of {mesh}"));
    let number = |key: &str| record[key].as_f64().unwrap();
    (
        number("ms_per_frame"),
        number("nodes") as usize,
        number("tets") as usize,
    )
}

fn mesh(name: &str, options: &PrepOptions) -> Option<TetMesh> {
    let path = scan(name)?;
    Some(prep_file(&path, options, &mut |_| {}).unwrap().mesh)
}

/// Predicted ms per frame on the H200 for `mesh` under `params` (the plan `tetrasim plan`
/// makes: the device's default workgroup size of 1024, sized per pass).
fn predicted(mesh: &TetMesh, params: &SimParams) -> f64 {
    let model = ModelBuilder::new(mesh).mass(params.mass).build().unwrap();
    let problem = Problem::new(&model, params).unwrap();
    let plan = EnginePlan::of_problem(&problem, 1024, true)
        .unwrap()
        .size_workgroups();
    gpu_profile("NVIDIA H200").unwrap().frame_ms(&plan)
}

fn check(label: &str, predicted: f64, measured: f64, failures: &mut Vec<String>) {
    let ratio = predicted / measured;
    println!("{label}: predicted {predicted:.3} ms, measured {measured:.3} ms ({ratio:.2}x)");
    if !(0.7..=1.3).contains(&ratio) {
        failures.push(format!(
            "{label}: predicted {predicted:.3} ms against {measured:.3} measured"
        ));
    }
}

#[test]
fn the_h200_cost_model_predicts_the_measured_frames_within_30_percent() {
    let bunny = mesh(
        "bun_zipper.ply",
        &PrepOptions {
            target_tets: Some(20_000),
            ..PrepOptions::default()
        },
    );
    let horse = mesh(
        "horse.ply",
        &PrepOptions {
            quality: None,
            preserve_surface: true,
            ..PrepOptions::default()
        },
    );
    let (Some(bunny), Some(horse)) = (bunny, horse) else {
        return;
    };
    // The first call's files, then the third session's (2026-11-26-fused/: fewer groups,
    // each unfused, as the engine runs them).
    let third = "2026-11-26-fused/bench_new_gauss-seidel";
    let stiff = "2026-11-27-stiff/stiff_bench_gauss-seidel";
    let solvers = [
        (
            "bench_new_gauss-seidel-8-global",
            Solver::GaussSeidel,
            8,
            None,
            0,
            0,
        ),
        ("bench_new_jacobi", Solver::Jacobi, 8, None, 0, 0),
        (
            "2026-11-27-lanes/bench_new_chebyshev-global",
            Solver::Chebyshev,
            8,
            Some(true),
            0,
            0,
        ),
        (
            &format!("{third}-8-global_fuse-off"),
            Solver::GaussSeidel,
            8,
            None,
            0,
            0,
        ),
        (
            &format!("{third}-4-global_fuse-off"),
            Solver::GaussSeidel,
            4,
            None,
            0,
            0,
        ),
        (
            &format!("{third}-2-global_fuse-off"),
            Solver::GaussSeidel,
            2,
            None,
            0,
            0,
        ),
        // Anderson (m = 5), 16 groups with it, and 4 inversion sweeps (2026-11-27-stiff/).
        (
            &format!("{stiff}-8-global-anderson5"),
            Solver::GaussSeidel,
            8,
            None,
            5,
            0,
        ),
        (
            &format!("{stiff}-16-global-anderson5"),
            Solver::GaussSeidel,
            16,
            None,
            5,
            0,
        ),
        (
            &format!("{stiff}-8-global-inversion4"),
            Solver::GaussSeidel,
            8,
            None,
            0,
            4,
        ),
    ];
    let mut failures = Vec::new();
    for (name, mesh) in [("bunny20k", &bunny), ("horse86m", &horse)] {
        for &(file, solver, groups, global_volume, anderson, inversion_sweeps) in &solvers {
            let (ms, nodes, tets) = measured(&format!("{file}.json"), name);
            assert_eq!(
                (mesh.nodes.len(), mesh.tets.len()),
                (nodes, tets),
                "{name} meshed here differs from the measured one"
            );
            let params = SimParams {
                method: Method::Volume,
                solver,
                groups,
                global_volume,
                anderson,
                inversion_sweeps,
                ..SimParams::default()
            };
            check(
                &format!("{name} {file}"),
                predicted(mesh, &params),
                ms,
                &mut failures,
            );
        }
    }
    // The real-size horse with implicit springs: `run`'s table, column ms/frame.
    let text = std::fs::read_to_string(data().join("implicit_horse_new.txt")).unwrap();
    let row = text
        .lines()
        .find(|l| l.starts_with("volume "))
        .expect("implicit_horse_new.txt has the volume row");
    let ms: f64 = row.split_whitespace().nth(7).unwrap().parse().unwrap();
    let params = SimParams {
        method: Method::Volume,
        springs: SpringKind::Implicit,
        mass: MassMode::Density { density: 1050.0 },
        ..SimParams::default()
    };
    check(
        "horse86m, implicit springs",
        predicted(&horse, &params),
        ms,
        &mut failures,
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
