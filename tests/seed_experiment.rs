//! The paper's experiment (preset `seed`: fit to 1 m, dropped from 0.1 m onto the floor, 1 kg
//! per node, dt 1 ms, 10 iterations, ks 5000, kd 15, 400 frames) on a generated ball of a few
//! thousand tets and on the bundled TetGen sphere (`meshes/sphere`), through the shared frame
//! loop: plain springs lose clearly more volume than
//! both constraint methods, and the volume constraint averages at least the paper's 98.70 %.

mod common;

use common::ball_mesh;
use tetrasim::metrics::RunRecord;
use tetrasim::params::Method;
use tetrasim::sim::build_model;
use tetrasim_cli::preset::Preset;
use tetrasim_cli::runner::{run_methods, RunOptions};

fn seed_records(backend: &str) -> Vec<RunRecord> {
    seed_records_on(&ball_mesh(4.5), "ball(4.5)", backend)
}

fn seed_records_on(mesh: &tetrasim::TetMesh, label: &str, backend: &str) -> Vec<RunRecord> {
    let preset = Preset::seed();
    let model = build_model(mesh, &preset.params, preset.placement).unwrap();
    assert!(
        (1000..5000).contains(&model.tets.len()),
        "{} tets",
        model.tets.len()
    );
    let options = RunOptions {
        backend: backend.to_string(),
        frames: preset.frames,
        mesh_label: label.into(),
        progress: false,
        output: None,
        gpu: Default::default(),
        checkpoint: Default::default(),
    };
    let records = run_methods(
        &model,
        &preset.params,
        &[Method::Mss, Method::Distance, Method::Volume],
        &options,
    )
    .unwrap();
    print!("{}", tetrasim::metrics::table(&records, true));
    records
}

fn check(records: &[RunRecord]) {
    let [mss, distance, volume] = records else {
        panic!("three records expected")
    };
    for r in records {
        assert!(!r.diverged, "{} diverged: {:?}", r.method, r.divergence);
        assert_eq!(
            (r.frames_run, r.volume_pct.len()),
            (400, 400),
            "{}",
            r.method
        );
        assert!(r.ms_per_frame > 0.0 && r.ms_per_frame.is_finite());
    }
    assert!(
        mss.avg_volume_pct + 5.0 < distance.avg_volume_pct.min(volume.avg_volume_pct),
        "mss {:.2} % should lose clearly more than distance {:.2} % and volume {:.2} %",
        mss.avg_volume_pct,
        distance.avg_volume_pct,
        volume.avg_volume_pct
    );
    assert!(
        mss.min_volume_pct < distance.min_volume_pct && mss.min_volume_pct < volume.min_volume_pct
    );
    assert!(
        volume.avg_volume_pct >= 98.70,
        "volume averaged {:.2} %",
        volume.avg_volume_pct
    );
}

#[test]
fn seed_experiment_on_reference_backend() {
    check(&seed_records("cpu-ref"));
}

#[test]
fn seed_experiment_on_parallel_backend() {
    check(&seed_records("cpu"));
}

#[test]
fn seed_experiment_on_bundled_sphere() {
    let prefix = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere");
    let mesh = tetrasim::mesh::io::read_tetgen(&prefix).unwrap();
    check(&seed_records_on(&mesh, "meshes/sphere", "cpu"));
}
