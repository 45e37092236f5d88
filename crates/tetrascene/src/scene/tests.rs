use super::*;
use tetrasim::params::MassMode;

const MINIMAL: &str = "[[object]]\nmesh = \"meshes/sphere\"\n";

#[test]
fn minimal_scene_gets_seed_defaults_without_floor() {
    let scene = Scene::parse(MINIMAL).unwrap();
    let p = scene.params_for(0);
    assert_eq!((p.dt, p.iterations, p.ks, p.kd), (1e-3, 10, 5000.0, 15.0));
    assert!(!p.floor, "no collider means no floor");
    assert_eq!(scene.frames(), 400);
    assert_eq!(
        scene.placement_for(0),
        Placement {
            fit_size: None,
            drop_height: None
        }
    );
}

#[test]
fn full_scene_maps_onto_params() {
    let text = r#"
        [solver]
        dt = 0.0005
        substeps = 2
        iterations = 5
        contact = "split"
        [[object]]
        mesh = "a"
        method = "distance"
        material = { ks = 100.0, kd = 1.0, density = 1000.0 }
        pin = { nodes = [3], box = { min = [0, 0, 0], max = [1, 1, 1] } }
        [[collider]]
        type = "floor"
        friction = 0.5
    "#;
    let scene = Scene::parse(text).unwrap();
    let p = scene.params_for(0);
    assert_eq!(
        (p.dt, p.substeps, p.iterations, p.ks, p.kd),
        (0.0005, 2, 5, 100.0, 1.0)
    );
    assert_eq!(p.method, Method::Distance);
    assert_eq!(p.contact, tetrasim::params::ContactMode::Split);
    assert_eq!(p.mass, MassMode::Density { density: 1000.0 });
    assert!(p.floor);
    assert_eq!(p.friction, 0.5);
    assert!(scene.objects[0].pin.pins[0]
        .region
        .unwrap()
        .contains(DVec3::splat(0.5)));
}

/// An object that names no method: the finite elements for a material given by its Young's
/// modulus, `volume` when it asks for springs or has no modulus, and a named method kept.
#[test]
fn a_material_given_by_its_modulus_runs_the_finite_elements_unless_told_otherwise() {
    let material = "material = { youngs_modulus = 1e5, poisson_ratio = 0.45, density = 1000.0 }";
    let method = |solver: &str, object: &str| {
        let text = format!("[solver]\n{solver}\n[[object]]\nmesh = \"a\"\n{object}\n");
        Scene::parse(&text).unwrap().params_for(0).method
    };
    assert_eq!(method("", material), Method::NeoHookean);
    assert_eq!(method("", ""), Method::Volume);
    assert_eq!(method("springs = \"implicit\"", material), Method::Volume);
    assert_eq!(method("solver = \"jacobi\"", material), Method::Volume);
    let named = format!("method = \"mss\"\n{material}");
    assert_eq!(method("", &named), Method::Mss);
}

#[test]
fn unknown_key_names_its_path() {
    let err = Scene::parse("[[object]]\nmesh = \"a\"\nmaterial = { kss = 1.0 }\n")
        .unwrap_err()
        .to_string();
    assert!(err.contains("object[0].material"), "{err}");
    assert!(err.contains("kss"), "{err}");
    assert!(err.contains("line 3"), "{err}");
}

#[test]
fn out_of_range_values_name_their_key() {
    for (text, key) in [
        (
            "[solver]\ndt = -1.0\n[[object]]\nmesh = \"a\"\n",
            "solver.dt",
        ),
        (
            "[solver]\ncontact = \"split\"\nwarm_start = true\nsprings = \"implicit\"\n[[object]]\nmesh = \"a\"\n",
            "solver.contact",
        ),
        (
            "[[object]]\nmesh = \"a\"\nmaterial = { ks = -5.0 }\n",
            "object[0].material.ks",
        ),
        (
            "[[object]]\nmesh = \"a\"\n[[collider]]\ntype = \"floor\"\nfriction = 2.0\n",
            "collider.friction",
        ),
        (
            "[[object]]\nmesh = \"a\"\npin = { box = { min = [1, 0, 0], max = [0, 1, 1] } }\n",
            "object[0].pin.box",
        ),
        (
            "[solver]\nframes = 0\n[[object]]\nmesh = \"a\"\n",
            "solver.frames",
        ),
        ("[solver]\n", "object"),
        (
            "[solver]\ngroups = 0\n[[object]]\nmesh = \"a\"\n",
            "solver.groups",
        ),
        (
            "[solver]\nsolver = \"chebyshev\"\nrho = 1.5\n[[object]]\nmesh = \"a\"\n",
            "solver.rho",
        ),
        (
            "[[object]]\nmesh = \"a\"\nmaterial = { density = -1.0 }\n",
            "object[0].material.density",
        ),
        (
            "[[object]]\nmesh = \"a\"\noffset = [0.0, nan, 0.0]\n",
            "object[0].offset",
        ),
    ] {
        let err = Scene::parse(text).unwrap_err().to_string();
        assert!(
            err.contains(&format!("`{key}`")),
            "expected key {key} in: {err}"
        );
    }
}

#[test]
fn wrong_type_names_its_path() {
    let err = Scene::parse("[solver]\niterations = \"ten\"\n[[object]]\nmesh = \"a\"\n")
        .unwrap_err()
        .to_string();
    assert!(err.contains("solver.iterations"), "{err}");
}
