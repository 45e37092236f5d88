//! Frames in flight on `vulkan` (lavapipe, validation layer on): the driver's pipelined
//! `advance_frames` queues the next frame before it reads the last one's volume, and gives
//! the same frames, bit for bit, as stepping and waiting frame by frame; a divergence is
//! reported for the same frame either way.

mod gpu_support;

use gpu_support::{assert_no_validation_messages, box_model, jittered, validated};
use tetrasim::params::{Method, SimParams};
use tetrasim::sim::{Advance, Simulation};
use tetrasim::Backend;

const FRAMES: u32 = 90;

/// Runs `frames` frames frame by frame (`advance`, every frame waited for) and pipelined
/// (`advance_frames`); returns both simulations and backends.
fn both_ways(
    model: &tetrasim::Model,
    params: &SimParams,
    frames: u32,
    sample: &dyn Fn(u32) -> bool,
) -> [(Simulation, tetrasim::backend::vulkan::VulkanBackend); 2] {
    let mut stepped = validated(model, params);
    let mut one = Simulation::new(model, params);
    for n in 1..=frames {
        if one.advance(&mut stepped, sample(n)).unwrap() == Advance::Stopped {
            break;
        }
    }
    let mut pipelined = validated(model, params);
    let mut two = Simulation::new(model, params);
    let mut seen = 0;
    let advanced = two
        .advance_frames(&mut pipelined, frames, sample, &mut |_| seen += 1)
        .unwrap();
    assert_eq!(advanced, two.frames());
    assert_eq!(seen, two.frames(), "on_frame runs once per recorded frame");
    [(one, stepped), (two, pipelined)]
}

#[test]
fn pipelined_frames_equal_frames_waited_for_one_by_one() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // A deformed, spinning box that lands (default solver: deterministic, no atomics).
    let model = jittered(&box_model([4, 3, 2], 0.25), 0.01, 0.3, 7);
    let params = SimParams {
        method: Method::Volume,
        ..SimParams::default()
    };
    let sample = |n: u32| n % 3 != 0;
    let [(one, mut stepped), (two, mut pipelined)] = both_ways(&model, &params, FRAMES, &sample);
    assert_eq!(one.frames(), FRAMES);
    assert_eq!(two.frames(), FRAMES);
    assert_eq!(one.series.volume_pct.len(), 60);
    assert_eq!(one.series, two.series, "same measures, bit for bit");
    let (a, b) = (stepped.state().unwrap(), pipelined.state().unwrap());
    assert_eq!(a, b, "same final state, bit for bit");
    // The landing happened (the measures are not those of a rigid fall).
    let min = one
        .series
        .volume_pct
        .iter()
        .cloned()
        .fold(f64::MAX, f64::min);
    let max_local = one
        .series
        .local_error_pct
        .iter()
        .cloned()
        .fold(0.0, f64::max);
    assert!(
        min < 100.0 && max_local > 0.01,
        "min {min} %, local {max_local} %"
    );
    // The pipelined run really had two frames in flight; the stepped one never did.
    assert_eq!(pipelined.max_frames_in_flight(), 2);
    assert_eq!(stepped.max_frames_in_flight(), 1);
    assert_eq!(pipelined.frames(), FRAMES);
    assert_no_validation_messages(&stepped);
    assert_no_validation_messages(&pipelined);
}

#[test]
fn a_divergence_in_flight_stops_at_the_same_frame() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // Springs far too stiff for the step: explicit integration blows up within frames.
    let model = box_model([3, 2, 2], 0.25);
    let params = SimParams {
        method: Method::Mss,
        ks: 1e9,
        dt: 4e-3,
        ..SimParams::default()
    };
    let [(one, stepped), (two, pipelined)] = both_ways(&model, &params, 200, &|_| true);
    let why = one.divergence.clone().expect("the stepped run diverges");
    assert!(one.frames() < 200, "{}", one.frames());
    // The speed is the diverged frame's own (from its status, not a later state).
    assert!(why.contains("the fastest node's speed"), "{why}");
    assert_eq!(two.divergence.as_deref(), Some(why.as_str()));
    assert_eq!(one.frames(), two.frames());
    assert_eq!(one.series, two.series);
    // The frame after the diverged one was already queued; it finished unrecorded.
    assert_eq!(pipelined.max_frames_in_flight(), 2);
    assert_no_validation_messages(&stepped);
    assert_no_validation_messages(&pipelined);
}
