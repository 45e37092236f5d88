//! Grasp a soft block in its middle, lift it and let go: a tool moving along keyframes,
//! declared once, with no per-frame code.
//!
//! ```text
//! cargo run --release --example grasp [BACKEND] [FRAMES]
//! ```
//!
//! `BACKEND` is `cpu` (default) or `cpu-ref`; `FRAMES` defaults to 500 (0.5 s). The block
//! (0.6 x 0.1 x 0.1 m) lies on the floor, clamped at both ends. A grab holds the nodes
//! within 6 cm of the middle of its top, lifts them 0.1 m over 0.2 s, holds, and releases
//! them at 0.3 s. It prints the middle's height every 50 frames and exits with status 1
//! unless the middle rose with the grab and sank back after the release.

use std::process::ExitCode;

use tetrasim::collider::{Grab, Keyframe, Motion};
use tetrasim::glam::DQuat;
use tetrasim::prelude::*;

const LIFT: f64 = 0.1;
const RELEASE: f64 = 0.3;

fn main() -> Result<ExitCode> {
    let mut args = std::env::args().skip(1);
    let backend_name = args.next().unwrap_or_else(|| "cpu".to_string());
    let frames: u32 = match args.next().map(|s| s.parse()) {
        None => 500,
        Some(Ok(n)) => n,
        Some(Err(e)) => return Err(Error::param("FRAMES", e.to_string())),
    };

    let (length, h) = (0.6, 0.05);
    let mesh = tetrasim::mesh::grid::box_tets(DVec3::ZERO, h, [12, 2, 2]);
    let eps = 1e-6;
    let key = |t: f64, lift: f64| Keyframe {
        t,
        position: DVec3::new(0.0, lift, 0.0),
        rotation: DQuat::IDENTITY,
    };
    let grab = Grab::new(DVec3::new(length / 2.0, 2.0 * h, h), 0.06)
        .moving(Motion::Keyframes(vec![key(0.0, 0.0), key(0.2, LIFT)]))
        .release_at(RELEASE);
    let model = ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: None,
            drop_height: None,
        })
        .material(&SimParams {
            ks: 20000.0,
            kd: 30.0,
            ..SimParams::default()
        })
        // Both end faces clamped.
        .pinned_in_box(DVec3::splat(-eps), DVec3::new(eps, 1.0, 1.0))
        .pinned_in_box(DVec3::new(length - eps, -eps, -eps), DVec3::splat(1.0))
        .build()?
        .with_grab(grab)?;
    let held = model.grabs[0].nodes.clone();
    let params = SimParams::default();
    let mut backend = create_backend(&backend_name, &model, &params)?;
    let rest = middle(&model.positions, &held);
    println!(
        "grasp: backend {}, {} nodes, holding {} of them, lifting {LIFT} m, letting go at {RELEASE} s",
        backend.name(),
        model.node_count(),
        held.len()
    );
    let (mut peak, mut last) = (0.0f64, 0.0);
    for frame in 1..=frames {
        backend.step_frame()?;
        let rise = middle(&backend.state()?.positions, &held) - rest;
        peak = peak.max(rise);
        last = rise;
        if frame % 50 == 0 {
            println!(
                "t = {:.2} s: middle raised {:.1} mm",
                f64::from(frame) * params.frame_time(),
                rise * 1e3
            );
        }
    }
    println!("peak {:.1} mm", peak * 1e3);
    println!("final {:.1} mm", last * 1e3);
    if peak > 0.9 * LIFT && last < 0.5 * peak {
        println!("ok: the block was lifted by its middle and let go");
        Ok(ExitCode::SUCCESS)
    } else {
        println!("unexpected: the grab did not lift and release the block");
        Ok(ExitCode::FAILURE)
    }
}

/// The mean height of the nodes `held` [m].
fn middle(positions: &[DVec3], held: &[u32]) -> f64 {
    held.iter().map(|&i| positions[i as usize].y).sum::<f64>() / held.len() as f64
}
