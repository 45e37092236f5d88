//! Contact without false restitution (physics.md, second edition): the floor must not turn its
//! own correction into velocity. A nearly rigid body (`distance`: every spring is a hard
//! constraint) dropped from 0.1 m onto the floor comes to rest: after its first contact its
//! lowest node never rises more than 2 mm above the floor, on every backend. The first
//! edition's projection made the same sphere bounce back up to 79 mm.

mod gpu_support;

use gpu_support::{bundled_sphere, for_each_backend};
use tetrasim::params::{Method, Placement};
use tetrasim::{ModelBuilder, SimParams};

const FRAMES: u32 = 400;
const REBOUND_LIMIT: f64 = 2e-3;

#[test]
#[ignore = "fails: the sphere rebounds 79 mm with Jacobi, 63 mm with the default Gauss-Seidel \
            and global volume (issue 10); see docs/PHYSICS.md, \"Contact\""]
fn a_rigid_sphere_does_not_bounce() {
    let model = ModelBuilder::new(&bundled_sphere())
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.1),
        })
        .build()
        .unwrap();
    let params = SimParams {
        method: Method::Distance,
        ..SimParams::default()
    };
    for_each_backend(&model, &params, |name, backend| {
        let mut contact = None;
        let mut rebound = 0.0f64;
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
        }
        let contact = contact.unwrap_or_else(|| panic!("{name}: the sphere never landed"));
        println!("{name}: first contact at frame {contact}, largest rebound {rebound:.2e} m");
        assert!(
            rebound < REBOUND_LIMIT,
            "{name}: the rigid sphere bounced {rebound} m back up"
        );
    });
}
