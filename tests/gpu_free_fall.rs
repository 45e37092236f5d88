//! Free fall on the GPU matches the closed form of symplectic Euler: springs at rest exert
//! no force, so after k steps v = -g k dt and y = y0 - g dt^2 k (k + 1) / 2, for every node.

mod gpu_support;

use tetrasim::params::{AtomicsMode, Method, SimParams};
use tetrasim::Backend;

#[test]
fn free_fall_moves_every_node_by_the_closed_form_amount() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = gpu_support::box_model([3, 2, 2], 0.1);
    for method in Method::ALL {
        for atomics in [AtomicsMode::Ext, AtomicsMode::Cas] {
            let params = SimParams {
                method,
                atomics,
                floor: false,
                substeps: 4,
                ..SimParams::default()
            };
            let mut gpu = gpu_support::validated(&model, &params);
            let frames = 5;
            for _ in 0..frames {
                gpu.step_frame().unwrap();
            }
            let state = gpu.state().unwrap();
            let k = f64::from(frames * params.substeps);
            let (g, dt) = (params.gravity, params.dt);
            let drop = g * dt * dt * k * (k + 1.0) / 2.0;
            for (i, (x, v)) in state.positions.iter().zip(&state.velocities).enumerate() {
                let x0 = model.positions[i];
                // f32 positions near 1 m: a few ulps of 1.2e-7 m per step.
                assert!(
                    (x.y - (x0.y - drop)).abs() < 2e-6,
                    "{method} {atomics:?} node {i}: y {} vs {}",
                    x.y,
                    x0.y - drop
                );
                assert!(
                    (x.x - x0.x).abs() < 1e-6 && (x.z - x0.z).abs() < 1e-6,
                    "{method} node {i} drifted sideways"
                );
                assert!(
                    (v.y + g * dt * k).abs() < 1e-4,
                    "{method} node {i}: vy {} vs {}",
                    v.y,
                    -g * dt * k
                );
            }
            let volume = gpu.volume().unwrap();
            assert!(
                (volume.volume / model.total_rest_volume() - 1.0).abs() < 1e-4,
                "{method}: rigid fall changed the volume"
            );
            assert_eq!(volume.inverted, 0);
            assert_eq!(gpu.frames(), frames);
            gpu_support::assert_no_validation_messages(&gpu);
        }
    }
}
