//! A run that blows up stops cleanly: distance constraints summed at omega = 1 by the Jacobi
//! solver on a box (physics.md: it diverges within a few frames; Gauss-Seidel does not) comes back as a record with `diverged: true`,
//! the frames before the blow-up, finite summaries, and JSON without NaN; the backend itself
//! reports where it happened.

mod common;

use common::{bare_params, box_mesh, model_in_place, seed_model, single_tet};
use tetrasim::backend::cpu::ReferenceBackend;
use tetrasim::backend::Backend;
use tetrasim::params::{ConstraintCombine, Method, Solver};
use tetrasim::{Error, SimParams};
use tetrasim_cli::runner::{run, RunOptions};

fn summed(method: Method) -> SimParams {
    SimParams {
        method,
        combine: ConstraintCombine::Sum,
        solver: Solver::Jacobi,
        ..SimParams::default()
    }
}

#[test]
fn diverging_run_is_recorded_not_fatal() {
    let model = seed_model(&box_mesh([3, 3, 3]));
    for backend in ["cpu-ref", "cpu"] {
        let options = RunOptions {
            backend: backend.into(),
            frames: 400,
            mesh_label: "box".into(),
            progress: false,
            output: None,
            gpu: Default::default(),
            checkpoint: Default::default(),
        };
        let record = run(&model, &summed(Method::Distance), &options).unwrap();
        assert!(
            record.diverged,
            "{backend}: plain summation at omega 1 should diverge"
        );
        assert!(record.frames_run < 400 && record.volume_pct.len() == record.frames_run as usize);
        assert!(
            record
                .divergence
                .as_deref()
                .is_some_and(|d| d.contains("distance")),
            "{:?}",
            record.divergence
        );
        assert!(record.min_volume_pct.is_finite() && record.avg_volume_pct.is_finite());
        let json = serde_json::to_string(&record).unwrap();
        assert!(!json.contains("NaN") && !json.contains("inf"), "{json}");
    }
}

#[test]
fn backend_names_the_frame_of_the_blow_up() {
    let model = seed_model(&box_mesh([3, 3, 3]));
    let mut backend = ReferenceBackend::new(&model, &summed(Method::Distance)).unwrap();
    let mut frames_ok = 0;
    let err = loop {
        match backend.step_frame() {
            Ok(()) => frames_ok += 1,
            Err(e) => break e,
        }
        assert!(frames_ok < 400, "no divergence in 400 frames");
    };
    let Error::Diverged(d) = err else {
        panic!("expected a divergence, got {err}")
    };
    assert_eq!(d.frame, frames_ok);
    assert_eq!(d.method, "distance");
    assert!(d.node.is_some_and(|n| (n as usize) < model.node_count()));
}

/// A tet whose apex flies through its base at 2 m/s, nothing holding it: no node is fast
/// or non-finite, but the body is inside out from about frame 550; the run stops there,
/// named, on every CPU backend (the frame driver checks each sampled frame's volume).
#[test]
fn a_body_turned_inside_out_stops_the_run() {
    let mut model = model_in_place(&single_tet());
    model.velocities[3] = glam::DVec3::new(0.0, 0.0, -2.0);
    let params = SimParams {
        method: Method::Mss,
        ..bare_params()
    };
    for backend in ["cpu-ref", "cpu"] {
        let options = RunOptions {
            backend: backend.into(),
            frames: 1000,
            mesh_label: "tet".into(),
            progress: false,
            output: None,
            gpu: Default::default(),
            checkpoint: Default::default(),
        };
        let record = run(&model, &params, &options).unwrap();
        assert!(record.diverged, "{backend}: an inside-out body is flagged");
        let cause = record.divergence.as_deref().unwrap_or_default();
        assert!(cause.contains("inside out"), "{backend}: {cause}");
        assert!(
            (500..600).contains(&record.frames_run),
            "{backend}: stopped after {} frames",
            record.frames_run
        );
        assert!(record.volume_pct.iter().all(|&v| v > 0.0));
    }
}
