//! Stability at the extremes (docs/STABILITY.md, "Extreme cases"): every case runs on
//! `cpu-ref`, `cpu` and (when a Vulkan device exists) `vulkan`, on small meshes, and asserts
//! its documented outcome: bounded and finite with the volume inside a stated band, or a
//! clean divergence report (frame, method, first bad node, likely cause).

mod common;
mod gpu_support;

use common::{box_mesh, single_tet};
use glam::DVec3;
use tetrasim::mesh::TetMesh;
use tetrasim::metrics::RunRecord;
use tetrasim::params::{Method, Placement, SimParams};
use tetrasim::{Model, ModelBuilder};
use tetrasim_cli::runner::{run, RunOptions};

/// What a case must do.
#[derive(Debug, Clone, Copy)]
enum Outcome {
    /// No divergence; every frame's volume % in `[lo, hi]`.
    Bounded { lo: f64, hi: f64 },
    /// Like `Bounded`, and the last frame's volume % in `last`.
    Recovers { lo: f64, hi: f64, last: (f64, f64) },
    /// Stops with a divergence report before the last frame; `estimate` says whether the
    /// message must quote the stable-dt estimate as the likely cause.
    Diverges { estimate: bool },
}

struct Case {
    name: &'static str,
    model: Model,
    params: SimParams,
    frames: u32,
    outcome: Outcome,
    /// The same case with the feature under test switched off (constraints, or springs for
    /// `mss`), which must leave the volume band: proof that the case deforms the body.
    off: Option<SimParams>,
}

/// `model` set in uniform contraction at `rate` [1/s] about its centroid: without internal
/// forces its volume shrinks like `(1 - rate t)^3`, so every case that starts so deforms.
fn squeezed(mut model: Model, rate: f64) -> Model {
    let centre = model.positions.iter().sum::<DVec3>() / model.node_count() as f64;
    for (x, v) in model.positions.iter().zip(model.velocities.iter_mut()) {
        *v = (centre - *x) * rate;
    }
    model
}

/// The seed placement (largest side 1 m, 0.1 m above the floor).
fn seed(mesh: &TetMesh) -> Model {
    ModelBuilder::new(mesh).build().unwrap()
}

fn in_place(mesh: &TetMesh) -> Model {
    ModelBuilder::new(mesh)
        .placement(Placement {
            fit_size: None,
            drop_height: None,
        })
        .build()
        .unwrap()
}

fn params(method: Method) -> SimParams {
    SimParams {
        method,
        ..SimParams::default()
    }
}

fn cases() -> Vec<Case> {
    let cube = box_mesh([2, 2, 2]);
    let mut out = Vec::new();
    let mut add = |name, model, params, frames, outcome| {
        out.push(Case {
            name,
            model,
            params,
            frames,
            outcome,
            off: None,
        })
    };
    use Outcome::*;
    // Stiffness: ks 1 collapses onto the floor but the volume constraint holds the volume.
    add(
        "ks 1, volume",
        seed(&cube),
        SimParams {
            ks: 1.0,
            kd: 0.01,
            ..params(Method::Volume)
        },
        200,
        Bounded {
            lo: 99.0,
            hi: 100.5,
        },
    );
    // Squeezed at 10/s: springs-free it would lose 3 % in the 1 ms run.
    add(
        "ks 1e7, dt 1e-5",
        squeezed(seed(&cube), 10.0),
        SimParams {
            ks: 1e7,
            dt: 1e-5,
            ..params(Method::Mss)
        },
        100,
        Bounded {
            lo: 99.0,
            hi: 101.0,
        },
    );
    add(
        "ks 1e7, dt 1e-3",
        seed(&cube),
        SimParams {
            ks: 1e7,
            ..params(Method::Mss)
        },
        100,
        Diverges { estimate: true },
    );
    // Step size.
    // Squeezed at 10/s: without the constraint it would lose 1.5 % in the 0.5 ms run.
    add(
        "dt 1e-5, volume",
        squeezed(seed(&cube), 10.0),
        SimParams {
            dt: 1e-5,
            ..params(Method::Volume)
        },
        50,
        Bounded {
            lo: 99.9,
            hi: 100.1,
        },
    );
    add(
        "dt 1e-2, mss",
        seed(&cube),
        SimParams {
            dt: 1e-2,
            ..params(Method::Mss)
        },
        100,
        Diverges { estimate: true },
    );
    // Iterations.
    for (name, iterations) in [("iterations 1", 1), ("iterations 100", 100)] {
        add(
            name,
            seed(&cube),
            SimParams {
                iterations,
                ..params(Method::Volume)
            },
            200,
            Bounded {
                lo: 99.0,
                hi: 100.5,
            },
        );
    }
    // Mass ratio 1e4 between neighbouring nodes.
    let mut heavy = seed(&cube);
    for i in (0..heavy.node_count()).step_by(2) {
        heavy.mass[i] = 1e4;
        heavy.inv_mass[i] = 1e-4;
    }
    add(
        "mass ratio 1e4",
        heavy,
        params(Method::Volume),
        200,
        Bounded {
            lo: 95.0,
            hi: 100.5,
        },
    );
    // A sliver: one tet whose apex sits 1e-3 of its size above the base plane.
    let sliver = TetMesh {
        nodes: vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.3, 1e-3, 0.3),
        ],
        tets: vec![[0, 1, 2, 3]],
        faces: Vec::new(),
    };
    add(
        "sliver tet, volume",
        seed(&sliver),
        params(Method::Volume),
        200,
        // The floor flattens it on impact (0 %, never inverted); the constraint lifts it back.
        Recovers {
            lo: 0.0,
            hi: 100.01,
            last: (95.0, 101.0),
        },
    );
    // Initially inverted: the apex reflected through its base. Reflection keeps every edge
    // length, so springs alone keep it inverted (-100 %); the volume constraint restores it.
    let mut inverted = in_place(&single_tet());
    let flip = |m: &mut Model| {
        let [a, b, c, d] = m.tets[0].map(|i| i as usize);
        let (pa, pb, pc) = (m.positions[a], m.positions[b], m.positions[c]);
        let n = (pb - pa).cross(pc - pa).normalize();
        let h = (m.positions[d] - pa).dot(n);
        m.positions[d] -= 2.0 * h * n;
    };
    flip(&mut inverted);
    let free = SimParams {
        gravity: glam::DVec3::ZERO,
        floor: false,
        ..SimParams::default()
    };
    add(
        "inverted tet, mss",
        inverted.clone(),
        SimParams {
            method: Method::Mss,
            ..free.clone()
        },
        100,
        Bounded {
            lo: -100.1,
            hi: -99.9,
        },
    );
    add(
        "inverted tet, volume",
        inverted,
        SimParams {
            method: Method::Volume,
            ..free.clone()
        },
        100,
        // One step flips it (the first frame is already positive), it overshoots, and
        // settles near its rest volume.
        Recovers {
            lo: 0.0,
            hi: 160.0,
            last: (95.0, 101.0),
        },
    );
    add(
        "single tet, volume",
        seed(&single_tet()),
        params(Method::Volume),
        200,
        Bounded {
            lo: 99.0,
            hi: 100.5,
        },
    );
    let pinned_cube = seed(&cube);
    let all = 0..pinned_cube.node_count() as u32;
    add(
        "fully pinned",
        ModelBuilder::new(&cube).pinned(all).build().unwrap(),
        params(Method::Distance),
        50,
        Bounded {
            lo: 99.9999,
            hi: 100.0001,
        },
    );
    add(
        "zero gravity",
        squeezed(seed(&cube), 1.0),
        SimParams {
            gravity: glam::DVec3::ZERO,
            ..params(Method::Volume)
        },
        100,
        Bounded {
            lo: 99.9,
            hi: 100.1,
        },
    );
    // 1e4 m from the origin: f32 positions have a spacing of ~1e-3 m there.
    let far = ModelBuilder::new(&cube)
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(1e4),
        })
        .build()
        .map(|mut m| {
            for p in &mut m.positions {
                p.x += 1e4;
            }
            m
        })
        .unwrap();
    add(
        "far from origin (1e4 m)",
        squeezed(far, 1.0),
        params(Method::Volume),
        100,
        Bounded {
            lo: 99.9,
            hi: 100.1,
        },
    );
    for case in &mut out {
        case.off = match case.name {
            "ks 1e7, dt 1e-5" => Some(SimParams {
                ks: 0.0,
                kd: 0.0,
                ..case.params.clone()
            }),
            "dt 1e-5, volume" | "zero gravity" | "far from origin (1e4 m)" => Some(SimParams {
                method: Method::Mss,
                ..case.params.clone()
            }),
            _ => None,
        };
    }
    out
}

fn backends() -> Vec<&'static str> {
    let mut b = vec!["cpu-ref", "cpu"];
    if gpu_support::vulkan_available() {
        b.push("vulkan");
    }
    b
}

fn run_case(case: &Case, backend: &str) -> RunRecord {
    let options = RunOptions {
        backend: backend.into(),
        frames: case.frames,
        mesh_label: case.name.into(),
        progress: false,
        output: None,
        gpu: Default::default(),
        checkpoint: Default::default(),
    };
    run(&case.model, &case.params, &options).unwrap()
}

fn check(case: &Case, backend: &str, r: &RunRecord) -> Result<(), String> {
    let json = serde_json::to_string(r).unwrap();
    if json.contains("NaN") || json.contains("inf") {
        return Err(format!("non-finite JSON: {json}"));
    }
    let (lo, hi, last) = match case.outcome {
        Outcome::Bounded { lo, hi } => (lo, hi, None),
        Outcome::Recovers { lo, hi, last } => (lo, hi, Some(last)),
        Outcome::Diverges { .. } => (0.0, 0.0, None),
    };
    match case.outcome {
        Outcome::Bounded { .. } | Outcome::Recovers { .. } => {
            if r.diverged {
                return Err(format!("diverged: {:?}", r.divergence));
            }
            let min = r.volume_pct.iter().copied().fold(f64::INFINITY, f64::min);
            let max = r
                .volume_pct
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max);
            if r.frames_run != case.frames || min < lo || max > hi {
                return Err(format!(
                    "{backend}: volume {min:.4} .. {max:.4} % over {} frames, band [{lo}, {hi}]",
                    r.frames_run
                ));
            }
            let end = r.volume_pct.last().copied().unwrap_or(f64::NAN);
            if let Some((a, b)) = last {
                if !(a..=b).contains(&end) {
                    return Err(format!(
                        "{backend}: last volume {end:.4} % outside [{a}, {b}]"
                    ));
                }
            }
        }
        Outcome::Diverges { estimate } => {
            let d = r.divergence.as_deref().unwrap_or("");
            let method = format!("method {}", case.params.method);
            let ok = r.diverged
                && r.frames_run < case.frames
                && d.contains("diverged at frame")
                && d.contains(&method)
                && d.contains("first bad node")
                && (!estimate || d.contains("stable dt estimate"));
            if !ok {
                return Err(format!(
                    "expected a clean divergence report, got diverged {} after {} frames: {d}",
                    r.diverged, r.frames_run
                ));
            }
        }
    }
    Ok(())
}

#[test]
fn every_extreme_case_has_its_documented_outcome() {
    let mut failures = Vec::new();
    for case in cases() {
        for backend in backends() {
            let r = run_case(&case, backend);
            let min = r.volume_pct.iter().copied().fold(f64::INFINITY, f64::min);
            let max = r
                .volume_pct
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max);
            println!(
                "{:<26} {:<8} frames {:>4} diverged {:<5} volume {:>10.4} .. {:>10.4} % last {:>10.4} {}",
                case.name,
                backend,
                r.frames_run,
                r.diverged,
                min,
                max,
                r.volume_pct.last().copied().unwrap_or(0.0),
                r.divergence.as_deref().unwrap_or("")
            );
            if let Err(e) = check(&case, backend, &r) {
                failures.push(format!("{} on {backend}: {e}", case.name));
            }
        }
        if let Some(off) = &case.off {
            let switched_off = Case {
                params: off.clone(),
                model: case.model.clone(),
                off: None,
                ..case
            };
            let r = run_case(&switched_off, "cpu-ref");
            let min = r.volume_pct.iter().copied().fold(f64::INFINITY, f64::min);
            println!("{:<26} switched off: least volume {min:.4} %", case.name);
            if check(&switched_off, "cpu-ref", &r).is_ok() {
                failures.push(format!(
                    "{}: passes with the constraints (springs) switched off, so it proves nothing",
                    case.name
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn fully_pinned_mesh_does_not_move_at_all() {
    let cube = box_mesh([2, 2, 2]);
    let n = cube.nodes.len() as u32;
    let model = ModelBuilder::new(&cube).pinned(0..n).build().unwrap();
    for backend in backends() {
        let mut b =
            tetrasim::sim::create_backend(backend, &model, &params(Method::Volume)).unwrap();
        for _ in 0..20 {
            b.step_frame().unwrap();
        }
        let s = b.state().unwrap();
        for (p, q) in s.positions.iter().zip(&model.positions) {
            assert!(p.distance(*q) < 1e-6, "{backend}: {p} moved from {q}");
        }
        assert!(s.velocities.iter().all(|v| *v == DVec3::ZERO), "{backend}");
    }
}

#[test]
fn far_from_origin_falls_like_near_origin() {
    let cube = box_mesh([2, 2, 2]);
    let params = SimParams {
        floor: false,
        ..params(Method::Volume)
    };
    let drop_of = |backend: &str, offset: f64| {
        let mut model = seed(&cube);
        for p in &mut model.positions {
            *p += DVec3::splat(offset);
        }
        let mut b = tetrasim::sim::create_backend(backend, &model, &params).unwrap();
        for _ in 0..100 {
            b.step_frame().unwrap();
        }
        let s = b.state().unwrap();
        common::centre_of_mass(&model.positions, &model.mass).y
            - common::centre_of_mass(&s.positions, &model.mass).y
    };
    let reference = drop_of("cpu-ref", 0.0);
    // Symplectic Euler free fall over 100 steps: g dt^2 k (k + 1) / 2.
    assert!((reference - 9.81 * 1e-6 * 100.0 * 101.0 / 2.0).abs() < 1e-9);
    for backend in backends() {
        let (near, far) = (drop_of(backend, 0.0), drop_of(backend, 1e4));
        println!("{backend}: drop {near:.6} m near the origin, {far:.6} m at 1e4 m");
        assert!((near - reference).abs() < 1e-5, "{backend}: {near}");
        // f64 is exact at 1e4 m; f32 rounds positions there to ~1e-3 m, so the drop may
        // differ by about that much.
        let tolerance = if backend == "cpu-ref" { 1e-9 } else { 2e-3 };
        assert!((far - reference).abs() < tolerance, "{backend}: {far}");
    }
}
