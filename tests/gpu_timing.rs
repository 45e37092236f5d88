//! GPU timestamps: every pass of the method (default solver: spring forces gathered, the
//! constraint passes once per colour group, the global volume constraint per iteration) is
//! timed, each time is positive, and their sum
//! per frame is no more than the frame's wall time measured on the host.

mod gpu_support;

use std::time::Instant;

use tetrasim::params::{Method, SimParams};
use tetrasim::Backend;

#[test]
fn pass_times_are_present_positive_and_within_the_frame_wall_time() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = gpu_support::box_model([8, 6, 6], 0.1);
    let expected: [(Method, &[&str]); 4] = [
        (
            Method::Mss,
            &[
                "spring_scatter",
                "integrate",
                "check",
                "volume_sum",
                "reactions",
            ],
        ),
        (
            Method::MssNode,
            &[
                "spring_gather",
                "integrate",
                "check",
                "volume_sum",
                "reactions",
            ],
        ),
        (
            Method::Distance,
            &[
                "spring_gather",
                "global_volume_prepare",
                "distance",
                "constraint_apply",
                "global_volume_sum",
                "global_volume",
                "integrate",
                "check",
                "volume_sum",
                "reactions",
            ],
        ),
        (
            Method::Volume,
            &[
                "spring_gather",
                "global_volume_prepare",
                "volume",
                "constraint_apply",
                "global_volume_sum",
                "global_volume",
                "integrate",
                "check",
                "volume_sum",
                "reactions",
            ],
        ),
    ];
    for (method, names) in expected {
        let params = SimParams {
            method,
            ..SimParams::default()
        };
        let mut gpu = gpu_support::validated(&model, &params);
        if !gpu.device().timestamps {
            println!("SKIPPED: the device has no timestamps");
            return;
        }
        let frames = 10;
        let start = Instant::now();
        for _ in 0..frames {
            gpu.step_frame().unwrap();
            gpu.volume().unwrap();
        }
        let wall_ms = start.elapsed().as_secs_f64() * 1e3 / f64::from(frames);
        let times = gpu.pass_times().unwrap();
        let got: Vec<&str> = times.iter().map(|t| t.name.as_str()).collect();
        assert_eq!(got, names, "{method}: timed passes");
        for t in &times {
            assert!(
                t.ms_per_frame > 0.0 && t.ms_per_frame.is_finite(),
                "{method}: pass {} took {} ms",
                t.name,
                t.ms_per_frame
            );
        }
        let gpu_ms: f64 = times.iter().map(|t| t.ms_per_frame).sum();
        println!("{method}: GPU {gpu_ms:.3} ms of {wall_ms:.3} ms wall per frame: {times:?}");
        assert!(
            gpu_ms <= wall_ms,
            "{method}: passes sum to {gpu_ms} ms, more than the frame's {wall_ms} ms wall time"
        );
        gpu_support::assert_no_validation_messages(&gpu);
    }
}
