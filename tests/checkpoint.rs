//! Checkpoints: a run saved at frame 30 and resumed in a new backend ends bit for bit where
//! the uninterrupted 60-frame run ends, with the same record series, on `cpu-ref` and `cpu`
//! (volume constraints under a moving collider and a clamp; the finite elements, whose
//! steps start from the last one's forces; warm-started implicit springs) and on `vulkan`
//! (its default solver, and the finite elements, whose forces and coarse level the
//! checkpoint carries from the device); and a truncated, corrupt or mismatched checkpoint
//! is refused, saying which.

mod gpu_support;

use std::path::Path;

use tetrasim::backend::Backend;
use tetrasim::sim::{create_backend, Checkpoint, Simulation};
use tetrasim_cli::launch::{stage, Staged};
use tetrasim_cli::scene::Scene;

const FRAMES: u32 = 60;
/// Not a multiple of `tetrasim::physics::COARSE_REBUILD_STEPS`: the finite elements'
/// coarse level the resumed run starts with is the one the checkpoint carried.
const SAVED_AT: u32 = 35;

fn mesh(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("meshes")
        .join(name);
    format!("{:?}", path.display().to_string())
}

/// A sphere pressed by a box collider that moves down, beside a bar held by a clamp that
/// moves (the colliders' and the clamps' clocks both matter).
fn springs_scene(extra: &str) -> Staged {
    let text = format!(
        "[solver]\nframes = {FRAMES}\n{extra}\n\
         [[object]]\nmesh = {}\nfit_size = 0.4\ndrop_height = 0.0\n\
         [[object]]\nmesh = {}\nfit_size = 0.5\ndrop_height = 0.3\noffset = [1.0, 0.0, 0.0]\n\
         pin = {{ box = {{ min = [0.7, 0.0, -1.0], max = [0.8, 1.0, 1.0] }}, motion = {{ \
         velocity = [0.0, 0.5, 0.0] }} }}\n\
         [[collider]]\ntype = \"floor\"\n\
         [[collider]]\ntype = \"box\"\ncenter = [0.0, 0.5, 0.0]\n\
         half_extents = [0.3, 0.05, 0.3]\nmotion = {{ velocity = [0.0, -1.0, 0.0] }}\n",
        mesh("sphere"),
        mesh("box"),
    );
    stage(&Scene::parse(&text).unwrap()).unwrap()
}

/// The bundled box of a soft material, dropped on the floor, with the finite elements.
fn elastic_scene() -> Staged {
    let text = format!(
        "[solver]\nframes = {FRAMES}\n[[object]]\nmesh = {}\nmethod = \"neo-hookean\"\n\
         fit_size = 0.2\ndrop_height = 0.01\nmaterial = {{ youngs_modulus = 1e5, \
         poisson_ratio = 0.45, density = 1000.0 }}\n[[collider]]\ntype = \"floor\"\n",
        mesh("box")
    );
    stage(&Scene::parse(&text).unwrap()).unwrap()
}

/// A run's end as bits: positions, velocities and the sampled volumes.
#[derive(Debug, PartialEq)]
struct End {
    positions: Vec<[u64; 3]>,
    velocities: Vec<[u64; 3]>,
    volumes: Vec<u64>,
    inverted: Vec<u32>,
}

fn end(backend: &mut dyn Backend, driver: &Simulation) -> End {
    let state = backend.state().unwrap();
    let bits = |v: &[glam::DVec3]| v.iter().map(|p| p.to_array().map(f64::to_bits)).collect();
    End {
        positions: bits(&state.positions),
        velocities: bits(&state.velocities),
        volumes: driver
            .series
            .volume_pct
            .iter()
            .map(|v| v.to_bits())
            .collect(),
        inverted: driver.series.inverted.clone(),
    }
}

fn new_backend(name: &str, staged: &Staged) -> Box<dyn Backend> {
    match name {
        "vulkan" => Box::new(gpu_support::validated(&staged.model, &staged.params)),
        _ => create_backend(name, &staged.model, &staged.params).unwrap(),
    }
}

fn advance(backend: &mut dyn Backend, driver: &mut Simulation, frames: u32) {
    for _ in 0..frames {
        driver.advance(backend, true).unwrap();
    }
    assert!(!driver.stopped(), "{:?}", driver.divergence);
}

/// The uninterrupted run's end, and the end of the run saved at [`SAVED_AT`] (through the
/// file's bytes) and resumed in a new backend and driver.
fn straight_and_resumed(name: &str, staged: &Staged) -> (End, End) {
    let (model, params) = (&staged.model, &staged.params);
    let mut backend = new_backend(name, staged);
    let mut driver = Simulation::new(model, params);
    advance(backend.as_mut(), &mut driver, FRAMES);
    let straight = end(backend.as_mut(), &driver);

    let mut backend = new_backend(name, staged);
    let mut driver = Simulation::new(model, params);
    advance(backend.as_mut(), &mut driver, SAVED_AT);
    let saved = Checkpoint::take(model, params, backend.as_mut(), &driver).unwrap();
    drop(backend);
    let bytes = saved.to_bytes().unwrap();
    let read = Checkpoint::from_bytes(&bytes).unwrap();
    assert_eq!(read.frames(), SAVED_AT);
    let mut backend = new_backend(name, staged);
    let mut driver = Simulation::new(model, params);
    read.resume(model, params, backend.as_mut(), &mut driver)
        .unwrap();
    advance(backend.as_mut(), &mut driver, FRAMES - SAVED_AT);
    (straight, end(backend.as_mut(), &driver))
}

#[test]
fn resumed_runs_end_bit_for_bit_where_uninterrupted_ones_do_on_the_cpu_backends() {
    for (label, staged) in [
        ("volume, collider and clamp", springs_scene("")),
        (
            "warm-started implicit springs",
            springs_scene("springs = \"implicit\"\nwarm_start = true"),
        ),
        ("neo-hookean", elastic_scene()),
    ] {
        for name in ["cpu-ref", "cpu"] {
            let (straight, resumed) = straight_and_resumed(name, &staged);
            assert_eq!(straight.volumes.len(), FRAMES as usize);
            let first = (straight.volumes.iter().zip(&resumed.volumes)).position(|(a, b)| a != b);
            let moved = (straight.positions.iter().zip(&resumed.positions))
                .filter(|(a, b)| a != b)
                .count();
            assert!(
                straight == resumed,
                "{label} on {name}: the resumed run differs (first volume at frame {first:?}, \
                 {moved} positions)"
            );
        }
    }
}

#[test]
fn resumed_runs_end_bit_for_bit_on_vulkan() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let staged = springs_scene("");
    let (straight, resumed) = straight_and_resumed("vulkan", &staged);
    assert!(straight == resumed, "the resumed vulkan run differs");
    let (straight, resumed) = straight_and_resumed("vulkan", &elastic_scene());
    assert!(
        straight == resumed,
        "the resumed neo-hookean vulkan run differs"
    );
    // Warm-started multipliers stay on the device: saving them is refused, not skipped.
    let warm = springs_scene("springs = \"implicit\"\nwarm_start = true");
    let mut backend = new_backend("vulkan", &warm);
    let driver = Simulation::new(&warm.model, &warm.params);
    let refused = Checkpoint::take(&warm.model, &warm.params, backend.as_mut(), &driver);
    let message = refused.unwrap_err().to_string();
    assert!(message.contains("warm-started"), "{message}");
}

/// A resume would fail if the checkpoint did not carry what it does: the same run resumed
/// from positions and velocities alone (`set_state`) leaves the uninterrupted run.
#[test]
fn the_state_alone_is_not_enough() {
    let staged = elastic_scene();
    let (model, params) = (&staged.model, &staged.params);
    let (straight, _) = straight_and_resumed("cpu", &staged);
    let mut backend = new_backend("cpu", &staged);
    let mut driver = Simulation::new(model, params);
    advance(backend.as_mut(), &mut driver, SAVED_AT);
    let state = backend.state().unwrap();
    let mut fresh = new_backend("cpu", &staged);
    fresh.set_state(&state).unwrap();
    advance(fresh.as_mut(), &mut driver, FRAMES - SAVED_AT);
    assert!(end(fresh.as_mut(), &driver).positions != straight.positions);
}

#[test]
fn bad_checkpoints_are_refused_saying_why() {
    let staged = springs_scene("");
    let (model, params) = (&staged.model, &staged.params);
    let mut backend = new_backend("cpu", &staged);
    let mut driver = Simulation::new(model, params);
    advance(backend.as_mut(), &mut driver, 5);
    let saved = Checkpoint::take(model, params, backend.as_mut(), &driver).unwrap();
    let bytes = saved.to_bytes().unwrap();
    let refused = |bytes: &[u8]| Checkpoint::from_bytes(bytes).unwrap_err();
    assert!(refused(&bytes[..bytes.len() - 9]).contains("truncated"));
    assert!(refused(&bytes[..40]).contains("truncated"));
    assert!(refused(b"solid cube\n").contains("not a tetrasim checkpoint"));
    let mut flipped = bytes.clone();
    let at = flipped.len() - 100;
    flipped[at] ^= 1;
    assert!(refused(&flipped).contains("checksum"));
    let mut newer = bytes.clone();
    newer[20] = 9;
    assert!(refused(&newer).contains("version 9"));

    let mismatch =
        |model, params, backend: &str| saved.check(model, params, backend).unwrap_err().to_string();
    assert!(mismatch(model, params, "cpu-ref").contains("saved by the cpu backend"));
    let other = elastic_scene();
    assert!(mismatch(&other.model, params, "cpu").contains("another mesh"));
    let mut moved = staged.model.clone();
    moved.positions[0].x += 1e-9;
    assert!(mismatch(&moved, params, "cpu").contains("another start"));
    let mut finer = params.clone();
    finer.dt = 5e-4;
    assert!(mismatch(model, &finer, "cpu").contains("another `dt`"));

    // A file: written whole, read back; a missing one names its path.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.ckpt");
    saved.write(&path).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), bytes);
    assert_eq!(Checkpoint::read(&path).unwrap().frames(), 5);
    let missing = Checkpoint::read(&dir.path().join("nope.ckpt")).unwrap_err();
    assert!(missing.to_string().contains("nope.ckpt"), "{missing}");
    std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
    let message = Checkpoint::read(&path).unwrap_err().to_string();
    assert!(
        message.contains("run.ckpt") && message.contains("truncated"),
        "{message}"
    );
}

/// The command line: `--checkpoint` at frame 300, `--resume` to 600, the same record as
/// the straight 600-frame run; `--resume` with a truncated file exits non-zero naming it.
#[test]
fn the_command_line_saves_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let run = |frames: &str, extra: &[&str], json: &str| {
        let method = if extra.contains(&"--method") {
            None
        } else {
            Some("volume")
        };
        std::process::Command::new(env!("CARGO_BIN_EXE_tetrasim"))
            .args(["run", "--quiet", "--backend", "cpu-ref"])
            .args(method.map(|m| ["--method", m]).into_iter().flatten())
            .args(["--frames", frames, "--json", json])
            .args(extra)
            .current_dir(dir.path())
            .output()
            .unwrap()
    };
    let volumes = |json: &str| -> Vec<f64> {
        let text = std::fs::read_to_string(dir.path().join(json)).unwrap();
        let records: Vec<tetrasim::metrics::RunRecord> = serde_json::from_str(&text).unwrap();
        records[0].volume_pct.clone()
    };
    assert!(run("600", &[], "straight.json").status.success());
    let saved = run(
        "300",
        &["--checkpoint", "ck/run.ckpt", "--checkpoint-every", "100"],
        "a.json",
    );
    assert!(
        saved.status.success(),
        "{}",
        String::from_utf8_lossy(&saved.stderr)
    );
    let resumed = run("600", &["--resume", "ck/run.ckpt"], "resumed.json");
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert_eq!(volumes("resumed.json"), volumes("straight.json"));
    assert_eq!(volumes("resumed.json").len(), 600);

    let bytes = std::fs::read(dir.path().join("ck/run.ckpt")).unwrap();
    std::fs::write(dir.path().join("short.ckpt"), &bytes[..bytes.len() - 1]).unwrap();
    let refused = run("600", &["--resume", "short.ckpt"], "b.json");
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success());
    assert!(
        stderr.contains("short.ckpt") && stderr.contains("truncated"),
        "{stderr}"
    );
    let done = run("300", &["--resume", "ck/run.ckpt"], "c.json");
    assert!(String::from_utf8_lossy(&done.stderr).contains("nothing left to run"));
    let all = run(
        "10",
        &["--method", "all", "--checkpoint", "x.ckpt"],
        "d.json",
    );
    let stderr = String::from_utf8_lossy(&all.stderr);
    assert!(
        !all.status.success() && stderr.contains("one method"),
        "{stderr}"
    );
}
