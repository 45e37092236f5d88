//! Scene files (TOML): objects, colliders, solver settings and outputs in one place.
//! `tetrasim run --scene FILE` reads one; the command-line flags are shorthand for a
//! one-object scene. Unknown keys and out-of-range values are errors naming the key's path
//! (e.g. `object[0].material.ks`, `object[0].pin[1].motion`,
//! `collider[2].motion.keyframes[1].t`; colliders are numbered in file order, the floor
//! included).
//!
//! ```toml
//! [solver]
//! dt = 0.001          # s
//! substeps = 1
//! iterations = 10
//! omega = 1.0
//! combine = "scaled" # momentum-conserving (default), or "sum", or "average" (first edition)
//! solver = "gauss-seidel" # colour groups (default), "jacobi" (the paper's method), or
//!                     # "chebyshev" (jacobi with chebyshev semi-iteration)
//! groups = 8          # colour groups of gauss-seidel
//! rho = 0.95          # spectral radius estimate of chebyshev
//! global_volume = true  # one global volume constraint per object (default: on for
//!                       # gauss-seidel, off for jacobi and chebyshev)
//! springs = "explicit"  # the paper's forces, or "implicit" (compliant constraints)
//! warm_start = false    # implicit springs start each step from the last multipliers
//! # (GPU choices such as --atomics, --device and --workgroup-size are flags, not scene keys)
//! epsilon = 1e-20     # skip a constraint whose denominator A is at or below this
//! gravity = 9.81      # m/s^2, along -Y
//! frames = 400
//!
//! [[object]]
//! mesh = "meshes/sphere"     # tet mesh: .node/.ele prefix, .vtk, .vtu, .msh or .mesh; or a
//!                            # surface (.ply/.obj/.off/.stl); relative to the scene file
//! method = "volume"
//! fit_size = 1.0             # m, largest bounding-box side (omit to keep the mesh's size)
//! drop_height = 0.1          # m, lowest node above y = 0 (omit to keep the position)
//! offset = [0.0, 0.0, 0.0]   # m, added after fit_size and drop_height (objects start apart)
//! velocity = [0.0, 0.0, 0.0] # m/s, initial
//! material = { ks = 5000.0, kd = 15.0, node_mass = 1.0 }   # or density = 1000.0 (kg/m^3)
//! # or a material in physical units, instead of ks and kd:
//! # material = { youngs_modulus = 1e5, poisson_ratio = 0.45, density = 1000.0, damping = 0.003 }
//! pin = { nodes = [0, 1], box = { min = [-1, 0, -1], max = [1, 0.12, 1] } }
//! # A pin may move: its nodes follow a motion (as a collider's, below) rigidly about their
//! # centroid, e.g. pin = { box = { .. }, motion = { keyframes = [{ t = 0.0 },
//! #   { t = 0.5, position = [0.3, 0, 0] }] } }  (a motion that holds no node is an error).
//! # Several pins, each fixed or with its own motion (keys object[0].pin[1].motion...):
//! #   pin = [{ box = { .. } }, { box = { .. }, motion = { .. } }]   or [[object.pin]] tables
//! self_contact = false       # whether its surface collides with itself (different objects
//!                            # always collide with each other)
//!
//! [[collider]]
//! type = "floor"             # the plane y = 0 (the fast path; at most one)
//! friction = 0.0             # in [0, 1]: tangential velocity removed per step in contact
//!
//! # Kinematic colliders (any number, in this order): every type below also takes
//! # friction (in [0, 1], default 0), thickness (m, >= 0, default 0: nodes are kept this far
//! # out) and an optional motion of its declared pose, either
//! #   motion = { velocity = [0, -0.1, 0], angular_velocity = [0, 1, 0] }  # m/s, rad/s
//! # (turning about the collider's centre) or keyframes in increasing time (positions
//! # linear, rotations slerped, the last key held):
//! #   motion = { keyframes = [{ t = 0.0 }, { t = 1.0, position = [0, -0.2, 0],
//! #                                         rotation = [1, 0, 0, 0] }] }
//! # (position: displacement of the centre, default [0, 0, 0]; rotation about the centre,
//! # default none). Quaternions are [w, x, y, z], unit within 1e-3 (then normalised).
//! [[collider]]
//! type = "plane"             # the half-space normal . x <= offset
//! normal = [0.1, 1.0, 0.0]   # need not be unit
//! offset = 0.0               # m, along the unit normal
//!
//! [[collider]]
//! type = "sphere"
//! center = [0.0, 1.5, 0.0]
//! radius = 0.2
//!
//! [[collider]]
//! type = "box"
//! center = [0.0, -0.1, 0.0]
//! half_extents = [1.0, 0.1, 1.0]
//! rotation = [1.0, 0.0, 0.0, 0.0]  # optional, default the identity
//!
//! [[collider]]
//! type = "capsule"           # the points within radius of the segment a-b
//! a = [-0.5, 1.2, 0.0]
//! b = [0.5, 1.2, 0.0]
//! radius = 0.1
//!
//! [[collider]]
//! type = "mesh"              # a closed surface (.ply/.obj/.off/.stl), relative to the scene
//! path = "tool.off"          # file, sampled as a signed distance grid; it turns about the
//! cells = 48                 # centre of its bounds; cells along its longest side (8 to 512)
//!
//! [output]
//! json = "out/metrics.json"  # the run records (`metrics` is accepted too)
//! dir = "out/frames"         # the deformed mesh every `every` frames (`surface_dir` too)
//! every = 10                 # these three need `dir`
//! format = "vtu"             # ply (default), obj, vtk or vtu (+ METHOD.pvd time series)
//! units = "input"            # simulation (default) or input: the mesh file's units
//! ```

use std::path::{Path, PathBuf};

use glam::{DQuat, DVec3};
use serde::Deserialize;

use crate::overrides::{MaterialOverrides, SolverOverrides};

use tetrasim::collider::{
    Collider as EngineCollider, DistanceGrid, Keyframe, Motion, MAX_CELLS, MIN_CELLS,
};
use tetrasim::error::{Error, Result};
use tetrasim::params::{Method, Placement, SimParams, SEED_FRAMES};

/// A whole scene as read from a file (paths already resolved against the file's folder).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// The values `solver` and the objects' materials override: the `seed` preset's in a
    /// file, the `--preset`'s in the scene `run`'s flags stand for.
    #[serde(skip)]
    pub base: SimParams,
    /// `[solver]`: time stepping and solver settings shared by all objects.
    #[serde(default)]
    pub solver: SolverOverrides,
    /// The simulated objects (at least one).
    #[serde(rename = "object", default)]
    pub objects: Vec<Object>,
    /// Collision shapes.
    #[serde(rename = "collider", default)]
    pub colliders: Vec<Collider>,
    /// What to write.
    #[serde(default)]
    pub output: Output,
}

/// `[[object]]`: one tet mesh with its placement, material and pins.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Object {
    /// Tet mesh (`.node/.ele` prefix, `.vtk`, `.vtu`, `.msh`, `.mesh`) or surface file.
    pub mesh: PathBuf,
    /// Tets to aim at when `mesh` is a surface file meshed in-process (default 5000).
    #[serde(default)]
    pub target_tets: Option<usize>,
    /// Simulation method.
    #[serde(default = "default_method")]
    pub method: Method,
    /// Largest bounding-box side after scaling [m]; absent keeps the mesh's size.
    #[serde(default)]
    pub fit_size: Option<f64>,
    /// Height of the lowest node above `y = 0` [m], centred in X and Z; absent keeps the
    /// mesh where it is.
    #[serde(default)]
    pub drop_height: Option<f64>,
    /// Moves the placed mesh by this much [m] (added after `fit_size` and `drop_height`), so
    /// that objects start apart.
    #[serde(default)]
    pub offset: [f64; 3],
    /// Initial velocity [m/s].
    #[serde(default)]
    pub velocity: [f64; 3],
    /// `material`: spring constants and mass.
    #[serde(default)]
    pub material: MaterialOverrides,
    /// Pinned nodes: one `pin` table or a list of them, each fixed or moving.
    #[serde(default)]
    pub pin: Pins,
    /// Whether the object's surface collides with itself (default off; different objects
    /// always collide with each other).
    #[serde(default)]
    pub self_contact: bool,
}

fn default_method() -> Method {
    Method::Volume
}

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

/// `[[collider]]`: a collision shape. `floor` is the plane `y = 0` of
/// [`SimParams::floor`] (the fast path, at most one); the others become
/// [`tetrasim::collider::Collider`]s on the staged model ([`Scene::colliders`]).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, tag = "type", rename_all = "kebab-case")]
pub enum Collider {
    /// The plane `y = 0`.
    Floor {
        /// Fraction of tangential velocity removed on contact, in [0, 1].
        #[serde(default)]
        friction: f64,
    },
    /// The half-space `normal . x <= offset`.
    Plane {
        /// Outward normal (need not be unit, must not be zero).
        normal: [f64; 3],
        /// Offset along the unit normal [m].
        offset: f64,
        /// Fraction of tangential velocity removed on contact, in [0, 1].
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
        /// Fraction of tangential velocity removed on contact, in [0, 1].
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
        /// Fraction of tangential velocity removed on contact, in [0, 1].
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
        /// Fraction of tangential velocity removed on contact, in [0, 1].
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
        /// The surface file.
        path: PathBuf,
        /// Grid cells along the longest side of its bounds (default [`DEFAULT_CELLS`]).
        #[serde(default = "default_cells")]
        cells: u32,
        /// Fraction of tangential velocity removed on contact, in [0, 1].
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

fn identity() -> [f64; 4] {
    [1.0, 0.0, 0.0, 0.0]
}

fn default_cells() -> u32 {
    DEFAULT_CELLS
}

/// `motion`: `{ velocity = [..], angular_velocity = [..] }` (constant, about the collider's
/// centre) or `{ keyframes = [{ t, position, rotation }, ...] }`.
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
    /// Displacement of the declared centre [m] (default none).
    #[serde(default)]
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
fn quaternion(key: &str, [w, x, y, z]: [f64; 4]) -> Result<DQuat> {
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
fn finite(key: &str, v: &[f64]) -> Result<()> {
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
                finite(&at("offset"), &[*offset])?;
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

/// `[output]`: files to write.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// The run records as JSON (`metrics` in older scenes).
    #[serde(alias = "metrics")]
    pub json: Option<PathBuf>,
    /// Folder for the deformed mesh every `every` frames (`surface_dir` in older scenes).
    #[serde(alias = "surface_dir")]
    pub dir: Option<PathBuf>,
    /// Frames between mesh files (default [`DEFAULT_EVERY`]); needs `dir`.
    pub every: Option<u32>,
    /// Mesh file format (default `ply`); needs `dir`.
    pub format: Option<tetrasim::output::OutputFormat>,
    /// Units and frame of written positions (default `simulation`); needs `dir`.
    pub units: Option<tetrasim::output::OutputUnits>,
}

/// Frames between mesh files when `every` is not given.
pub const DEFAULT_EVERY: u32 = 10;

impl Output {
    /// Error naming the first of `every`, `format`, `units` given without `dir`; `key` turns
    /// a field name into the name the user wrote (`output.every`, `--every`).
    pub fn check(&self, key: impl Fn(&str) -> String, dir_key: &str) -> Result<()> {
        if self.dir.is_some() {
            return Ok(());
        }
        for (name, given) in [
            ("every", self.every.is_some()),
            ("format", self.format.is_some()),
            ("units", self.units.is_some()),
        ] {
            if given {
                return Err(Error::param(
                    key(name),
                    format!("acts only on mesh files, and no {dir_key} is given"),
                ));
            }
        }
        Ok(())
    }
}

impl Scene {
    /// Reads, parses and validates a scene file; relative paths in it are taken relative
    /// to the file's folder.
    pub fn load(path: &Path) -> Result<Scene> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let mut scene = Scene::parse(&text).map_err(|e| match e {
            Error::Param { key, message } => {
                Error::param(key, format!("{message} (in {})", path.display()))
            }
            other => other,
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        for object in &mut scene.objects {
            object.mesh = base.join(&object.mesh);
        }
        for collider in &mut scene.colliders {
            if let Collider::Mesh { path, .. } = collider {
                *path = base.join(&*path);
            }
        }
        let output = &mut scene.output;
        for p in [&mut output.json, &mut output.dir].into_iter().flatten() {
            *p = base.join(&*p);
        }
        Ok(scene)
    }

    /// Parses and validates scene text.
    pub fn parse(text: &str) -> Result<Scene> {
        let deserializer = toml::Deserializer::new(text);
        let scene: Scene = serde_path_to_error::deserialize(deserializer).map_err(|e| {
            let key = e.path().to_string();
            let inner = e.into_inner();
            let message = inner.message().to_string();
            let at = inner
                .span()
                .map(|s| format!(" (line {})", line_of(text, s.start)))
                .unwrap_or_default();
            Error::param(
                if key == "." { "scene".to_string() } else { key },
                format!("{message}{at}"),
            )
        })?;
        scene.validate()?;
        Ok(scene)
    }

    /// Checks ranges; errors name the key's path.
    pub fn validate(&self) -> Result<()> {
        if self.objects.is_empty() {
            return Err(Error::param("object", "the scene has no [[object]]"));
        }
        if self.frames() == 0 {
            return Err(Error::param("solver.frames", "must be at least 1"));
        }
        if self.output.every == Some(0) {
            return Err(Error::param("output.every", "must be at least 1"));
        }
        self.output
            .check(|name| format!("output.{name}"), "output.dir")?;
        let solver = self.solver.solver.unwrap_or(self.base.solver);
        if let Some((key, needs)) = self.solver.misplaced(solver) {
            return Err(Error::param(
                format!("solver.{key}"),
                format!(
                    "acts only with solver = \"{}\"; the solver is {solver}",
                    needs.name()
                ),
            ));
        }
        for i in 0..self.objects.len() {
            let o = &self.objects[i];
            let key = |k: &str| format!("object[{i}].{k}");
            for (name, value) in [("fit_size", o.fit_size), ("drop_height", o.drop_height)] {
                if let Some(v) = value {
                    if !v.is_finite() || (name == "fit_size" && v <= 0.0) {
                        return Err(Error::param(key(name), format!("out of range: {v}")));
                    }
                }
            }
            if o.velocity.iter().any(|v| !v.is_finite()) {
                return Err(Error::param(key("velocity"), "must be finite"));
            }
            if o.offset.iter().any(|v| !v.is_finite()) {
                return Err(Error::param(key("offset"), "must be finite"));
            }
            if let Some((a, b)) = o.material.conflict() {
                return Err(Error::param(
                    key("material"),
                    format!("give {a} or {b}, not both"),
                ));
            }
            for (j, pin) in o.pin.pins.iter().enumerate() {
                let at = o.pin.key(i, j);
                if let Some(b) = pin.region {
                    if (0..3).any(|a| b.min[a] > b.max[a] || b.min[a].is_nan() || b.max[a].is_nan())
                    {
                        return Err(Error::param(
                            format!("{at}.box"),
                            "min must not exceed max on any axis",
                        ));
                    }
                }
                if let Some(motion) = &pin.motion {
                    motion.motion(&format!("{at}.motion"))?;
                    if pin.is_empty() {
                        return Err(Error::param(
                            format!("{at}.motion"),
                            "moves no node: the pin holds none (give `nodes` or a `box`)",
                        ));
                    }
                }
            }
            self.params_for(i).validate().map_err(|e| match e {
                Error::Param { key: k, message } => Error::param(scene_key(i, &k), message),
                other => other,
            })?;
        }
        let mut floor = None;
        for (i, c) in self.colliders.iter().enumerate() {
            if let Collider::Floor { .. } = c {
                if let Some(first) = floor {
                    return Err(Error::param(
                        format!("collider[{i}]"),
                        format!(
                            "a second floor (collider[{first}] is one): a scene has at most one"
                        ),
                    ));
                }
                floor = Some(i);
            }
            c.engine(&format!("collider[{i}]"), None)?;
        }
        Ok(())
    }

    /// The engine's colliders, in scene order, the floor left out (it is
    /// [`SimParams::floor`]): each `mesh` surface read and sampled. Errors name the
    /// collider's key in the scene (`collider[2].path`).
    pub fn colliders(&self) -> Result<Vec<EngineCollider>> {
        let mut out = Vec::new();
        for (i, c) in self.colliders.iter().enumerate() {
            let key = format!("collider[{i}]");
            let grid = match c {
                Collider::Mesh { path, cells, .. } => Some(mesh_grid(&key, path, *cells)?),
                _ => None,
            };
            out.extend(c.engine(&key, grid)?);
        }
        Ok(out)
    }

    /// Frames to simulate (`solver.frames`, default the `seed` preset's).
    pub fn frames(&self) -> u32 {
        self.solver.frames.unwrap_or(SEED_FRAMES)
    }

    /// The solver parameters of object `index`: the base, its method and the floor, with
    /// the `[solver]` table and its material applied.
    pub fn params_for(&self, index: usize) -> SimParams {
        let o = &self.objects[index];
        let floor = self.colliders.iter().find_map(|c| match c {
            Collider::Floor { friction } => Some(*friction),
            _ => None,
        });
        let mut params = SimParams {
            method: o.method,
            floor: floor.is_some(),
            friction: floor.unwrap_or(0.0),
            ..self.base.clone()
        };
        self.solver.apply(&mut params);
        o.material.apply(&mut params);
        params
    }

    /// Placement of object `index`.
    pub fn placement_for(&self, index: usize) -> Placement {
        let o = &self.objects[index];
        Placement {
            fit_size: o.fit_size,
            drop_height: o.drop_height,
        }
    }
}

/// The sampled surface of the `mesh` collider `key` (`collider[2]`): errors name
/// `collider[2].path` (an unreadable or open surface) or `collider[2].cells`.
fn mesh_grid(key: &str, path: &Path, cells: u32) -> Result<DistanceGrid> {
    let surface = tetrasim::mesh::io::read_surface(path)
        .map_err(|e| Error::param(format!("{key}.path"), Error::from(e).to_string()))?;
    DistanceGrid::from_surface(&surface.vertices, &surface.triangles, cells).map_err(|e| match e {
        Error::Param { key: k, message } => Error::param(
            format!("{key}.{k}"),
            match k.as_str() {
                "path" => format!("{message} ({})", path.display()),
                _ => message,
            },
        ),
        other => other,
    })
}

/// Where a [`SimParams`] key lives in a scene file.
fn scene_key(object: usize, key: &str) -> String {
    match key {
        "constraint_epsilon" => "solver.epsilon".to_string(),
        "friction" => "collider.friction".to_string(),
        "mass" => format!("object[{object}].material.node_mass"),
        key if SolverOverrides::has(key) => format!("solver.{key}"),
        key if MaterialOverrides::has(key) => format!("object[{object}].material.{key}"),
        other => format!("object[{object}].{other}"),
    }
}

/// 1-based line of byte offset `at` in `text`.
fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())]
        .bytes()
        .filter(|&b| b == b'\n')
        .count()
        + 1
}

#[cfg(test)]
mod tests {
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
        assert_eq!(p.mass, MassMode::Density { density: 1000.0 });
        assert!(p.floor);
        assert_eq!(p.friction, 0.5);
        assert!(scene.objects[0].pin.pins[0]
            .region
            .unwrap()
            .contains(DVec3::splat(0.5)));
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
}

#[cfg(test)]
mod collider_tests;

#[cfg(test)]
mod pin_tests;
