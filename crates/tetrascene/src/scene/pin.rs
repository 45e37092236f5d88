//! `pin`: nodes held by index or box, fixed or moving (one table or a list of them).

use super::*;

/// `pin`: nodes held by index and/or inside an axis-aligned box (in placed coordinates,
/// metres), fixed, or moving rigidly with a `motion` about their centroid (a clamp,
/// [`tetrasim::collider::Clamp`]).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pin {
    /// Node indices.
    #[serde(default)]
    pub nodes: Vec<u32>,
    /// Box whose nodes are pinned.
    #[serde(default, rename = "box")]
    pub region: Option<Aabb>,
    /// How the pinned nodes move (absent: they stay put).
    #[serde(default)]
    pub motion: Option<MotionSpec>,
}

impl Pin {
    /// Whether it holds no node by index and has no box.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty() && self.region.is_none()
    }
}

/// An object's pins: `pin = { .. }` (one, keys `object[k].pin...`) or
/// `pin = [{ .. }, { .. }]` / `[[object.pin]]` (several, keys `object[k].pin[j]...`), each
/// with its own motion, e.g. a block clamped at both ends with one end pulled.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Pins {
    /// The pins in file order.
    pub pins: Vec<Pin>,
    /// Whether the file gave a list (how errors name a pin).
    pub list: bool,
}

impl Pins {
    /// One pin, written as a table.
    pub fn one(pin: Pin) -> Pins {
        Pins {
            pins: vec![pin],
            list: false,
        }
    }

    /// The scene key of pin `j` of object `object`: `object[0].pin` or `object[0].pin[1]`.
    pub fn key(&self, object: usize, j: usize) -> String {
        match self.list {
            true => format!("object[{object}].pin[{j}]"),
            false => format!("object[{object}].pin"),
        }
    }
}

impl<'de> Deserialize<'de> for Pins {
    fn deserialize<D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> std::result::Result<Pins, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = Pins;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a pin table { nodes, box, motion } or a list of them")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> std::result::Result<Pins, A::Error> {
                Pin::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(Pins::one)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> std::result::Result<Pins, A::Error> {
                Ok(Pins {
                    pins: Vec::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))?,
                    list: true,
                })
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// An axis-aligned box [m].
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Aabb {
    /// Lowest corner.
    pub min: [f64; 3],
    /// Highest corner.
    pub max: [f64; 3],
}

impl Aabb {
    /// Whether `p` lies inside or on the box.
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(DVec3::from(self.min)).all() && p.cmple(DVec3::from(self.max)).all()
    }
}
