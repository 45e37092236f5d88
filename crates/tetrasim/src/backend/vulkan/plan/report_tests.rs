//! The report's cost column: each pass's predicted time per run and its share of the
//! frame, as the cost model computes them, and what the model leaves out.

use super::tests::{plan, volume_sweep, COUNTS, ONE_OBJECT};
use super::*;

#[test]
fn the_report_prints_each_pass_s_predicted_time_and_share_of_the_frame() {
    let sweeps = volume_sweep();
    let params = SimParams {
        method: Method::Volume,
        ..SimParams::default()
    };
    let p = plan(&params, &sweeps);
    let report = p.render();
    let h200 = GPU_PROFILES[0];
    let table = report
        .lines()
        .skip_while(|l| !l.starts_with("pass "))
        .skip(1)
        .take_while(|l| !l.starts_with("estimated bytes"));
    let (mut frame_us, mut shares) = (0.0, 0.0);
    for (line, pass) in table.zip(&p.passes) {
        let words: Vec<&str> = line.split_whitespace().collect();
        let number = |k: usize| words[words.len() - k].parse::<f64>().unwrap();
        let (us, share) = (number(2), number(1));
        assert!((us - h200.dispatch_us(&p, pass)).abs() < 0.01, "{line}");
        frame_us += us * f64::from(p.runs_per_frame(pass));
        shares += share;
    }
    assert!((frame_us * 1e-3 - h200.frame_ms(&p)).abs() < 1e-3 * h200.frame_ms(&p));
    assert!(
        (shares - 100.0).abs() < 0.1 * p.passes.len() as f64,
        "{shares}\n{report}"
    );
}

#[test]
fn plan_names_the_minres_loop_its_model_leaves_out() {
    let sweeps = volume_sweep();
    let params = SimParams {
        method: Method::Volume,
        iterations: 2,
        minres: 4,
        ..SimParams::default()
    };
    let small = EnginePlan::new(COUNTS, &params, 64, false, &sweeps, Some(ONE_OBJECT));
    assert_eq!(small.minres_object_loop(), Some((8, 1)));
    assert!(!small.render().contains("not counted"));
    // horse86m: every one of its 24228 nodes is on the surface.
    let horse = GlobalCounts {
        nodes: 24228,
        faces: 48452,
        largest: 48452,
        largest_nodes: 24228,
        ..ONE_OBJECT
    };
    let plan = EnginePlan::new(COUNTS, &params, 256, false, &sweeps, Some(horse));
    assert_eq!(plan.minres_object_loop(), Some((24228, 95)));
    let text = plan.render();
    assert!(
        text.contains("24228 surface nodes summed by one workgroup per object (95 per invocation)"),
        "{text}"
    );
    let without = SimParams {
        minres: 0,
        ..params
    };
    let off = EnginePlan::new(COUNTS, &without, 256, false, &sweeps, Some(horse));
    assert_eq!(off.minres_object_loop(), None);
}
