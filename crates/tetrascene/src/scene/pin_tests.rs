//! `self_contact` and `pin` on `[[object]]`: one pin table or a list of them, each fixed or
//! moving with a `motion`, and what is refused (with the key's path: `object[0].pin.motion`,
//! `object[0].pin[1].motion.keyframes[2].t`).

use glam::DVec3;
use tetrasim::collider::Motion;

use super::*;

/// A one-object scene whose object has these extra lines.
fn object(lines: &str) -> String {
    format!("[[object]]\nmesh = \"a\"\n{lines}\n")
}

/// The error of parsing an object with these lines.
fn refused(lines: &str) -> String {
    Scene::parse(&object(lines)).unwrap_err().to_string()
}

#[test]
fn self_contact_defaults_to_off_and_is_read() {
    let off = Scene::parse(&object("")).unwrap();
    assert!(!off.objects[0].self_contact);
    assert!(off.objects[0].pin.pins.is_empty());
    let on = Scene::parse(&object("self_contact = true")).unwrap();
    assert!(on.objects[0].self_contact);
}

#[test]
fn one_pin_table_with_keyframes_or_velocities() {
    let scene = Scene::parse(&object(
        "pin = { nodes = [1, 2], motion = { keyframes = [{ t = 0.0 }, \
         { t = 0.5, position = [0.3, 0, 0], rotation = [0.7071068, 0.7071068, 0, 0] }] } }",
    ))
    .unwrap();
    let pins = &scene.objects[0].pin;
    assert!(!pins.list);
    assert_eq!(pins.pins.len(), 1);
    assert_eq!(pins.pins[0].nodes, [1, 2]);
    assert_eq!(pins.key(0, 0), "object[0].pin");
    let motion = pins.pins[0].motion.as_ref().unwrap().motion("m").unwrap();
    let Motion::Keyframes(keys) = motion else {
        panic!("keyframes: {motion:?}")
    };
    assert_eq!(keys[1].position, DVec3::new(0.3, 0.0, 0.0));
    assert!(
        (keys[1].rotation.length() - 1.0).abs() < 1e-12,
        "normalised"
    );

    let scene = Scene::parse(&object(
        "pin = { box = { min = [0, 0, 0], max = [1, 1, 1] }, \
         motion = { velocity = [0, 0.1, 0], angular_velocity = [0, 0, 1] } }",
    ))
    .unwrap();
    let motion = scene.objects[0].pin.pins[0].motion.as_ref().unwrap();
    assert_eq!(
        motion.motion("m").unwrap(),
        Motion::Velocity {
            linear: DVec3::new(0.0, 0.1, 0.0),
            angular: DVec3::new(0.0, 0.0, 1.0),
        }
    );
}

#[test]
fn a_list_of_pins_inline_or_as_tables() {
    let inline = Scene::parse(&object(
        "pin = [{ nodes = [0] }, { nodes = [9], motion = { velocity = [1, 0, 0] } }]",
    ))
    .unwrap();
    let tables = Scene::parse(&object(
        "[[object.pin]]\nnodes = [0]\n[[object.pin]]\nnodes = [9]\n\
         motion = { velocity = [1, 0, 0] }",
    ))
    .unwrap();
    assert_eq!(inline, tables);
    let pins = &inline.objects[0].pin;
    assert!(pins.list);
    assert_eq!(pins.pins.len(), 2);
    assert!(pins.pins[0].motion.is_none());
    assert_eq!(pins.key(0, 1), "object[0].pin[1]");
}

#[test]
fn bad_pins_name_their_key() {
    for (lines, needles) in [
        (
            "pin = { nodes = [0], motion = { keyframes = [{ t = 0.5 }, { t = 0.2 }] } }",
            &["`object[0].pin.motion.keyframes[1].t`", "increasing time"][..],
        ),
        (
            "pin = [{ nodes = [0] }, { nodes = [1], motion = { keyframes = [{ t = 0.0 }, \
             { t = 1.0, rotation = [0.5, 0.5, 0, 0] }] } }]",
            &[
                "`object[0].pin[1].motion.keyframes[1].rotation`",
                "unit quaternion",
            ][..],
        ),
        (
            "pin = { motion = { velocity = [0, 1, 0] } }",
            &["`object[0].pin.motion`", "moves no node"][..],
        ),
        (
            "pin = [{ nodes = [0] }, { motion = { velocity = [0, 1, 0] } }]",
            &["`object[0].pin[1].motion`", "moves no node"][..],
        ),
        (
            "pin = { nodes = [0], motion = { velocity = [0, 1, 0], keyframes = [{ t = 0.0 }] } }",
            &["`object[0].pin.motion`", "not both"][..],
        ),
        (
            "pin = { nodes = [0], motion = { velocity = [0, nan, 0] } }",
            &["`object[0].pin.motion.velocity`", "finite"][..],
        ),
        (
            "pin = [{ nodes = [0] }, { box = { min = [1, 0, 0], max = [0, 1, 1] } }]",
            &["`object[0].pin[1].box`"][..],
        ),
        (
            "pin = [{ nodes = [0] }, { nodez = [1] }]",
            &["object[0].pin[1]", "nodez"][..],
        ),
        (
            "pin = { nodes = [0], motion = { spin = 1.0 } }",
            &["object[0].pin.motion", "spin"][..],
        ),
        ("pin = 3", &["object[0].pin", "a pin table"][..]),
        ("self_contact = \"yes\"", &["object[0].self_contact"][..]),
    ] {
        let err = refused(lines);
        for needle in needles {
            assert!(err.contains(needle), "{lines}: `{needle}` missing: {err}");
        }
    }
}
