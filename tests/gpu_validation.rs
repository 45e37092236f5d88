//! The validation-layer plumbing works: a deliberate API misuse is recorded (so the other
//! GPU tests' "zero messages" means something), and a full run records none.

mod gpu_support;

use std::sync::{Arc, Mutex};

use ash::vk;
use tetrasim::backend::vulkan::VulkanBackend;
use tetrasim::gpu::{Context, ContextOptions};
use tetrasim::params::{Method, SimParams};
use tetrasim::Backend;

/// Validated contexts share the process's validated instance, whose messengers hear every
/// device of it: the misuse must not reach the clean run's log.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

#[test]
fn a_deliberate_misuse_is_recorded() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let _guard = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let ctx = Context::new(&ContextOptions {
        validation: true,
        ..Default::default()
    })
    .unwrap();
    assert!(ctx.validation());
    assert!(ctx.validation_messages().is_empty());
    // usage must not be empty (VUID-VkBufferCreateInfo-usage-requiredbitmask).
    let info = vk::BufferCreateInfo::default()
        .size(64)
        .usage(vk::BufferUsageFlags::empty());
    let buffer = unsafe { ctx.device().create_buffer(&info, None) };
    if let Ok(b) = buffer {
        unsafe { ctx.device().destroy_buffer(b, None) };
    }
    let messages = ctx.validation_messages();
    assert!(
        messages.iter().any(|m| m.contains("usage")),
        "expected a message about `usage`, got {messages:?}"
    );
}

#[test]
fn a_full_run_of_every_method_on_one_context_has_no_messages() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let _guard = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let ctx = Arc::new(
        Context::new(&ContextOptions {
            validation: true,
            ..Default::default()
        })
        .unwrap(),
    );
    let model = gpu_support::box_model([4, 3, 2], 0.1);
    for method in Method::ALL {
        let params = SimParams {
            method,
            iterations: 3,
            ..SimParams::default()
        };
        let mut gpu = VulkanBackend::with_context(ctx.clone(), &model, &params, Some(64)).unwrap();
        for _ in 0..20 {
            gpu.step_frame().unwrap();
            let v = gpu.volume().unwrap();
            assert!(
                v.volume.is_finite() && v.volume > 0.0,
                "{method}: volume {v:?}"
            );
        }
        let state = gpu.state().unwrap();
        assert!(
            state.positions.iter().all(|p| p.y >= 0.0),
            "{method}: a node is below the floor"
        );
        assert!(!gpu.pass_times().unwrap().is_empty());
    }
    let messages = ctx.validation_messages();
    assert!(
        messages.is_empty(),
        "{} validation messages:\n{}",
        messages.len(),
        messages.join("\n")
    );
}
