//! A run that blows up stops cleanly: distance constraints summed at omega = 1 by the Jacobi
//! solver on a box (physics.md: it diverges within a few frames; Gauss-Seidel does not) comes back as a record with `diverged: true`,
//! the frames before the blow-up, finite summaries, and JSON without NaN; the backend itself
//! reports where it happened.

mod common;

use common::{box_mesh, seed_model};
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
