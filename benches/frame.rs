//! `cargo bench --bench frame`: one frame of each method per backend on the bundled sphere
//! (2857 tets), `seed` physics. The `vulkan` rows are skipped when no Vulkan device exists.

use criterion::{criterion_group, criterion_main, Criterion};
use tetrasim::bench::Backends;
use tetrasim::engine::EngineOptions;
use tetrasim::params::{Method, Placement, SimParams};
use tetrasim::runner::{build_model, load_mesh};

fn frames(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere");
    let mesh = load_mesh(&path, None)
        .expect("bundled mesh meshes/sphere")
        .mesh;
    let mut backends = Backends::new(EngineOptions::default());
    let vulkan = matches!(tetrasim::gpu::list_devices(), Ok(d) if !d.is_empty());
    let mut group = c.benchmark_group("frame");
    group.sample_size(10);
    group.warm_up_time(std::time::Duration::from_millis(500));
    group.measurement_time(std::time::Duration::from_secs(2));
    for backend in ["cpu", "vulkan"] {
        if backend == "vulkan" && !vulkan {
            eprintln!("no Vulkan device: skipping the vulkan benchmarks");
            continue;
        }
        for method in Method::ALL {
            let params = SimParams {
                method,
                ..SimParams::default()
            };
            let model = build_model(&mesh, &params, Placement::default()).expect("model");
            let mut solver = backends.create(backend, &model, &params).expect("backend");
            group.bench_function(format!("{backend}/{method}"), |b| {
                // The scene keeps falling and bouncing; each frame is a real frame of it.
                b.iter(|| solver.step_frame().expect("frame"))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, frames);
criterion_main!(benches);
