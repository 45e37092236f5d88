//! Drop a ball on the floor from your own loop and read the positions back every frame.
//!
//! ```text
//! cargo run --release --example drop [BACKEND] [FRAMES]
//! ```
//!
//! `BACKEND`: `cpu` (default), `cpu-ref` or `vulkan`; `FRAMES`: 1000 (1 s). Prints the
//! lowest node's height, the centre of mass and the volume ratio every 50 frames; exits
//! with status 1 unless the ball came to rest on the floor with its volume kept.

use std::process::ExitCode;

use tetrasim::prelude::*;

fn main() -> Result<ExitCode> {
    let mut args = std::env::args().skip(1);
    let backend_name = args.next().unwrap_or_else(|| "cpu".to_string());
    let frames: u32 = match args.next().map(|s| s.parse()) {
        None => 1000,
        Some(Ok(n)) => n,
        Some(Err(e)) => return Err(Error::param("FRAMES", e.to_string())),
    };

    // The bundled sphere (823 nodes) is compiled into the library, so this works from any
    // folder; a path to your own tet mesh (TetGen prefix, .vtk, .vtu, .msh, .mesh) or a
    // surface file (.ply, .obj, .off, .stl, meshed in-process) loads the same way.
    let mesh = load_mesh(Path::new("meshes/sphere"), None)?.mesh;

    // Scale it to 0.5 m across, centre it over the origin and put its lowest node 0.1 m
    // above the floor y = 0. 0.2 kg per node (165 kg in all).
    let mass = MassMode::PerNode { mass: 0.2 };
    let model = ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: Some(0.5),
            drop_height: Some(0.1),
        })
        .mass(mass)
        .build()?;

    // The default physics: volume constraints, Gauss-Seidel, dt = 1 ms, one step a frame.
    // More spring damping than the default (15 N s/m) so that the bounces die out, and
    // some friction so that the ball does not slide on.
    let params = SimParams {
        mass,
        kd: 60.0,
        friction: 0.5,
        ..SimParams::default()
    };
    let mut backend = create_backend(&backend_name, &model, &params)?;
    let rest_volume = model.total_rest_volume();
    println!(
        "drop: backend {}, {} nodes, {} tets, {frames} frames of {} s",
        backend.name(),
        model.node_count(),
        model.tets.len(),
        params.frame_time()
    );

    // Your loop: step, read back, use the numbers (draw, log, couple to your own code ...).
    let mut state = backend.state()?;
    let mut last_airborne = 0; // the last frame whose lowest node was above 1 mm
    for frame in 1..=frames {
        backend.step_frame()?;
        state = backend.state()?; // positions [m] and velocities [m/s] of every node
        if lowest_height(&state) > 1e-3 {
            last_airborne = frame;
        }
        if frame % 50 == 0 || frame == frames {
            let lowest = lowest_height(&state);
            let centre = centre_of_mass(&state, &model.mass);
            let ratio = backend.volume()?.volume / rest_volume;
            println!(
                "frame {frame:4}  lowest {lowest:+.5} m  centre ({:+.4}, {:+.4}, {:+.4}) m  volume {ratio:.4}",
                centre.x, centre.y, centre.z
            );
        }
    }

    let lowest = lowest_height(&state);
    let ratio = backend.volume()?.volume / rest_volume;
    let speed = state
        .velocities
        .iter()
        .map(|v| v.length())
        .fold(0.0, f64::max);
    println!("final lowest {lowest:.6} m");
    println!("final volume ratio {ratio:.5}");
    println!("final fastest node {speed:.4} m/s");
    println!("final frames on the floor {}", frames - last_airborne);
    // On the floor, no bounce in the last 0.3 s, and the volume kept.
    let on_floor = lowest.abs() < 1e-3;
    let settled = f64::from(frames - last_airborne) * params.frame_time() >= 0.3;
    let volume_kept = (ratio - 1.0).abs() < 0.01;
    if on_floor && settled && volume_kept {
        println!("ok: came to rest on the floor (no bounce in the last 0.3 s), volume within 1 %");
        Ok(ExitCode::SUCCESS)
    } else {
        println!(
            "FAILED: on the floor (|lowest| < 1 mm): {on_floor}, no bounce in the last 0.3 s: \
             {settled}, volume within 1 %: {volume_kept}"
        );
        Ok(ExitCode::FAILURE)
    }
}

/// Height of the lowest node [m].
fn lowest_height(state: &State) -> f64 {
    state
        .positions
        .iter()
        .map(|p| p.y)
        .fold(f64::INFINITY, f64::min)
}

/// Mass-weighted mean position [m].
fn centre_of_mass(state: &State, mass: &[f64]) -> DVec3 {
    let sum: DVec3 = state.positions.iter().zip(mass).map(|(&p, &m)| p * m).sum();
    sum / mass.iter().sum::<f64>()
}
