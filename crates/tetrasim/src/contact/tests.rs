use super::*;
use crate::mesh::grid::box_tets;
use crate::model::ModelBuilder;

#[test]
fn closest_points_on_a_triangle() {
    let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let inside = closest_on_triangle(DVec3::new(0.25, 0.25, 1.0), t);
    assert!((inside[1] - 0.25).abs() < 1e-12 && (inside[2] - 0.25).abs() < 1e-12);
    assert_eq!(
        closest_on_triangle(DVec3::new(-1.0, -1.0, 0.0), t),
        [1.0, 0.0, 0.0]
    );
    let edge = closest_on_triangle(DVec3::new(0.5, -1.0, 0.0), t);
    assert!((edge[1] - 0.5).abs() < 1e-12 && edge[2] == 0.0);
}

/// Two unit-ish boxes, the second `gap` above the first.
fn two_boxes(gap: f64) -> Model {
    let mesh = box_tets(DVec3::ZERO, 0.1, [2, 2, 2]);
    let a = ModelBuilder::new(&mesh).build().expect("a box");
    let top = a.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
    let bottom = a.positions.iter().map(|p| p.y).fold(f64::MAX, f64::min);
    let b = ModelBuilder::new(&mesh)
        .offset(DVec3::new(0.0, top - bottom + gap, 0.0))
        .build()
        .expect("a box");
    Model::concat(&[a, b]).expect("two boxes")
}

#[test]
fn touching_boxes_pair_their_facing_nodes_only() {
    let model = two_boxes(0.001);
    let bodies = BodyContact::new(&model).expect("two objects collide");
    let still = vec![DVec3::ZERO; model.node_count()];
    let contacts = bodies.find(&model, &model.positions, &still, 1e-3);
    assert!(
        !contacts.is_empty(),
        "the facing layers are within the margin"
    );
    for c in &contacts {
        let [p, a, ..] = c.nodes().map(|i| i as usize);
        assert_ne!(bodies.object_of[p], bodies.object_of[a], "{c:?}");
        let x = c.nodes().map(|i| model.positions[i as usize]);
        let value = c.value(x, 0.0);
        assert!((value - 0.001).abs() < 1e-9, "the gap: {value}");
        assert!((c.gradients().iter().copied().sum::<DVec3>()).length() < 1e-12);
    }
    // Apart by more than the margin: none; one object alone: no body contact at all.
    let apart = two_boxes(1.0);
    let far = BodyContact::new(&apart).expect("two objects");
    assert!(far.find(&apart, &apart.positions, &still, 1e-3).is_empty());
    let mesh = box_tets(DVec3::ZERO, 0.1, [2, 2, 2]);
    let one = ModelBuilder::new(&mesh).build().expect("a box");
    assert!(BodyContact::new(&one).is_none());
    let folding = ModelBuilder::new(&mesh)
        .self_contact(true)
        .build()
        .expect("a box");
    let own = BodyContact::new(&folding).expect("self-contact");
    assert!(
        own.find(
            &folding,
            &folding.positions,
            &vec![DVec3::ZERO; folding.node_count()],
            1e-3
        )
        .is_empty(),
        "a box at rest does not touch itself"
    );
}
