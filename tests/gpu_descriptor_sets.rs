//! Each pass binds its own arrays (`backend/vulkan/passes.rs`): a rich scene (volume
//! constraints with the global ones, Anderson acceleration, a collider) touches more arrays
//! (35) than a pass may bind on lavapipe (32 storage buffers per stage), and with one
//! descriptor set shared by every pass lavapipe crashed on it (SIGSEGV in its worker
//! thread). With a set per pass it runs, the validation layer silent, and every pass stays
//! within the device's limit.

mod common;
mod gpu_support;

use std::collections::BTreeSet;

use common::{ball_mesh, near_floor_model, over_tilted_plane, run_frames};
use tetrasim::params::Method;
use tetrasim::{Backend, SimParams};

#[test]
fn a_scene_past_the_per_stage_limit_runs_with_a_set_per_pass() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = over_tilted_plane(near_floor_model(&ball_mesh(3.0)));
    let params = SimParams {
        method: Method::Volume,
        iterations: 2,
        anderson: 3,
        ..SimParams::default()
    };
    let mut gpu = gpu_support::validated(&model, &params);
    let limit = gpu.device().max_storage_buffers as usize;
    let plan = gpu.plan();
    let union: BTreeSet<u32> = (plan.passes.iter())
        .flat_map(|p| p.stage.bindings.iter().map(|(id, _)| id.binding()))
        .collect();
    let widest = (plan.passes.iter())
        .map(|p| p.stage.bindings.len())
        .max()
        .unwrap();
    println!(
        "{} arrays in all, at most {widest} in one pass; the device allows {limit} per stage",
        union.len()
    );
    if limit <= 32 {
        assert!(union.len() > limit, "the scene no longer passes the limit");
    }
    assert!(widest <= limit, "a pass binds {widest} arrays");
    run_frames(&mut gpu, 20);
    let volume = gpu.volume().unwrap();
    assert!(
        volume.volume > 0.9 * model.total_rest_volume(),
        "{volume:?}"
    );
    gpu_support::assert_no_validation_messages(&gpu);
}
