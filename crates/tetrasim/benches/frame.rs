//! `cargo bench --bench frame`: one frame of each method per backend on the bundled sphere
//! (2857 tets), `seed` physics. The `vulkan` rows are skipped when no Vulkan device exists.
// criterion_group! defines an undocumented public function.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use tetrasim::backend::vulkan::EngineOptions;
use tetrasim::params::{Method, Placement, SimParams};
use tetrasim::problem::Problem;
use tetrasim::sim::{build_model, load_mesh, BackendFactory, DEFAULT_MESH};

fn frames(c: &mut Criterion) {
    // The bundled copy when run from another folder than the repository's root.
    let mesh = load_mesh(std::path::Path::new(DEFAULT_MESH), None)
        .expect("bundled mesh meshes/sphere")
        .mesh;
    // Wall-clock timing: no GPU timestamps, no per-frame volume read-back.
    let mut backends = BackendFactory::new(EngineOptions {
        untimed: true,
        volume_on_demand: true,
        ..EngineOptions::default()
    });
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
            let problem = Problem::new(&model, &params).expect("valid parameters");
            let mut solver = backends.create(backend, &problem).expect("backend");
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
