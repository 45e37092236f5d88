//! The finite elements' Newton step against contacts (docs/PHYSICS.md, "Finite elements
//! against contacts"): which nodes a contact holds, the stiffness that holds them along it,
//! and the force that stiffness stands for, which the contact's solve takes.

use super::elastic::{components, sym3_apply, Sym3};
use super::{Real, Vector};

/// How many times stiffer than its own diagonal block makes it a node a contact holds is
/// along the contact, in the finite elements' Newton step (docs/PHYSICS.md, "Finite elements
/// against contacts"): stiff enough that the solve moves it along the contact a thousandth
/// of what it would free, so the solve carries the contact's load into the body.
pub const HELD_STIFFNESS: f64 = 1.0e3;

/// The strain within which a node that ends the step so far on the floor counts as
/// resting on it, held although the floor does not push it yet (at rest the step's start
/// balances its forces): its gap to the floor over the height of its thinnest tet.
pub const HELD_GAP: f64 = 1.0e-3;

/// Whether the floor holds a node in the finite elements' Newton step: it pushes the node
/// (`floor_pushes`), or the node ends the step so far at height `y` within `HELD_GAP` of it
/// in strain (`reach`: one over the height of its thinnest tet).
#[inline]
pub fn floor_holds<R: Real>(floor_pushes: bool, y: R, reach: R) -> bool {
    floor_pushes || y * reach <= R::from_f64(HELD_GAP)
}

/// A node's diagonal block `block` stiffened along the direction `normal` (unit; zero:
/// unchanged) a contact holds it along, and the stiffening as one vector `h`: the block
/// becomes `block + h h^T`, `h = normal sqrt(HELD_STIFFNESS normal^T block normal)`.
#[inline]
pub fn held_block<V: Vector>(block: Sym3<V::Real>, normal: V) -> (Sym3<V::Real>, V) {
    let along = normal.dot(sym3_apply(block, normal));
    if along.partial_cmp(&V::Real::ZERO) != Some(std::cmp::Ordering::Greater) {
        return (block, V::ZERO);
    }
    let h = normal * (V::Real::from_f64(HELD_STIFFNESS) * along).sqrt();
    let [x, y, z] = components(h);
    let outer = [x * x, y * y, z * z, x * y, x * z, y * z];
    ([0, 1, 2, 3, 4, 5].map(|k| block[k] + outer[k]), h)
}

/// A held node's force increment `increment` for its move `d` (of which `h (h . d)` stands
/// for the force its contact, stiffened by `h`, took; [`held_block`]), with that part's
/// share away from the contact cut to what the contacts push the node with now, `pushed`
/// (their force on it [N]): a contact cannot pull, so a node that leaves it does so at the
/// next linearisation, not by the stiffening's guess.
#[inline]
pub fn held_increment<V: Vector>(increment: V, h: V, d: V, pushed: V) -> V {
    let length = h.length();
    if h == V::ZERO {
        return increment;
    }
    let away = h.dot(d) * length;
    let push = h.dot(pushed) / length;
    if away > push {
        increment - h * ((away - push) / length)
    } else {
        increment
    }
}

/// The mass a node of mass `mass` brings to the rigid part of its object's elastic forces
/// ([`crate::physics::RigidPart`]): none where a contact holds it (`h`, its stiffening, not
/// zero; [`held_block`]), as the contact, not the body's motion, takes its force.
#[inline]
pub fn held_mass<V: Vector>(mass: f64, h: V) -> f64 {
    if h == V::ZERO {
        mass
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn the_block_stiffens_along_the_contact_only() {
        let block = [2.0, 2.0, 2.0, 0.0, 0.0, 0.0];
        let (held, h) = held_block(block, DVec3::Y);
        assert_eq!(h, DVec3::Y * (HELD_STIFFNESS * 2.0).sqrt());
        assert!((held[1] - 2.0 * (1.0 + HELD_STIFFNESS)).abs() < 1e-9);
        assert_eq!(
            [held[0], held[2], held[3], held[4], held[5]],
            [2.0, 2.0, 0.0, 0.0, 0.0]
        );
        assert_eq!(held_block(block, DVec3::ZERO), (block, DVec3::ZERO));
    }

    #[test]
    fn a_contact_never_pulls() {
        let h = DVec3::Y * 10.0;
        // Pressed into the contact: the stiffening's force stands whole.
        let into = DVec3::new(0.1, -0.01, 0.0);
        assert_eq!(
            held_increment(h * h.dot(into), h, into, DVec3::Y),
            h * h.dot(into)
        );
        // Pulled off it by 1 N (`h (h . d)` = 1 along +Y) where it pushes with 0.25 N: 0.25.
        let off = DVec3::Y * 0.01;
        let cut = held_increment(h * h.dot(off), h, off, DVec3::Y * 0.25);
        assert!((cut - DVec3::Y * 0.25).length() < 1e-12, "{cut}");
        assert!(floor_holds(false, 1e-5, 10.0) && !floor_holds(false, 1e-3, 10.0));
    }
}
