//! The scene parser and the checkpoint reader on arbitrary bytes, as the fuzz targets
//! (`fuzz/`, `scripts/fuzz.sh`) and their regression test (`tests/fuzz_regressions.rs`) run
//! them: each entry point drops what it gets, so a panic, a hang or a runaway allocation is
//! the only failure. Files a scene names are replaced by the bundled box (objects) and its
//! surface (mesh colliders), so an input never reads the fuzzing machine's files.

use std::path::{Path, PathBuf};

use tetrasim::sim::Checkpoint;

use crate::launch::{stage, Staged};
use crate::scene::{Collider, Scene};

/// The most objects a fuzzed scene stages (each is the bundled box).
const MOST_OBJECTS: usize = 4;

/// The repository's `meshes/` folder (its bundled box and the box's surface).
fn meshes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes")
}

/// A scene file's text: parsed, validated and staged into a model, every object's mesh the
/// bundled box and every mesh collider the box's surface.
pub fn scene(data: &[u8]) {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = staged_on_the_box(text);
    }
}

/// What [`scene`] does with `text`: the scene parsed, its files replaced by the bundled box
/// and its surface (at most [`MOST_OBJECTS`] objects), validated and staged.
pub fn staged_on_the_box(text: &str) -> tetrasim::Result<Staged> {
    let mut scene = Scene::parse(text)?;
    scene.objects.truncate(MOST_OBJECTS);
    for object in &mut scene.objects {
        object.mesh = meshes().join("box");
        // Meshing a surface is the mesh preprocessor's job (its readers are fuzzed apart).
        object.target_tets = None;
    }
    for collider in &mut scene.colliders {
        if let Collider::Mesh { path, .. } = collider {
            *path = meshes().join("box_surface.off");
        }
    }
    scene.validate()?;
    stage(&scene)
}

/// A checkpoint's bytes, read and checked against the bundled box's default run.
pub fn checkpoint(data: &[u8]) {
    let Ok(checkpoint) = Checkpoint::from_bytes(data) else {
        return;
    };
    let text = format!("[[object]]\nmesh = {:?}\n", meshes().join("box"));
    let staged = Scene::parse(&text).and_then(|scene| stage(&scene));
    if let Ok(staged) = staged {
        let _ = checkpoint.check(&staged.model, &staged.params, checkpoint.backend());
    }
}

/// A fuzz target's entry point: the reader on arbitrary bytes.
pub type Target = fn(&[u8]);

/// Every entry point by the name of its fuzz target.
pub const TARGETS: [(&str, Target); 2] = [("scene", scene), ("checkpoint", checkpoint)];
