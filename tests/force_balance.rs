//! Internal forces sum to zero (Newton's third law holds per spring and per constraint), and
//! the two spring evaluation orders (`mss` spring-centric scatter, `mss-node` node-centric
//! gather) agree to rounding, per force and over a whole run.

mod common;

use common::{box_mesh, jittered_state, max_distance, model_in_place, run_frames, seed_model};
use glam::DVec3;
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::backend::Backend;
use tetrasim::params::{ConstraintCombine, Method};
use tetrasim::SimParams;

fn sum_and_scale(f: &[DVec3]) -> (DVec3, f64) {
    (f.iter().sum(), f.iter().map(|v| v.length()).sum())
}

fn deformed_backend(method: Method, combine: ConstraintCombine) -> ReferenceBackend {
    let model = model_in_place(&box_mesh([3, 3, 2]));
    // No floor: the box sits at y = 0, and the jitter would put nodes under it.
    let params = SimParams {
        method,
        combine,
        floor: false,
        ..SimParams::default()
    };
    let mut backend = ReferenceBackend::new(&model, &params).unwrap();
    backend
        .set_state(&jittered_state(&model, 0.02, 0.5, 11))
        .unwrap();
    backend
}

#[test]
fn spring_forces_sum_to_zero_in_both_orders() {
    let backend = deformed_backend(Method::Mss, ConstraintCombine::Scaled);
    for (order, f) in [
        ("scatter", backend.spring_forces_scatter()),
        ("gather", backend.spring_forces_gather()),
    ] {
        let (sum, scale) = sum_and_scale(&f);
        assert!(
            scale > 100.0,
            "the jitter should load the springs, total |f| = {scale}"
        );
        assert!(
            sum.length() < 1e-12 * scale,
            "{order}: sum {sum} of forces totalling {scale} N"
        );
    }
}

#[test]
fn summed_and_scaled_constraint_forces_sum_to_zero() {
    for (method, combine) in [
        (Method::Distance, ConstraintCombine::Sum),
        (Method::Volume, ConstraintCombine::Sum),
        (Method::Distance, ConstraintCombine::Scaled),
        (Method::Volume, ConstraintCombine::Scaled),
    ] {
        let forces = deformed_backend(method, combine).forces();
        let (sum, scale) = sum_and_scale(&forces.constraints);
        assert!(
            scale > 1.0,
            "{method}: constraints should act, total |f| = {scale}"
        );
        assert!(
            sum.length() < 1e-10 * scale,
            "{method}: sum {sum} of forces totalling {scale} N"
        );
        let gravity: DVec3 = forces.gravity.iter().sum();
        let total: DVec3 = forces.total().iter().sum();
        assert!(
            (total - gravity).length() < 1e-10 * scale,
            "{method}: total {total} vs gravity {gravity}"
        );
    }
}

#[test]
fn scatter_and_gather_give_the_same_spring_forces() {
    let backend = deformed_backend(Method::Mss, ConstraintCombine::Scaled);
    let (a, b) = (
        backend.spring_forces_scatter(),
        backend.spring_forces_gather(),
    );
    let largest = a.iter().map(|f| f.length()).fold(0.0, f64::max);
    let diff = max_distance(&a, &b);
    assert!(
        diff < 1e-12 * largest,
        "largest per-node difference {diff:e} N (largest force {largest} N)"
    );
}

#[test]
fn mss_and_mss_node_runs_agree() {
    let model = seed_model(&box_mesh([4, 3, 3]));
    let diag = model.bounds_diagonal();
    let run = |backend: &mut dyn Backend| {
        run_frames(backend, 100);
        backend.state().unwrap().positions
    };
    let params = |method| SimParams {
        method,
        ..SimParams::default()
    };
    let a = run(&mut ReferenceBackend::new(&model, &params(Method::Mss)).unwrap());
    let b = run(&mut ReferenceBackend::new(&model, &params(Method::MssNode)).unwrap());
    let d = max_distance(&a, &b);
    assert!(
        d < 1e-9 * diag,
        "cpu-ref: mss and mss-node differ by {d:e} m after 100 frames"
    );
    let a = run(&mut ParallelBackend::new(&model, &params(Method::Mss)).unwrap());
    let b = run(&mut ParallelBackend::new(&model, &params(Method::MssNode)).unwrap());
    let d = max_distance(&a, &b);
    assert!(
        d < 1e-4 * diag,
        "cpu: mss and mss-node differ by {d:e} m after 100 frames"
    );
}
