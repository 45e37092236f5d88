//! Gravity as it may be written: a vector `[x, y, z]` [m/s^2], or a magnitude along -Y (the
//! up axis is +Y: the floor is the plane `y = 0`). [`super::SimParams::gravity`] holds the
//! vector; scenes, flags, Python keywords and older run records may give either form.

use std::str::FromStr;

use glam::DVec3;
use serde::{Deserialize, Deserializer, Serialize};

/// Gravity as given: a magnitude along -Y, or a vector.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a magnitude along -Y (9.81) or a vector [x, y, z]"
)]
pub enum Gravity {
    /// `g` [m/s^2] along -Y (`9.81` is Earth's, pulling toward the floor `y = 0`).
    Down(f64),
    /// The acceleration `[x, y, z]` [m/s^2].
    Vector([f64; 3]),
}

impl Gravity {
    /// The acceleration [m/s^2].
    pub fn vector(self) -> DVec3 {
        match self {
            Gravity::Down(g) => DVec3::new(0.0, -g, 0.0),
            Gravity::Vector(v) => DVec3::from(v),
        }
    }
}

impl FromStr for Gravity {
    type Err = String;

    /// `9.81` (along -Y) or `0,0,-9.81` (a vector; spaces allowed, brackets optional).
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let inner = text.trim().trim_start_matches('[').trim_end_matches(']');
        let parts: Vec<&str> = inner.split(',').map(str::trim).collect();
        let number = |s: &str| {
            s.parse::<f64>()
                .map_err(|_| format!("`{s}` is not a number"))
        };
        match parts.as_slice() {
            [g] => Ok(Gravity::Down(number(g)?)),
            [x, y, z] => Ok(Gravity::Vector([number(x)?, number(y)?, number(z)?])),
            _ => Err(format!(
                "expected a magnitude along -Y (9.81) or a vector x,y,z (0,0,-9.81), got `{text}`"
            )),
        }
    }
}

/// Reads [`super::SimParams::gravity`] in either form ([`Gravity`]).
pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<DVec3, D::Error> {
    Gravity::deserialize(d).map(Gravity::vector)
}

/// The default: Earth's, along -Y.
pub(super) fn earth() -> DVec3 {
    Gravity::Down(9.81).vector()
}
