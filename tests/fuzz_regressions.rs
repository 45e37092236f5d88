//! The fuzz targets' inputs replayed on stable (`fuzz/`, `scripts/fuzz.sh`): every input a
//! target once failed on (`fuzz/regressions/TARGET/`) and the fixtures the corpora are seeded
//! from, through the same entry points (`tetmesh::mesh::io::fuzzing` for the mesh readers
//! and the Python layer's array checks, `tetrascene::fuzzing` for scenes and checkpoints).
//! Each must come back (read or refused) without a panic and within the fuzzers' 10 s per
//! input.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use tetrasim::mesh::io::fuzzing::{self, TARGETS, TETGEN_SEPARATOR};

/// The system allocator, noting the largest single request: the fuzzers refuse an input
/// that asks for more than 2 GiB at once, and so does the replay.
struct Largest;

static LARGEST: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is passed on to the system allocator unchanged.
unsafe impl GlobalAlloc for Largest {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's promise, passed on.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's promise, passed on.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Largest = Largest;

/// The most one input may ask for at once (the fuzzers' `-malloc_limit_mb=2048`).
const MOST_BYTES: usize = 2 << 30;

/// The files in `dir` (none if it does not exist), sorted.
fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.is_file() && p.extension().map_or(true, |e| e != "md"));
    files.sort();
    files
}

/// Runs `target` on `data`, failing the test on a panic, a request for more than 2 GiB at
/// once or more than 10 s.
fn replay(name: &str, target: fn(&[u8]), data: &[u8], what: &str) {
    let start = Instant::now();
    let outcome = std::panic::catch_unwind(|| target(data));
    assert!(outcome.is_ok(), "fuzz target {name} panicked on {what}");
    let largest = LARGEST.load(Ordering::Relaxed);
    assert!(
        largest <= MOST_BYTES,
        "fuzz target {name} asked for {largest} bytes at once on {what}"
    );
    let took = start.elapsed();
    assert!(
        took < Duration::from_secs(10),
        "fuzz target {name} took {took:?} on {what}"
    );
}

#[test]
fn inputs_the_fuzzers_failed_on_are_read_or_refused() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut replayed = 0;
    for (name, target) in TARGETS.into_iter().chain(tetrascene::fuzzing::TARGETS) {
        for file in files_in(&root.join("fuzz/regressions").join(name)) {
            let data = std::fs::read(&file).unwrap();
            replay(name, target, &data, &file.display().to_string());
            replayed += 1;
        }
    }
    println!("{replayed} regression inputs replayed");
}

/// The seeds: every tet fixture through the format-picking and sniffing targets, and the
/// bundled TetGen meshes through the TetGen target, each also cut short at every 97th byte
/// (a truncated file). The valid ones must still read: a harness that dropped its input
/// would pass the replay above vacuously.
#[test]
fn the_seed_fixtures_go_through_every_target() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let fixtures = files_in(&root.join("tests/data/meshio"));
    let tet: Vec<PathBuf> = fixtures
        .into_iter()
        .filter(|p| {
            p.extension()
                .is_some_and(|e| ["vtk", "vtu", "msh", "mesh"].contains(&e.to_str().unwrap_or("")))
        })
        .collect();
    assert!(tet.len() >= 10, "{tet:?}");
    for file in &tet {
        let data = std::fs::read(file).unwrap();
        let what = file.display().to_string();
        let format = tetrasim::mesh::io::TetFormat::sniff(&data);
        assert!(format.is_some(), "{what}: no format sniffed");
        for cut in (0..data.len()).step_by(97) {
            replay("sniffed", fuzzing::sniffed, &data[..cut], &what);
            for pick in 0..4u8 {
                let picked: Vec<u8> = [&[pick][..], &data[..cut]].concat();
                replay("tet_mesh", fuzzing::tet_mesh, &picked, &what);
                replay("surface", fuzzing::surface, &picked, &what);
            }
        }
    }
    for prefix in ["meshes/box", "meshes/sphere", "meshes/torus"] {
        let read = |ext: &str| std::fs::read(root.join(format!("{prefix}.{ext}"))).unwrap();
        let data = [read("node"), read("ele"), read("face")].join(&TETGEN_SEPARATOR);
        let whole = tetrasim::mesh::io::tetgen::parse_tetgen(
            &read("node"),
            &read("ele"),
            Some(&read("face")),
            Path::new(prefix),
        );
        assert!(whole.is_ok(), "{prefix}: {whole:?}");
        for cut in (0..data.len()).step_by(997) {
            replay("tetgen", fuzzing::tetgen, &data[..cut], prefix);
        }
    }
}

/// The example scenes through the scene target, whole (each must stage: a harness that
/// refused them would pass vacuously) and cut short at every 31st byte.
#[test]
fn the_example_scenes_go_through_the_scene_target() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scenes: Vec<PathBuf> = files_in(&root.join("examples/scenes"))
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    assert!(scenes.len() >= 5, "{scenes:?}");
    let mut staged = 0;
    for file in &scenes {
        let text = std::fs::read_to_string(file).unwrap();
        let what = file.display().to_string();
        // On the box, a pin placed for the scene's own mesh may hold no node: refused.
        match tetrascene::fuzzing::staged_on_the_box(&text) {
            Ok(_) => staged += 1,
            Err(e) => println!("{what} on the box: {e}"),
        }
        for cut in (0..text.len()).step_by(31) {
            replay(
                "scene",
                tetrascene::fuzzing::scene,
                &text.as_bytes()[..cut],
                &what,
            );
        }
    }
    assert!(
        staged + 1 >= scenes.len(),
        "only {staged} of {} scenes staged",
        scenes.len()
    );
}

/// A checkpoint of the bundled box, whole (it must pass the target's check against the
/// box's default run) and cut short or with a byte flipped at every 53rd byte.
#[test]
fn a_checkpoint_goes_through_the_checkpoint_target() {
    use tetrasim::sim::{create_backend, Checkpoint, Simulation};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = format!("[[object]]\nmesh = {:?}\n", root.join("meshes/box"));
    let scene = tetrascene::scene::Scene::parse(&text).unwrap();
    let staged = tetrascene::launch::stage(&scene).unwrap();
    let (model, params) = (&staged.model, &staged.params);
    let mut backend = create_backend("cpu", model, params).unwrap();
    let mut sim = Simulation::new(model, params);
    sim.advance_frames(backend.as_mut(), 3, &|_| true, &mut |_| {})
        .unwrap();
    let taken = Checkpoint::take(model, params, backend.as_mut(), &sim).unwrap();
    let bytes = taken.to_bytes().unwrap();
    let read = Checkpoint::from_bytes(&bytes).unwrap();
    assert!(read.check(model, params, read.backend()).is_ok());
    for at in (0..bytes.len()).step_by(53) {
        replay(
            "checkpoint",
            tetrascene::fuzzing::checkpoint,
            &bytes[..at],
            "a cut checkpoint",
        );
        let mut flipped = bytes.clone();
        flipped[at] ^= 0x5A;
        replay(
            "checkpoint",
            tetrascene::fuzzing::checkpoint,
            &flipped,
            "a flipped checkpoint",
        );
    }
}

/// The bundled box as the `arrays` target reads arrays: whole, it must come back as the
/// box (a harness that refused it would pass vacuously); cut short at every 101st byte or
/// with a byte flipped there, it must be read or refused without a panic.
#[test]
fn the_box_goes_through_the_arrays_target() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mesh = tetrasim::mesh::io::read_tet_mesh(&root.join("meshes/box")).unwrap();
    let data = fuzzing::arrays_input(&mesh);
    let read = fuzzing::arrays_mesh(&data).expect("the box's arrays pass the checks");
    assert_eq!((read.nodes, read.tets), (mesh.nodes, mesh.tets));
    for at in (0..data.len()).step_by(101) {
        replay("arrays", fuzzing::arrays, &data[..at], "cut arrays");
        let mut flipped = data.clone();
        flipped[at] ^= 0xA5;
        replay("arrays", fuzzing::arrays, &flipped, "flipped arrays");
    }
}
