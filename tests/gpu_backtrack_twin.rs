//! The finite elements' backtracking decision on the GPU (`elastic_backtrack`)
//! equals `backtrack` (src/schedule/family/elastic.rs) on potentials that fall as the
//! quadratic model predicts (the linearisation kept), fall short of it (relinearised), rise
//! at the full step but fall at a halving, never fall within the halvings (done), or are
//! halved back into the trusted strain (taken unchecked). A brick of `vulkan`'s finite
//! elements (docs/GPU.md, "Finite elements on the GPU").

mod gpu_support;

use bytemuck::Zeroable;
use gpu_support::twin;
use tetrasim::gpu::commands::{barrier, one_shot, Access};
use tetrasim::gpu::layout::{binding, PushConstants};
use tetrasim::gpu::{Buffer, Kernel};
use tetrasim::schedule::family::{backtrack, Backtracked};
use tetrasim::shaders::file;

/// State words (glsl/physics/newton.glsl).
const CURVATURE: usize = 1;
const ALPHA: usize = 2;
const STRAIN: usize = 4;
const DONE: usize = 5;
const CHECK: usize = 6;
const RELINEARISE: usize = 7;
const PARTIALS: usize = 16;

/// One case: the conjugate gradients' step, its strain per unit step, the direction's
/// curvature and the potential's change at a step `a`.
struct Case {
    name: &'static str,
    alpha: f64,
    strain: f64,
    curvature: f64,
    change: fn(f64) -> f64,
}

/// The quadratic model's change at `a` for the step 1 of curvature 2: `-2 a (1 - a / 2)`.
fn model(a: f64) -> f64 {
    -2.0 * a * (1.0 - 0.5 * a)
}

fn cases() -> [Case; 5] {
    let case = |name, strain, change| Case {
        name,
        alpha: 1.0,
        strain,
        curvature: 2.0,
        change,
    };
    [
        case("falls as predicted", 0.05, |a| 0.9 * model(a)),
        case("falls short", 0.05, |a| 0.3 * model(a)),
        case("rises, then falls at a halving", 0.5, |a| {
            model(a) + 3.0 * a * a * a
        }),
        case("never falls", 1e3, |a| a),
        case("halved into the trust", 0.03, |a| a),
    ]
}

/// The GPU's decision on `case`: the step taken (`None`: done) and whether it relinearises.
fn on_gpu(case: &Case) -> (Option<f32>, bool) {
    let ctx = twin::context();
    let mut words = [0u32; PARTIALS + 9];
    words[CURVATURE] = (case.curvature as f32).to_bits();
    words[ALPHA] = (case.alpha as f32).to_bits();
    words[STRAIN] = (case.strain as f32).to_bits();
    words[CHECK] = 1;
    let mut step = case.alpha;
    for k in 0..9 {
        words[PARTIALS + k] = ((case.change)(step) as f32).to_bits();
        step *= 0.5;
    }
    let bytes = (4 * words.len()) as u64;
    let state = Buffer::with_data(&ctx, "elastic state", bytemuck::cast_slice(&words)).unwrap();
    let readback = Buffer::readback(&ctx, "readback", bytes).unwrap();
    let layout = Kernel::binding_layout(&ctx, "backtrack twin", &[binding::ELASTIC_STATE]).unwrap();
    layout.write(&[(binding::ELASTIC_STATE, &state)]);
    let key = file::PASSES_ELASTIC_BACKTRACK_COMP;
    let pass = Kernel::with_constants(&ctx, key, key, &layout, 64, &[1]).unwrap();
    one_shot(&ctx, |cmd| {
        pass.record(cmd, &PushConstants::zeroed(), 1);
        barrier(&ctx, cmd, &[&state], Access::COMPUTE, Access::TRANSFER_READ);
        twin::copy(&ctx, cmd, &state, &readback, [0, 0], bytes);
        twin::to_host(&ctx, cmd, &readback);
    })
    .unwrap();
    let out = twin::floats(&ctx, &readback);
    let word = |k: usize| out[k].to_bits();
    let alpha = (word(DONE) == 0).then_some(out[ALPHA]);
    (alpha, word(RELINEARISE) != 0)
}

#[test]
fn the_gpu_backtracking_decides_as_its_definition() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let (mut kept, mut halved) = (0, 0);
    for case in cases() {
        let want: Backtracked = backtrack(
            case.alpha,
            case.strain,
            case.curvature,
            Some(0.0),
            case.change,
        );
        let (alpha, relinearise) = on_gpu(&case);
        assert!(want.checked, "{}: checked", case.name);
        assert_eq!(
            alpha.map(f64::from),
            want.alpha,
            "{}: the step taken",
            case.name
        );
        assert_eq!(relinearise, want.relinearise, "{}: relinearised", case.name);
        kept += usize::from(want.alpha.is_some() && !want.relinearise);
        halved += usize::from(want.alpha.is_some_and(|a| a < case.alpha));
        println!("{}: {want:?}", case.name);
    }
    assert!(kept >= 1 && halved >= 2, "kept {kept}, halved {halved}");
}
