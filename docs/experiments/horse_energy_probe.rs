//! The horse drop's energy, frame by frame (docs/PHYSICS.md, "Projected Newton and a trust in
//! `dF`"): copy to tests/, build the quality-0 horse at /tmp/horse/horse86m (tetprep
//! ../shared/meshes/horse.ply --preserve-surface --quality 0) and run
//! `ITERS=10 DROP=0.01 cargo test --release -p tetrasim-cli --test horse_energy_probe -- --ignored --nocapture`.

use glam::DVec3;
use tetrasim::backend::cpu::ParallelBackend;
use tetrasim::mesh::io::read_tet_mesh;
use tetrasim::params::{MassMode, Method, Placement, SpringKind};
use tetrasim::physics::{elastic_energy, lame, shape_gradients, stable_neo_hookean, ElasticTet};
use tetrasim::{Backend, ModelBuilder, SimParams};

#[test]
#[ignore]
fn probe() {
    let iters: u32 = std::env::var("ITERS").map(|s| s.parse().unwrap()).unwrap_or(10);
    let drop: f64 = std::env::var("DROP").map(|s| s.parse().unwrap()).unwrap_or(0.01);
    let frames: usize = std::env::var("FRAMES").map(|s| s.parse().unwrap()).unwrap_or(160);
    let params = SimParams {
        method: Method::NeoHookean,
        springs: SpringKind::Explicit,
        youngs_modulus: Some(1e5),
        poisson_ratio: Some(0.45),
        mass: MassMode::Density { density: 1050.0 },
        floor: true,
        iterations: iters,
        ..SimParams::default()
    };
    let mesh = read_tet_mesh(std::path::Path::new("/tmp/horse/horse86m")).unwrap();
    let placement = Placement { fit_size: None, drop_height: Some(drop) };
    let model = (ModelBuilder::new(&mesh).placement(placement)).material(&params).build().unwrap();
    let (mu, lambda) = lame(1e5, 0.45);
    let (mu_s, lambda_s, alpha) = stable_neo_hookean(mu, lambda);
    let tets: Vec<ElasticTet<f64>> = model.tets.iter().enumerate().map(|(t, tet)| {
        let p = tet.map(|i| model.positions[i as usize]);
        ElasticTet { shape: shape_gradients(p).unwrap_or([[0.0; 3]; 3]), volume: model.rest_volume[t], mu: mu_s, lambda: lambda_s, alpha }
    }).collect();
    let mut solver = ParallelBackend::new(&model, &params).unwrap();
    for frame in 0..frames {
        solver.step_frame().unwrap();
        if frame % 5 == 0 {
            let s = solver.state().unwrap();
            let m = &model.mass;
            let ke: f64 = s.velocities.iter().zip(m).map(|(v, m)| 0.5 * m * v.length_squared()).sum();
            let pe: f64 = s.positions.iter().zip(m).map(|(x, m)| m * 9.81 * x.y).sum();
            let el: f64 = model.tets.iter().zip(&tets).map(|(tet, t)| elastic_energy(t, tet.map(|k| s.positions[k as usize]))).sum();
            let mass: f64 = m.iter().sum();
            let p: DVec3 = s.velocities.iter().zip(m).map(|(v, m)| *v * *m).sum();
            let c: DVec3 = s.positions.iter().zip(m).map(|(x, m)| *x * *m).sum::<DVec3>() / mass;
            let l: DVec3 = s.positions.iter().zip(&s.velocities).zip(m).map(|((x, v), m)| (*x - c).cross(*v * *m)).sum();
            let vol = solver.volume().unwrap();
            println!("{frame:4} total {:.5} ke {:.5} pe {:.5} el {:.5} vcm {:.4} L {:.3e} vol {:.3}", ke + pe + el, ke, pe, el, p.y / mass, l.length(), 100.0 * vol.volume / model.rest_volume.iter().sum::<f64>());
        }
    }
}
