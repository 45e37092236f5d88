//! The fast backend (`cpu`: f32, rayon) follows the reference (`cpu-ref`: f64) through 100
//! frames of the `seed` preset, dropped from 1 cm so that it lands after 45 frames and the
//! floor contact is part of the comparison, for every method.
//!
//! Tolerance: every node within 1e-5 of the bounding-box diagonal of the reference, and volume
//! percentages within 0.01 points. f32 has a relative precision of 6e-8; measured on this
//! 1.2k-tet ball: about 1e-7 diagonals for every method, so the bound leaves a factor 100.

mod common;

use common::{ball_mesh, max_distance, near_floor_model, run_frames};
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::backend::Backend;
use tetrasim::params::Method;
use tetrasim::SimParams;

const TOLERANCE: f64 = 1e-5;

#[test]
fn cpu_follows_cpu_ref_for_100_frames() {
    let model = near_floor_model(&ball_mesh(3.0));
    let diag = model.bounds_diagonal();
    let rest = model.total_rest_volume();
    assert!(model.tets.len() > 500, "{} tets", model.tets.len());
    for method in Method::ALL {
        let params = SimParams {
            method,
            ..SimParams::default()
        };
        let mut reference = ReferenceBackend::new(&model, &params).unwrap();
        let mut fast = ParallelBackend::new(&model, &params).unwrap();
        let mut lowest = f64::INFINITY;
        for _ in 0..10 {
            run_frames(&mut reference, 10);
            let y = reference
                .state()
                .unwrap()
                .positions
                .iter()
                .map(|p| p.y)
                .fold(f64::INFINITY, f64::min);
            lowest = lowest.min(y);
        }
        run_frames(&mut fast, 100);
        let (a, b) = (reference.state().unwrap(), fast.state().unwrap());
        // The ball has touched the floor on the way (the floor constraint lands nodes on
        // y = 0 up to rounding).
        assert!(
            lowest.abs() < 1e-12,
            "{method}: lowest node only reached {lowest} m"
        );
        let d = max_distance(&a.positions, &b.positions);
        println!(
            "{method}: max node distance {d:e} m = {:e} diagonals",
            d / diag
        );
        assert!(
            d < TOLERANCE * diag,
            "{method}: max node distance {d:e} m, diagonal {diag} m"
        );
        let (va, vb) = (
            reference.volume().unwrap().volume / rest,
            fast.volume().unwrap().volume / rest,
        );
        assert!(
            (100.0 * (va - vb)).abs() < 0.01,
            "{method}: volume {:.4} % vs {:.4} %",
            100.0 * va,
            100.0 * vb
        );
    }
}
