//! Hold one end of a bar and drag a node of the other end from your own loop.
//!
//! ```text
//! cargo run --release --example pull [BACKEND] [FRAMES]
//! ```
//!
//! `BACKEND` is `cpu` (default), `cpu-ref` or `vulkan`; `FRAMES` defaults to 600 (0.6 s).
//! The node is pinned (inverse mass 0), so the solver never moves it by force; the program
//! moves it instead, writing its position and velocity with `Backend::set_state` before
//! every frame. The bar floats (no gravity, no floor). It prints the bar's stretch every 50
//! frames and exits with status 1 unless the bar stretched and its free end followed.

use std::process::ExitCode;

use tetrasim::prelude::*;

/// Pulling speed along +X [m/s] and for how long [s]; then the node is held still.
const SPEED: f64 = 0.1;
const PULL_TIME: f64 = 0.3;

fn main() -> Result<ExitCode> {
    let mut args = std::env::args().skip(1);
    let backend_name = args.next().unwrap_or_else(|| "cpu".to_string());
    let frames: u32 = match args.next().map(|s| s.parse()) {
        None => 600,
        Some(Ok(n)) => n,
        Some(Err(e)) => return Err(Error::param("FRAMES", e.to_string())),
    };

    // A 0.4 x 0.1 x 0.1 m bar of 8 x 2 x 2 cubes, 5 tets each, kept where it is generated.
    let (length, h) = (0.4, 0.05);
    let mesh = tetrasim::mesh::grid::box_tets(DVec3::ZERO, h, [8, 2, 2]);
    let eps = 1e-6;
    // The handle: the centre node of the end face x = length.
    let handle = mesh
        .nodes
        .iter()
        .position(|p| p.distance(DVec3::new(length, h, h)) < eps)
        .expect("the bar has a node at the centre of its end face") as u32;
    let model = ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: None,
            drop_height: None,
        })
        // The whole face x = 0 is held, and the handle is pinned so only we move it.
        .pinned_in_box(DVec3::splat(-eps), DVec3::new(eps, 1.0, 1.0))
        .pinned([handle])
        .build()?;
    let params = SimParams {
        gravity: glam::DVec3::ZERO,
        floor: false,
        ..SimParams::default()
    };
    let mut backend = create_backend(&backend_name, &model, &params)?;
    let dt = params.frame_time();
    // The free nodes of the far face (they are not pinned: they follow only through the mesh).
    let far: Vec<usize> = (0..model.node_count())
        .filter(|&i| model.positions[i].x > length - eps && i != handle as usize)
        .collect();
    let start = model.positions[handle as usize];
    println!(
        "pull: backend {}, {} nodes, {} pinned, pulling node {handle} at {SPEED} m/s for {PULL_TIME} s",
        backend.name(),
        model.node_count(),
        model.node_count() - model.free_node_count(),
    );

    let mut stretch = 0.0;
    let mut far_shift = 0.0;
    for frame in 0..frames {
        // Where the handle is at the start of this frame, and how fast it moves during it.
        let t = f64::from(frame) * dt;
        let velocity = if t < PULL_TIME { SPEED } else { 0.0 };
        let mut state = backend.state()?;
        state.positions[handle as usize] = start + DVec3::X * (SPEED * t.min(PULL_TIME));
        state.velocities[handle as usize] = DVec3::X * velocity;
        backend.set_state(&state)?;

        backend.step_frame()?;

        // Read back: the bar's length along X (the far face's mean X) and how far the free
        // nodes of the far face moved.
        let state = backend.state()?;
        let far_x = far.iter().map(|&i| state.positions[i].x).sum::<f64>() / far.len() as f64;
        stretch = far_x / length - 1.0;
        far_shift = far_x - length;
        if (frame + 1) % 50 == 0 || frame + 1 == frames {
            let pulled = state.positions[handle as usize].x - start.x;
            println!(
                "frame {:4}  handle +{:.4} m  far face +{far_shift:.4} m  stretch {:.2} %  volume {:.4}",
                frame + 1,
                pulled,
                100.0 * stretch,
                backend.volume()?.volume / model.total_rest_volume()
            );
        }
    }

    let pulled = SPEED * (f64::from(frames) * dt).min(PULL_TIME);
    println!(
        "final stretch {:.3} %, far face moved {far_shift:.4} m of the handle's {pulled:.4} m",
        100.0 * stretch
    );
    // The far face must follow the handle most of the way, and the bar be longer.
    if stretch > 0.0 && far_shift > 0.5 * pulled {
        println!("ok: the bar stretched and its far end followed the handle");
        Ok(ExitCode::SUCCESS)
    } else {
        println!("FAILED: stretch {stretch:e}, far face shift {far_shift:e} m");
        Ok(ExitCode::FAILURE)
    }
}
