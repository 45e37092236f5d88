//! Scene files drive `run`, and the engine builds only what a scene needs: initial
//! velocities and pins reach every backend, several objects become one model, mixed
//! materials are refused, `plan` differs between a springs-only scene and a volume scene
//! with a floor, the plan equals what the Vulkan engine really allocates and records, and a
//! diverging scene exits with status 3 and still writes its metrics.

mod common;
mod gpu_support;

use std::path::Path;
use std::process::Command;

use common::box_mesh;
use glam::DVec3;
use tetrasim::backend::vulkan::plan::{BufferId, EnginePlan};
use tetrasim::backend::vulkan::{EngineOptions, VulkanBackend};
use tetrasim::mesh::io::write_tetgen;
use tetrasim::metrics::RunRecord;
use tetrasim::params::{Method, SimParams};
use tetrasim::problem::Problem;
use tetrasim::sim::create_backend;
use tetrasim::Backend;
use tetrasim_cli::launch::stage;
use tetrasim_cli::scene::Scene;

fn tetrasim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tetrasim"))
}

/// Writes a 2x2x2-cell box (edge 0.1 m) as `dir/box` and a scene with `body` around it.
fn scene_file(dir: &Path, name: &str, body: &str) -> std::path::PathBuf {
    write_tetgen(dir.join("box"), &box_mesh([2, 2, 2])).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, body).unwrap();
    path
}

const TWO_OBJECTS: &str = r#"
[solver]
gravity = 0.0
frames = 10
[[object]]
mesh = "box"
method = "mss"
pin = { box = { min = [-1, -1, -1], max = [1, 0.01, 1] } }
[[object]]
mesh = "box"
method = "mss"
drop_height = 2.0
velocity = [0.5, 0.0, -0.25]
"#;

#[test]
fn two_objects_with_pins_and_velocity_run_on_every_backend() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::load(&scene_file(dir.path(), "two.toml", TWO_OBJECTS)).unwrap();
    let staged = stage(&scene).unwrap();
    let m = &staged.model;
    let per = box_mesh([2, 2, 2]).nodes.len();
    assert_eq!(m.node_count(), 2 * per);
    assert_eq!(m.tets.len(), 2 * 48);
    // Object 0: the nine nodes of its bottom face (y = 0) are pinned; object 1 is free and
    // moving, object 0 at rest.
    assert_eq!(m.node_count() - m.free_node_count(), 9);
    assert!(m.velocities[..per].iter().all(|v| *v == DVec3::ZERO));
    assert!(m.velocities[per..]
        .iter()
        .all(|v| *v == DVec3::new(0.5, 0.0, -0.25)));
    // Object 1's indices are shifted past object 0's nodes.
    assert!(m.tets[48..].iter().flatten().all(|&i| i as usize >= per));
    assert!(m
        .springs
        .iter()
        .all(|s| ((s[0] as usize) < per) == ((s[1] as usize) < per)));

    let mut backends = vec!["cpu-ref", "cpu"];
    if gpu_support::vulkan_available() {
        backends.push("vulkan");
    }
    for name in backends {
        let mut b = create_backend(name, m, &staged.params).unwrap();
        for _ in 0..staged.frames {
            b.step_frame().unwrap();
        }
        let s = b.state().unwrap();
        let t = f64::from(staged.frames) * staged.params.dt;
        for i in 0..m.node_count() {
            // Springs at rest and no gravity: a rigid translation at the initial velocity.
            let expected = m.positions[i] + m.velocities[i] * t;
            assert!(
                s.positions[i].distance(expected) < 1e-5,
                "{name} node {i}: {} vs {expected}",
                s.positions[i]
            );
        }
    }
}

#[test]
fn objects_with_different_materials_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let text = TWO_OBJECTS.replacen("method = \"mss\"", "method = \"volume\"", 1);
    let scene = Scene::load(&scene_file(dir.path(), "mixed.toml", &text)).unwrap();
    let err = stage(&scene).unwrap_err().to_string();
    assert!(
        err.contains("`object[1]`") && err.contains("not supported yet"),
        "{err}"
    );
}

fn plan_of(text: &str) -> EnginePlan {
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::load(&scene_file(dir.path(), "s.toml", text)).unwrap();
    let staged = stage(&scene).unwrap();
    let problem = Problem::new(&staged.model, &staged.params).unwrap();
    EnginePlan::of_problem(&problem, 64, scene.output.json.is_some()).unwrap()
}

const SPRINGS_ONLY: &str = "[[object]]\nmesh = \"box\"\nmethod = \"mss\"\n";
const VOLUME_FLOOR: &str = "[[object]]\nmesh = \"box\"\nmethod = \"volume\"\n\
    [[collider]]\ntype = \"floor\"\n[output]\nmetrics = \"m.json\"\n";
const VOLUME_FLOOR_JACOBI: &str = "[solver]\nsolver = \"jacobi\"\n\
    [[object]]\nmesh = \"box\"\nmethod = \"volume\"\n\
    [[collider]]\ntype = \"floor\"\n[output]\nmetrics = \"m.json\"\n";

#[test]
fn springs_only_and_volume_with_floor_plan_differently() {
    let springs = plan_of(SPRINGS_ONLY);
    let volume = plan_of(VOLUME_FLOOR_JACOBI);
    assert_eq!(
        springs.pass_list(),
        ["spring_scatter", "integrate[no floor]", "check"]
    );
    assert_eq!(
        volume.pass_list(),
        [
            "spring_scatter",
            "10 x (volume, constraint_apply#sums[floor])",
            "integrate[floor]",
            "check",
            "volume_sum",
            "reactions"
        ]
    );
    // The Jacobi volume scene adds constraint sums (16 B/node), degrees (4 B/node), the
    // volume compliances and the volume multipliers (4 B/tet each), and copies the partials
    // (16 B per workgroup) every frame; with its records, the forces out's inputs (32 B/node,
    // a 4-byte placeholder in the springs' scene, which has no records), each node's clamp
    // (4 B) and their one workgroup's sum, copied too; both have the rest volumes and the
    // spring damping.
    let (n, t) = (27u64, 48u64);
    assert_eq!(
        volume.device_bytes() - springs.device_bytes(),
        16 * n + 4 * n + 4 * t + 4 * t + (32 * n - 4) + 4 * n + 16
    );
    assert_eq!(
        (springs.readback_bytes(), volume.readback_bytes()),
        (16, 16 + 16 + 16)
    );
    assert_eq!(
        (
            springs.dispatches_per_frame(),
            volume.dispatches_per_frame()
        ),
        (3, 1 + 20 + 1 + 1 + 1 + 1)
    );
    assert!(volume.bytes_per_frame() > 5 * springs.bytes_per_frame());

    // The default Gauss-Seidel solver: spring forces gathered, each iteration's two passes
    // once per colour group and then the global volume constraint (its chunks' sums, then
    // the multiplier applied), the gather path's buffers instead of the atomic sums.
    let gs = plan_of(VOLUME_FLOOR);
    let k = u64::from(gs.schedule.group_count());
    assert!(k > 1 && k <= 8, "{k} groups");
    assert_eq!(gs.schedule.sweeps[0].constraints(), t);
    assert_eq!(
        gs.pass_list(),
        [
            "spring_gather".to_string(),
            "global_volume_prepare".into(),
            format!(
                "10 x ({k} groups x (volume#gather, constraint_apply#gather[floor]), \
                 global_volume_sum, global_volume[floor])"
            ),
            "integrate[floor]".into(),
            "check".into(),
            "volume_sum".into(),
            "reactions".into()
        ]
    );
    assert_eq!(
        gs.dispatches_per_frame() as u64,
        1 + 1 + 10 * (2 * k + 2) + 1 + 1 + 1 + 1
    );
    let global = gs.global.unwrap();
    assert_eq!((global.objects, global.nodes), (1, 26));
    assert_eq!(
        gs.buffer(BufferId::SurfaceFaces).map(|b| b.bytes),
        Some(16 * u64::from(global.faces))
    );
    let gathered = [
        (BufferId::Degrees, 4 * k * n),
        (BufferId::GroupMembers, 4 * t),
        (BufferId::Contributions, 16 * 4 * t),
        (BufferId::NodeSlotOffsets, 4 * (k * n + 1)),
        (BufferId::NodeSlotItems, 4 * 4 * t),
    ];
    for (id, bytes) in gathered {
        assert_eq!(gs.buffer(id).map(|b| b.bytes), Some(bytes), "{id:?}");
    }
    assert!(!gs.has(BufferId::ConstraintSum));
}

#[test]
fn solver_keys_the_solver_does_not_use_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (text, key) in [
        (
            "[solver]\nsolver = \"jacobi\"\ngroups = 4\n",
            "solver.groups",
        ),
        ("[solver]\nrho = 0.9\n", "solver.rho"),
    ] {
        let text = format!("{text}[[object]]\nmesh = \"box\"\n");
        let err = Scene::load(&scene_file(dir.path(), "s.toml", &text))
            .unwrap_err()
            .to_string();
        assert!(err.contains(key) && err.contains("acts only with"), "{err}");
    }
    let ok = "[solver]\nsolver = \"chebyshev\"\nrho = 0.9\n[[object]]\nmesh = \"box\"\n";
    let scene = Scene::load(&scene_file(dir.path(), "ok.toml", ok)).unwrap();
    assert_eq!(scene.params_for(0).rho, 0.9);
}

#[test]
fn plan_cli_prints_the_pass_lists() {
    let dir = tempfile::tempdir().unwrap();
    let a = scene_file(dir.path(), "a.toml", SPRINGS_ONLY);
    let b = scene_file(dir.path(), "b.toml", VOLUME_FLOOR);
    let print = |p: &Path| {
        let out = tetrasim()
            .arg("plan")
            .arg("--scene")
            .arg(p)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    };
    let c = scene_file(dir.path(), "c.toml", VOLUME_FLOOR_JACOBI);
    let (a, b, c) = (print(&a), print(&b), print(&c));
    assert!(
        a.contains("per time step: spring_scatter -> integrate[no floor]\n"),
        "{a}"
    );
    assert!(
        b.contains("per time step: spring_gather -> global_volume_prepare -> 10 x (")
            && b.contains(
                " groups x (volume#gather, constraint_apply#gather[floor]), global_volume_sum, \
                 global_volume[floor]) -> integrate[floor]\n"
            ),
        "{b}"
    );
    assert!(
        c.contains(
            "per time step: spring_scatter -> 10 x (volume, constraint_apply#sums[floor]) -> integrate[floor]\n"
        ),
        "{c}"
    );
    assert!(!a.contains("constraint degrees") && b.contains("group members"));
    assert!(c.contains("constraint sums") && !c.contains("group members"));
}

#[test]
fn the_engine_builds_and_records_exactly_the_plan() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = gpu_support::box_model([3, 2, 2], 0.1);
    for method in Method::ALL {
        for (floor, on_demand) in [(true, false), (false, true)] {
            let params = SimParams {
                method,
                floor,
                ..SimParams::default()
            };
            let options = EngineOptions {
                validation: true,
                volume_on_demand: on_demand,
                ..Default::default()
            };
            let mut gpu = VulkanBackend::new(&model, &params, &options).unwrap();
            let plan = gpu.plan().clone();
            assert_eq!(gpu.device_bytes(), plan.device_bytes(), "{method}");
            assert_eq!(plan.has_pass("volume_sum"), !on_demand);
            gpu.step_frame().unwrap();
            let mut timed: Vec<String> = gpu
                .pass_times()
                .unwrap()
                .into_iter()
                .map(|p| p.name)
                .collect();
            let mut planned: Vec<String> =
                plan.passes.iter().map(|p| p.name().to_string()).collect();
            if !timed.is_empty() {
                timed.sort();
                planned.sort();
                assert_eq!(timed, planned, "{method} floor {floor}");
            }
            // The volume is right either way (on demand: measured now).
            let v = gpu.volume().unwrap();
            assert!((v.volume / model.total_rest_volume() - 1.0).abs() < 1e-3);
            gpu_support::assert_no_validation_messages(&gpu);
        }
    }
}

#[test]
fn diverging_scene_exits_3_and_writes_finite_metrics() {
    let dir = tempfile::tempdir().unwrap();
    let text = "[solver]\ndt = 0.02\nframes = 200\n[[object]]\nmesh = \"box\"\nmethod = \"mss\"\n\
                fit_size = 1.0\n[output]\nmetrics = \"m.json\"\n";
    let scene = scene_file(dir.path(), "d.toml", text);
    let out = tetrasim()
        .args(["run", "--quiet", "--backend", "cpu", "--scene"])
        .arg(&scene)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("warning: dt exceeds"), "{stderr}");
    for needle in [
        "diverged at frame",
        "substep",
        "method mss",
        "first bad node",
        "stable dt estimate",
    ] {
        assert!(stderr.contains(needle), "`{needle}` missing: {stderr}");
    }
    let json = std::fs::read_to_string(dir.path().join("m.json")).unwrap();
    assert!(!json.contains("NaN") && !json.contains("inf"), "{json}");
    let records: Vec<RunRecord> = serde_json::from_str(&json).unwrap();
    assert!(records[0].diverged && records[0].frames_run < 200);
    assert!(records[0].min_volume_pct.is_finite());
}
