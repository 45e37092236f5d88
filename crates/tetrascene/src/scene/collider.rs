//! `[[collider]]` tables: the kinematic collider types with their motion, checked and turned
//! into the engine's [`tetrasim::collider::Collider`]s.

use super::*;

/// `[[collider]]`: a collision shape. `floor` is the plane `y = 0` of
/// [`SimParams::floor`] (the fast path, at most one); the others become
/// [`tetrasim::collider::Collider`]s on the staged model ([`Scene::colliders`]).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, tag = "type", rename_all = "kebab-case")]
pub enum Collider {
    /// The plane `y = 0`.
    Floor {
        /// Friction in [0, 1]: Coulomb's mu (at most this fraction of the sliding removed per step).
        #[serde(default)]
        friction: f64,
    },
    /// The half-space `normal . x <= distance`.
    Plane {
        /// Outward normal (need not be unit, must not be zero).
        normal: [f64; 3],
        /// Distance of the plane from the origin along the unit normal [m] (`offset` before
        /// 2026-12-06, still read with a warning).
        #[serde(rename = "distance", alias = "offset")]
        offset: f64,
        /// Friction in [0, 1]: Coulomb's mu (at most this fraction of the sliding removed per step).
        #[serde(default)]
        friction: f64,
        /// Contact thickness [m], >= 0.
        #[serde(default)]
        thickness: f64,
        /// How it moves (absent: fixed).
        #[serde(default)]
        motion: Option<MotionSpec>,
    },
    /// A ball.
    Sphere {
        /// Centre [m].
        center: [f64; 3],
        /// Radius [m], > 0.
        radius: f64,
        /// Friction in [0, 1]: Coulomb's mu (at most this fraction of the sliding removed per step).
        #[serde(default)]
        friction: f64,
        /// Contact thickness [m], >= 0.
        #[serde(default)]
        thickness: f64,
        /// How it moves (absent: fixed).
        #[serde(default)]
        motion: Option<MotionSpec>,
    },
    /// An oriented box.
    #[serde(rename = "box")]
    Cuboid {
        /// Centre [m].
        center: [f64; 3],
        /// Half its size along its own axes [m], each > 0.
        half_extents: [f64; 3],
        /// Orientation as a unit quaternion `[w, x, y, z]` (default the identity).
        #[serde(default = "identity")]
        rotation: [f64; 4],
        /// Friction in [0, 1]: Coulomb's mu (at most this fraction of the sliding removed per step).
        #[serde(default)]
        friction: f64,
        /// Contact thickness [m], >= 0.
        #[serde(default)]
        thickness: f64,
        /// How it moves (absent: fixed).
        #[serde(default)]
        motion: Option<MotionSpec>,
    },
    /// The points within `radius` of the segment `a`-`b`.
    Capsule {
        /// One end of the axis [m].
        a: [f64; 3],
        /// The other end of the axis [m].
        b: [f64; 3],
        /// Radius [m], > 0.
        radius: f64,
        /// Friction in [0, 1]: Coulomb's mu (at most this fraction of the sliding removed per step).
        #[serde(default)]
        friction: f64,
        /// Contact thickness [m], >= 0.
        #[serde(default)]
        thickness: f64,
        /// How it moves (absent: fixed).
        #[serde(default)]
        motion: Option<MotionSpec>,
    },
    /// A closed triangle surface (`.ply`, `.obj`, `.off`, `.stl`; relative to the scene
    /// file), sampled as a signed distance grid; it turns about the centre of its bounds.
    Mesh {
        /// The surface file (`path` before 2026-12-06, still read with a warning).
        #[serde(rename = "mesh", alias = "path")]
        path: PathBuf,
        /// Grid cells along the longest side of its bounds (default [`DEFAULT_CELLS`]).
        #[serde(default = "default_cells")]
        cells: u32,
        /// Friction in [0, 1]: Coulomb's mu (at most this fraction of the sliding removed per step).
        #[serde(default)]
        friction: f64,
        /// Contact thickness [m], >= 0.
        #[serde(default)]
        thickness: f64,
        /// How it moves (absent: fixed).
        #[serde(default)]
        motion: Option<MotionSpec>,
    },
}

/// Grid cells along the longest side of a `mesh` collider when `cells` is not given.
pub const DEFAULT_CELLS: u32 = 48;

/// How far a quaternion's length may be from 1 (it is then normalised): scene files hold
/// rounded values such as `[0.7071, 0.0, 0.7071, 0.0]`.
pub const QUATERNION_TOLERANCE: f64 = 1e-3;

pub(super) fn identity() -> [f64; 4] {
    [1.0, 0.0, 0.0, 0.0]
}

pub(super) fn default_cells() -> u32 {
    DEFAULT_CELLS
}

/// `motion`: `{ velocity = [..], angular_velocity = [..] }` (constant, about the collider's
/// centre) or `{ keyframes = [{ t, translation, rotation }, ...] }`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSpec {
    /// Linear velocity [m/s].
    #[serde(default)]
    pub velocity: Option<[f64; 3]>,
    /// Angular velocity [rad/s] about the centre, its direction the axis.
    #[serde(default)]
    pub angular_velocity: Option<[f64; 3]>,
    /// Keyframes in increasing time.
    #[serde(default)]
    pub keyframes: Option<Vec<KeyframeSpec>>,
}

/// One keyframe of a `motion`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeSpec {
    /// Time [s].
    pub t: f64,
    /// Displacement of the declared centre [m] (default none; `position` before
    /// 2026-12-06, still read with a warning).
    #[serde(default, rename = "translation", alias = "position")]
    pub position: [f64; 3],
    /// Rotation about the declared centre, a unit quaternion `[w, x, y, z]` (default none).
    #[serde(default = "identity")]
    pub rotation: [f64; 4],
}

impl MotionSpec {
    /// The engine's motion; `key` names it (e.g. `collider[1].motion`).
    pub fn motion(&self, key: &str) -> Result<Motion> {
        let velocity = self.velocity.is_some() || self.angular_velocity.is_some();
        let motion = match (&self.keyframes, velocity) {
            (Some(_), true) => {
                return Err(Error::param(
                    key,
                    "give velocity and angular_velocity, or keyframes, not both",
                ))
            }
            (Some(keys), false) => Motion::Keyframes(
                keys.iter()
                    .enumerate()
                    .map(|(j, k)| {
                        Ok(Keyframe {
                            t: k.t,
                            position: DVec3::from(k.position),
                            rotation: quaternion(
                                &format!("{key}.keyframes[{j}].rotation"),
                                k.rotation,
                            )?,
                        })
                    })
                    .collect::<Result<_>>()?,
            ),
            (None, true) => Motion::Velocity {
                linear: DVec3::from(self.velocity.unwrap_or_default()),
                angular: DVec3::from(self.angular_velocity.unwrap_or_default()),
            },
            (None, false) => Motion::Fixed,
        };
        motion.validate(key)?;
        Ok(motion)
    }
}

/// The quaternion `[w, x, y, z]`, normalised, or an error naming `key` unless its length is
/// within [`QUATERNION_TOLERANCE`] of 1.
pub(super) fn quaternion(key: &str, [w, x, y, z]: [f64; 4]) -> Result<DQuat> {
    let q = DQuat::from_xyzw(x, y, z, w);
    let length = q.length();
    match length.is_finite() && (length - 1.0).abs() <= QUATERNION_TOLERANCE {
        true => Ok(q / length),
        false => Err(Error::param(
            key,
            format!(
                "must be a unit quaternion [w, x, y, z], got [{w}, {x}, {y}, {z}] (length {length})"
            ),
        )),
    }
}

/// Error naming `key` unless every component of `v` is finite.
pub(super) fn finite(key: &str, v: &[f64]) -> Result<()> {
    match v.iter().all(|x| x.is_finite()) {
        true => Ok(()),
        false => Err(Error::param(key, format!("must be finite, got {v:?}"))),
    }
}

impl Collider {
    /// The collider's `type` in scene files.
    pub fn name(&self) -> &'static str {
        match self {
            Collider::Floor { .. } => "floor",
            Collider::Plane { .. } => "plane",
            Collider::Sphere { .. } => "sphere",
            Collider::Cuboid { .. } => "box",
            Collider::Capsule { .. } => "capsule",
            Collider::Mesh { .. } => "mesh",
        }
    }

    /// The engine's collider of this `[[collider]]`, checked, `key` naming it in errors
    /// (`collider[2]`); `None` for the floor. A `mesh` needs its sampled surface `grid`
    /// ([`Scene::colliders`] reads it); without one only its other values are checked.
    pub fn engine(&self, key: &str, grid: Option<DistanceGrid>) -> Result<Option<EngineCollider>> {
        let at = |name: &str| format!("{key}.{name}");
        let (collider, friction, thickness, motion) = match self {
            Collider::Floor { .. } => return Ok(None),
            Collider::Plane {
                normal,
                offset,
                friction,
                thickness,
                motion,
            } => {
                finite(&at("normal"), normal)?;
                finite(&at("distance"), &[*offset])?;
                let plane =
                    EngineCollider::plane(DVec3::from(*normal), *offset).map_err(|e| match e {
                        Error::Param { key: k, message } => Error::param(at(&k), message),
                        other => other,
                    })?;
                (plane, friction, thickness, motion)
            }
            Collider::Sphere {
                center,
                radius,
                friction,
                thickness,
                motion,
            } => {
                finite(&at("center"), center)?;
                let ball = EngineCollider::sphere(DVec3::from(*center), *radius);
                (ball, friction, thickness, motion)
            }
            Collider::Cuboid {
                center,
                half_extents,
                rotation,
                friction,
                thickness,
                motion,
            } => {
                finite(&at("center"), center)?;
                let rotation = quaternion(&at("rotation"), *rotation)?;
                let cuboid = EngineCollider::cuboid(
                    DVec3::from(*center),
                    DVec3::from(*half_extents),
                    rotation,
                );
                (cuboid, friction, thickness, motion)
            }
            Collider::Capsule {
                a,
                b,
                radius,
                friction,
                thickness,
                motion,
            } => {
                finite(&at("a"), a)?;
                finite(&at("b"), b)?;
                let capsule = EngineCollider::capsule(DVec3::from(*a), DVec3::from(*b), *radius);
                (capsule, friction, thickness, motion)
            }
            Collider::Mesh {
                cells,
                friction,
                thickness,
                motion,
                ..
            } => {
                if !(MIN_CELLS..=MAX_CELLS).contains(cells) {
                    return Err(Error::param(
                        at("cells"),
                        format!("must be {MIN_CELLS} to {MAX_CELLS}, got {cells}"),
                    ));
                }
                let mesh = match grid {
                    // The grid is centred on its bounds: the mesh turns about that centre.
                    Some(mut grid) => {
                        let centre = (grid.origin + grid.end()) / 2.0;
                        grid.origin -= centre;
                        let mut mesh = EngineCollider::mesh(grid);
                        mesh.pose.position = centre;
                        mesh
                    }
                    // Checks the values the shape does not hold.
                    None => EngineCollider::sphere(DVec3::ZERO, 1.0),
                };
                (mesh, friction, thickness, motion)
            }
        };
        let mut collider = collider.with_friction(*friction);
        collider.thickness = *thickness;
        if let Some(motion) = motion {
            collider = collider.moving(motion.motion(&at("motion"))?);
        }
        collider.validate(key)?;
        Ok(Some(collider))
    }

    /// The surface file of a `mesh` collider.
    pub fn path(&self) -> Option<&Path> {
        match self {
            Collider::Mesh { path, .. } => Some(path),
            _ => None,
        }
    }
}

/// The sampled surface of the `mesh` collider `key` (`collider[2]`): errors name
/// `collider[2].mesh` (an unreadable or open surface) or `collider[2].cells`.
pub(super) fn mesh_grid(key: &str, path: &Path, cells: u32) -> Result<DistanceGrid> {
    let surface = tetrasim::mesh::io::read_surface(path)
        .map_err(|e| Error::param(format!("{key}.mesh"), Error::from(e).to_string()))?;
    DistanceGrid::from_surface(&surface.vertices, &surface.triangles, cells).map_err(|e| match e {
        // The engine names the surface `path`; the scene's key for it is `mesh`.
        Error::Param { key: k, message } if k == "path" => Error::param(
            format!("{key}.mesh"),
            format!("{message} ({})", path.display()),
        ),
        Error::Param { key: k, message } => Error::param(format!("{key}.{k}"), message),
        other => other,
    })
}
