//! Materials in physical units and implicit springs from the command line and from scenes:
//! what is refused (with the flag or key named), what a run records, `--no-fit`, and
//! objects of one scene with different materials.

mod common;

use std::process::{Command, Output};

use common::ball_mesh;
use tetrasim::mesh::io::write_tetgen;
use tetrasim::metrics::RunRecord;
use tetrasim_cli::scene::Scene;

fn tetrasim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn contradictory_or_out_of_range_material_flags_are_refused() {
    for (args, needles) in [
        (&["--poisson-ratio", "0.4"][..], &["--youngs-modulus"][..]),
        (&["--damping", "0.01"][..], &["--youngs-modulus"][..]),
        (
            &["--youngs-modulus", "1e5", "--ks", "100"][..],
            &["--ks", "--youngs-modulus"][..],
        ),
        (
            &["--youngs-modulus", "1e5", "--poisson-ratio", "0.7"][..],
            &["poisson_ratio", "(-1, 0.5]"][..],
        ),
        (&["--youngs-modulus=-5"][..], &["youngs_modulus"][..]),
        (
            &["--youngs-modulus", "1e5", "--poisson-ratio", "0.3"][..],
            &["density", "1 kg per node"][..],
        ),
        (
            &["--springs", "implicit", "--method", "distance"][..],
            &["springs", "mss and volume"][..],
        ),
        (
            &["--springs", "implicit", "--solver", "chebyshev"][..],
            &["springs", "chebyshev"][..],
        ),
        (
            &["--no-fit", "--fit-size", "1"][..],
            &["--fit-size", "--no-fit"][..],
        ),
    ] {
        let out = tetrasim(&[&["run", "--frames", "1", "--quiet"][..], args].concat());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} was accepted");
        assert!(!stderr.contains("panicked"), "{stderr}");
        for needle in needles {
            assert!(
                stderr.contains(needle),
                "{args:?}: `{needle}` missing: {stderr}"
            );
        }
    }
}

#[test]
fn scenes_refuse_spring_constants_beside_a_youngs_modulus() {
    for (material, needle) in [
        (
            "{ youngs_modulus = 1e5, ks = 10.0 }",
            "give youngs_modulus or ks",
        ),
        ("{ poisson_ratio = 0.3 }", "poisson_ratio"),
    ] {
        let text = format!("[[object]]\nmesh = \"a\"\nmaterial = {material}\n");
        let err = Scene::parse(&text).unwrap_err().to_string();
        assert!(err.contains("object[0]") && err.contains(needle), "{err}");
    }
}

#[test]
fn a_material_run_records_it_and_does_not_warn_about_the_explicit_bound() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("m.json");
    let run = |springs: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
            .args(["run", "--quiet", "--method", "volume", "--frames", "20"])
            .args([
                "--fit-size",
                "0.1",
                "--youngs-modulus",
                "1e5",
                "--poisson-ratio",
                "0.45",
            ])
            .args(["--density", "1000", "--springs", springs, "--json"])
            .arg(&json)
            .output()
            .unwrap();
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    // The same material with the paper's explicit springs is far beyond their bound.
    assert!(run("explicit").contains("warning: dt exceeds"));
    let stderr = run("implicit");
    assert!(!stderr.contains("warning: dt exceeds"), "{stderr}");
    let records: Vec<RunRecord> =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let r = &records[0];
    assert!(!r.diverged, "{:?}", r.divergence);
    assert_eq!(r.params.springs.name(), "implicit");
    assert_eq!(
        (
            r.params.youngs_modulus,
            r.params.poisson_ratio,
            r.derived.damping
        ),
        (Some(1e5), Some(0.45), Some(0.003))
    );
    assert!(r.min_volume_pct > 99.0, "{}", r.min_volume_pct);
    // The material as it acted: the springs' stiffness from E, the mass from the density
    // (a ball of 0.1 m: about 0.52 kg), and no `ks`, `kd` that did not act.
    let [least, mean, most] = r.derived.spring_stiffness.expect("spring_stiffness");
    assert!(
        0.0 < least && least < mean && mean < most,
        "{least} {mean} {most}"
    );
    let mass = r.derived.mass_kg.expect("mass_kg");
    assert!((0.45..0.53).contains(&mass), "{mass} kg");
    let raw: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let params = raw[0]["params"].as_object().unwrap();
    assert!(
        !params.contains_key("ks") && !params.contains_key("kd"),
        "{params:?}"
    );
}

/// The finite elements have no springs: their run's header names their solve, not the
/// sweeps' solver and global volume, and no explicit bound is warned about.
#[test]
fn a_finite_element_run_names_its_solve_and_warns_of_no_spring_bound() {
    let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args(["run", "--quiet", "--method", "neo-hookean", "--frames", "5"])
        .args([
            "--fit-size",
            "0.1",
            "--youngs-modulus",
            "1e5",
            "--poisson-ratio",
            "0.45",
        ])
        .args(["--density", "1000"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("solver newton (conjugate gradients"),
        "{stderr}"
    );
    assert!(!stderr.contains("global volume"), "{stderr}");
    assert!(!stderr.contains("warning: dt exceeds"), "{stderr}");
}

/// `--no-fit` keeps the mesh's size and its X and Z; a drop height only lifts it.
#[test]
fn without_fitting_the_mesh_keeps_its_size_and_is_only_lifted() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    let mesh = ball_mesh(1.5);
    write_tetgen(&prefix, &mesh).unwrap();
    let text = format!(
        "[[object]]\nmesh = {:?}\ndrop_height = 0.25\n",
        prefix.display().to_string()
    );
    let scene = Scene::parse(&text).unwrap();
    let staged = tetrasim_cli::launch::stage(&scene).unwrap();
    let lowest = mesh.nodes.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    for (p, q) in mesh.nodes.iter().zip(&staged.model.positions) {
        assert_eq!((p.x, p.z), (q.x, q.z));
        assert!((q.y - (p.y - lowest + 0.25)).abs() < 1e-12);
    }
}

/// `offset` moves an object after `fit_size` and `drop_height`: every node by exactly the
/// offset, pin boxes see the moved object, and the recorded placement includes it (so
/// `--units input` still undoes it).
#[test]
fn an_offset_moves_the_placed_object_and_its_pin_box() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    write_tetgen(&prefix, &ball_mesh(1.5)).unwrap();
    let scene = |offset: &str| {
        let text = format!(
            "[[object]]\nmesh = {:?}\nfit_size = 0.5\ndrop_height = 0.1\noffset = {offset}\n\
             pin = {{ box = {{ min = [1.9, -5.0, -5.0], max = [3.0, 5.0, 5.0] }} }}\n",
            prefix.display().to_string()
        );
        tetrasim_cli::launch::stage(&Scene::parse(&text).unwrap()).unwrap()
    };
    let (still, moved) = (scene("[0.0, 0.0, 0.0]"), scene("[2.0, 0.5, -1.0]"));
    let shift = glam::DVec3::new(2.0, 0.5, -1.0);
    for (p, q) in still.model.positions.iter().zip(&moved.model.positions) {
        assert!((*q - *p - shift).length() < 1e-12);
    }
    // The box x >= 1.9 holds the moved ball's nodes with x >= -0.1 (before the move), none
    // of the unmoved ball's.
    assert!(still.model.inv_mass.iter().all(|&w| w > 0.0));
    let pinned = moved.model.inv_mass.iter().filter(|&&w| w == 0.0).count();
    let expected = still.model.positions.iter().filter(|p| p.x >= -0.1).count();
    assert_eq!(pinned, expected);
    let placement = moved.model.placements[0];
    let original = ball_mesh(1.5).nodes[7];
    assert!((placement.apply(original) - moved.model.positions[7]).length() < 1e-12);
    let err = Scene::parse("[[object]]\nmesh = \"a\"\noffset = [1.0, inf, 0.0]\n")
        .unwrap_err()
        .to_string();
    assert!(err.contains("object[0].offset"), "{err}");
}

/// Two objects, two materials: each model keeps its own per-spring stiffness, and the run
/// goes through (it used to be refused).
#[test]
fn objects_of_one_scene_may_have_different_materials() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    write_tetgen(&prefix, &ball_mesh(1.5)).unwrap();
    let text = format!(
        "[solver]\nsprings = \"implicit\"\nframes = 30\n\
         [[object]]\nmesh = {p:?}\nfit_size = 0.1\ndrop_height = 0.01\n\
         material = {{ youngs_modulus = 1e4, poisson_ratio = 0.45, density = 1000.0 }}\n\
         [[object]]\nmesh = {p:?}\nfit_size = 0.1\ndrop_height = 0.05\n\
         material = {{ youngs_modulus = 1e6, density = 1100.0 }}\n",
        p = prefix.display().to_string()
    );
    let path = dir.path().join("two.toml");
    std::fs::write(&path, text).unwrap();
    let scene = Scene::load(&path).unwrap();
    let staged = tetrasim_cli::launch::stage(&scene).unwrap();
    let material = staged.model.material.as_ref().unwrap();
    let half = material.spring_stiffness.len() / 2;
    let ratio = material.spring_stiffness[half] / material.spring_stiffness[0];
    assert!((ratio - 100.0).abs() < 1e-6, "stiffness ratio {ratio}");
    assert!(material.volume_compliance[0] > 0.0);
    assert_eq!(*material.volume_compliance.last().unwrap(), 0.0);
    let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args(["run", "--quiet", "--scene"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A material with the default explicit springs diverges at once; the advice names the
/// fixes that take the material (implicit springs, the finite elements) before a smaller
/// step, as the caller set the run: flags from flags, a scene's keys from a scene.
#[test]
fn divergence_advice_names_the_fix_in_the_callers_words() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    write_tetgen(&prefix, &ball_mesh(1.5)).unwrap();
    let mesh = prefix.display().to_string();
    let material = [
        "--youngs-modulus",
        "1e7",
        "--poisson-ratio",
        "0.3",
        "--density",
        "1000",
    ];
    let flags = tetrasim(
        &[
            &[
                "run",
                "--quiet",
                "--mesh",
                &mesh,
                "--method",
                "volume",
                "--fit-size",
                "0.1",
                "--frames",
                "100",
            ],
            &material[..],
        ]
        .concat(),
    );
    let scene = dir.path().join("stiff.toml");
    let text = format!(
        "[solver]\nframes = 100\n[[object]]\nmesh = {mesh:?}\nmethod = \"volume\"\n\
         fit_size = 0.1\nmaterial = {{ youngs_modulus = 1e7, poisson_ratio = 0.3, density = 1000.0 }}\n"
    );
    std::fs::write(&scene, text).unwrap();
    let keys = tetrasim(&["run", "--quiet", "--scene", scene.to_str().unwrap()]);
    for (out, names) in [
        (
            flags,
            ["`--springs implicit`", "`--method neo-hookean`", "`--dt "],
        ),
        (
            keys,
            [
                "`springs = \"implicit\"`",
                "`method = \"neo-hookean\"`",
                "`dt = ",
            ],
        ),
    ] {
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "{stderr}");
        for name in names {
            assert!(stderr.contains(name), "`{name}` missing: {stderr}");
        }
    }
}
