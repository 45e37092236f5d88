use super::*;

const DT: f64 = 1e-3;

#[test]
fn each_shape_measures_its_distance() {
    let cases: Vec<(Collider, DVec3, f64, DVec3)> = vec![
        (
            Collider::plane(DVec3::new(0.0, 0.0, 2.0), 0.5).expect("a plane"),
            DVec3::new(3.0, 1.0, 0.2),
            -0.3,
            DVec3::Z,
        ),
        (
            Collider::sphere(DVec3::ONE, 0.5),
            DVec3::new(1.0, 1.0, 2.0),
            0.5,
            DVec3::Z,
        ),
        (
            Collider::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.5, 0.25), DQuat::IDENTITY),
            DVec3::new(0.2, -0.4, 0.0),
            -0.1,
            -DVec3::Y,
        ),
        (
            Collider::cuboid(
                DVec3::ZERO,
                DVec3::ONE,
                DQuat::from_rotation_z(std::f64::consts::FRAC_PI_4),
            ),
            DVec3::new(2.0, 0.0, 0.0),
            2.0 - 2f64.sqrt(),
            DVec3::new(1.0, 0.0, 0.0),
        ),
        (
            Collider::capsule(DVec3::new(-1.0, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0), 0.2),
            DVec3::new(0.5, 0.0, 0.1),
            -0.1,
            DVec3::Z,
        ),
        (
            Collider::capsule(DVec3::new(-1.0, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0), 0.2),
            DVec3::new(1.5, 0.0, 0.0),
            0.3,
            DVec3::X,
        ),
    ];
    for (collider, x, phi, normal) in cases {
        collider.validate("collider").expect("valid");
        let (d, n) = ColliderAt::new(&collider, 0.0, DT).distance(x);
        assert!(
            (d - phi).abs() < 1e-12,
            "{:?} at {x}: {d} != {phi}",
            collider.shape
        );
        assert!(
            (n - normal).length() < 1e-12,
            "{:?} at {x}: normal {n}",
            collider.shape
        );
    }
}

#[test]
fn a_moving_collider_is_placed_at_the_steps_end_and_drags_by_its_surface_velocity() {
    let ball = Collider::sphere(DVec3::ZERO, 1.0).moving(Motion::Velocity {
        linear: DVec3::new(2.0, 0.0, 0.0),
        angular: DVec3::new(0.0, 0.0, 1.0),
    });
    let at = ColliderAt::new(&ball, 1.0, DT);
    assert!((at.end.position.x - 2.0 * (1.0 + DT)).abs() < 1e-12);
    // A point on top of the ball moves with the centre and, turning about +Z, towards -X.
    let top = at.end.position + DVec3::Y;
    let u = at.surface_velocity(top, DT);
    assert!((u - DVec3::new(1.0, 0.0, 0.0)).length() < 1e-3, "{u}");
}

#[test]
fn solve_node_pushes_out_of_every_collider_and_pins_stay() {
    let colliders = [
        Collider::sphere(DVec3::ZERO, 0.5),
        Collider::cuboid(
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::new(2.0, 0.5, 2.0),
            DQuat::IDENTITY,
        ),
    ];
    let at: Vec<_> = colliders
        .iter()
        .map(|c| ColliderAt::new(c, 0.0, DT))
        .collect();
    let (w, x, v) = (2.0, DVec3::new(0.3, 0.3, 0.0), DVec3::new(0.0, -1.0, 0.0));
    let gravity = DVec3::new(0.0, -9.81 / w, 0.0);
    let (f, contact) = solve_node(&at, gravity, DVec3::ZERO, x, v, w, DT);
    let end = end_position(x, v, f, w, DT);
    assert!(at[0].distance(end).0 > -1e-12, "outside the ball: {end}");
    assert!(contact
        .touching
        .is_some_and(|t| t.collider == 0 && t.pressed > 0.0));
    // Solving again from the result changes nothing.
    let (again, same) = solve_node(&at, f, contact.force, x, v, w, DT);
    assert!((again - f).length() < 1e-9 && (same.force - contact.force).length() < 1e-9);
    let (pinned, none) = solve_node(&at, gravity, DVec3::ZERO, x, v, 0.0, DT);
    assert_eq!((pinned, none.touching), (gravity, None));
}

#[test]
fn bad_colliders_name_their_key() {
    let message = |c: Collider| c.validate("collider[3]").expect_err("refused").to_string();
    assert!(message(Collider::sphere(DVec3::ZERO, 0.0)).contains("collider[3].radius"));
    assert!(message(Collider::capsule(DVec3::ZERO, DVec3::X, -1.0)).contains("collider[3].radius"));
    let flat = Collider::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.0, 1.0), DQuat::IDENTITY);
    assert!(message(flat).contains("half_extents.y"));
    let skew = Collider::cuboid(
        DVec3::ZERO,
        DVec3::ONE,
        DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0),
    );
    assert!(message(skew).contains("collider[3].rotation"));
    assert!(message(Collider::sphere(DVec3::ZERO, 1.0).with_friction(1.5)).contains("friction"));
    let zero = Collider::plane(DVec3::ZERO, 0.0)
        .expect_err("refused")
        .to_string();
    assert!(zero.contains("normal"), "{zero}");
}
