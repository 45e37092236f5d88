//! Contact without false restitution (physics.md, second edition): the floor must not turn its
//! own correction into velocity. A nearly rigid body (`distance`: every spring is a hard
//! constraint) dropped from 0.1 m onto the floor comes to rest: after its first contact its
//! lowest node never rises more than 2 mm above the floor, on every backend. The first
//! edition's projection made the same sphere bounce back up to 79 mm.
//!
//! With the default (combined) contact the sphere still rebounds (the solver residual's
//! elastic bounce, issue 10; the ignored test below is issue 26's target); split contact
//! (`contact = "split"`, physics.md third edition) removes the rebound on every backend,
//! at the local volume error this file prints and docs/PHYSICS.md tabulates.

mod gpu_support;

use gpu_support::{bundled_sphere, for_each_backend};
use tetrasim::params::{ContactMode, Method, Placement};
use tetrasim::{Backend, Model, ModelBuilder, SimParams};

const FRAMES: u32 = 400;
const REBOUND_LIMIT: f64 = 2e-3;

/// The `distance` sphere dropped from 0.1 m.
fn dropped_sphere() -> Model {
    ModelBuilder::new(&bundled_sphere())
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.1),
        })
        .build()
        .unwrap()
}

/// `FRAMES` frames of `backend`: the frame of first contact, the largest height of the
/// lowest node after it [m] and the average local volume error [% of the rest volume].
fn rebound(name: &str, model: &Model, backend: &mut dyn Backend) -> (u32, f64, f64) {
    let rest = model.total_rest_volume();
    let mut contact = None;
    let mut rebound = 0.0f64;
    let mut local = 0.0;
    for frame in 0..FRAMES {
        backend.step_frame().unwrap();
        let lowest = backend
            .state()
            .unwrap()
            .positions
            .iter()
            .map(|p| p.y)
            .fold(f64::INFINITY, f64::min);
        if contact.is_none() && lowest < 1e-4 {
            contact = Some(frame);
        }
        if contact.is_some() {
            rebound = rebound.max(lowest);
        }
        local += backend.volume().unwrap().local_error / rest * 100.0 / f64::from(FRAMES);
    }
    let contact = contact.unwrap_or_else(|| panic!("{name}: the sphere never landed"));
    println!(
        "{name}: first contact at frame {contact}, largest rebound {rebound:.2e} m, \
         average local volume error {local:.3} %"
    );
    (contact, rebound, local)
}

#[test]
#[ignore = "fails: the sphere rebounds 79 mm with Jacobi, 63 mm with the default Gauss-Seidel \
            and global volume (issue 10); see docs/PHYSICS.md, \"Contact\"; issue 26's target"]
fn a_rigid_sphere_does_not_bounce() {
    let model = dropped_sphere();
    let params = SimParams {
        method: Method::Distance,
        ..SimParams::default()
    };
    for_each_backend(&model, &params, |name, backend| {
        let (_, rebound, _) = rebound(name, &model, backend);
        assert!(
            rebound < REBOUND_LIMIT,
            "{name}: the rigid sphere bounced {rebound} m back up"
        );
    });
}

#[test]
fn split_contact_keeps_a_rigid_sphere_down_on_every_backend() {
    let model = dropped_sphere();
    let combined = SimParams {
        method: Method::Distance,
        ..SimParams::default()
    };
    let split = SimParams {
        contact: ContactMode::Split,
        ..combined.clone()
    };
    // The same drop with the default contact bounces (what split contact is for).
    let mut reference = tetrasim::create_backend("cpu-ref", &model, &combined).unwrap();
    let (landed, bounce, combined_local) = rebound("cpu-ref combined", &model, &mut *reference);
    assert!(
        bounce > 10.0 * REBOUND_LIMIT,
        "combined contact rebounds {bounce} m: the drop no longer tests split contact"
    );
    for_each_backend(&model, &split, |name, backend| {
        let (contact, rebound, local) = rebound(name, &model, backend);
        assert!(
            rebound < REBOUND_LIMIT,
            "{name}: with split contact the rigid sphere bounced {rebound} m back up"
        );
        assert!(
            contact.abs_diff(landed) <= 1,
            "{name}: landed at frame {contact}, combined contact at {landed}"
        );
        // The documented price: a higher local volume error, but bounded.
        assert!(
            local < 1.0 && local >= combined_local,
            "{name}: average local volume error {local} % (combined {combined_local} %)"
        );
    });
}
