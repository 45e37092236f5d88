//! The one frame driver (`tetrasim::sim::Simulation`) that run, bench and render step through: the
//! series it keeps, the time axis, sampling on demand, and a divergence turned into a stop
//! after which nothing more is stepped.

mod common;

use common::{ball_mesh, seed_model};
use tetrasim::params::{Method, SimParams};
use tetrasim::sim::{create_backend, Advance, Simulation};

#[test]
fn series_follow_the_sampled_frames() {
    let model = seed_model(&ball_mesh(2.0));
    let params = SimParams {
        method: Method::Volume,
        substeps: 2,
        ..SimParams::default()
    };
    let mut backend = create_backend("cpu-ref", &model, &params).unwrap();
    let mut sim = Simulation::new(&model, &params);
    for frame in 0..6 {
        let sample = frame % 2 == 1;
        assert!(matches!(
            sim.advance(backend.as_mut(), sample).unwrap(),
            Advance::Stepped(_)
        ));
    }
    assert_eq!(sim.frames(), 6);
    assert!((sim.time() - 6.0 * 2.0 * params.dt).abs() < 1e-15);
    let s = &sim.series;
    assert_eq!(s.volume_pct.len(), 3);
    assert_eq!(s.inverted.len(), 3);
    assert_eq!(s.local_error_pct.len(), 3);
    let expected: Vec<f64> = [2.0, 4.0, 6.0]
        .iter()
        .map(|f| f * 2.0 * params.dt)
        .collect();
    for (t, e) in s.time_s.iter().zip(&expected) {
        assert!((t - e).abs() < 1e-15, "{:?}", s.time_s);
    }
    // Free fall from rest: no deformation yet, the volume is the rest volume.
    for v in &s.volume_pct {
        assert!((v - 100.0).abs() < 1e-9, "{v}");
    }
    assert!(sim.divergence.is_none());
}

/// A `cpu-ref` run of springs far too stiff for the step: explicit integration blows up
/// within frames.
fn diverging_run() -> (Box<dyn tetrasim::Backend>, Simulation) {
    let model = seed_model(&ball_mesh(2.0));
    let params = SimParams {
        method: Method::Mss,
        ks: 1e12,
        dt: 1e-2,
        ..SimParams::default()
    };
    let backend = create_backend("cpu-ref", &model, &params).unwrap();
    (backend, Simulation::new(&model, &params))
}

#[test]
fn a_divergence_stops_the_run() {
    let (mut backend, mut sim) = diverging_run();
    let mut stepped = 0;
    for _ in 0..200 {
        match sim.advance(backend.as_mut(), true).unwrap() {
            Advance::Stepped(_) => stepped += 1,
            Advance::Stopped => break,
        }
    }
    assert!(stepped < 200, "never diverged");
    let why = sim.divergence.clone().expect("a divergence is recorded");
    assert!(!why.is_empty());
    // Stopped for good: no more frames, the series keeps only finite values.
    let frames = sim.frames();
    assert_eq!(
        sim.advance(backend.as_mut(), true).unwrap(),
        Advance::Stopped
    );
    assert_eq!(sim.frames(), frames);
    assert!(sim.series.volume_pct.iter().all(|v| v.is_finite()));
}

#[test]
fn advance_frames_records_what_advance_records() {
    let model = seed_model(&ball_mesh(2.0));
    let params = SimParams {
        method: Method::Volume,
        ..SimParams::default()
    };
    let sample = |n: u32| n % 2 == 0 || n == 25;
    let mut a = create_backend("cpu", &model, &params).unwrap();
    let mut one = Simulation::new(&model, &params);
    for n in 1..=25 {
        one.advance(a.as_mut(), sample(n)).unwrap();
    }
    let mut b = create_backend("cpu", &model, &params).unwrap();
    let mut two = Simulation::new(&model, &params);
    let mut progress = Vec::new();
    // In two calls, as `run` does between mesh outputs.
    for frames in [10, 15] {
        two.advance_frames(b.as_mut(), frames, &sample, &mut |s| {
            progress.push(s.frames())
        })
        .unwrap();
    }
    assert_eq!(progress, (1..=25).collect::<Vec<u32>>());
    assert_eq!(two.frames(), 25);
    assert_eq!(one.series.volume_pct.len(), 13);
    assert_eq!(one.series, two.series);
    assert_eq!(a.state().unwrap(), b.state().unwrap());
}

#[test]
fn advance_frames_stops_at_a_divergence() {
    let (mut backend, mut sim) = diverging_run();
    let advanced = sim
        .advance_frames(backend.as_mut(), 200, &|_| true, &mut |_| {})
        .unwrap();
    assert!(advanced < 200, "never diverged");
    assert_eq!(advanced, sim.frames());
    assert!(sim.divergence.is_some());
    assert_eq!(
        sim.advance_frames(backend.as_mut(), 5, &|_| true, &mut |_| {})
            .unwrap(),
        0
    );
}
