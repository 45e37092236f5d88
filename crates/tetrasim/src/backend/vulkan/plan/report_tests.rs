//! The report's cost column: each pass's predicted time per run and its share of the
//! frame, as the cost model computes them.

use super::tests::{plan, volume_sweep};
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
