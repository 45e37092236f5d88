//! Scene files (TOML): objects, colliders, solver settings and outputs in one place.
//! `tetrasim run --scene FILE` reads one; the command-line flags are shorthand for a
//! one-object scene. Unknown keys and out-of-range values are errors naming the key's path
//! (e.g. `object[0].material.ks`, `object[0].pin[1].motion`,
//! `collider[2].motion.keyframes[1].t`; colliders are numbered in file order, the floor
//! included). Keys renamed on 2026-12-06 so that each concept has one name (`epsilon`,
//! a plane's `offset`, a mesh collider's `path`, a keyframe's `position`, `[output] dir`)
//! are still read, with a warning naming the new one ([`crate::renamed`]).
//!
//! ```toml
//! [solver]
//! accuracy = "balanced" # the speed/accuracy dial: "fast", "balanced" (the defaults) or
//!                     # "accurate"; sets solver, groups, iterations, substeps and dt, and
//!                     # any of them given here overrides it (docs/guide/accuracy.md)
//! dt = 0.001          # s
//! substeps = 1
//! iterations = 10
//! omega = 1.0
//! combine = "scaled" # momentum-conserving (default), or "sum", or "average" (first edition)
//! solver = "gauss-seidel" # colour groups (default), "jacobi" (the paper's method), or
//!                     # "chebyshev" (jacobi with chebyshev semi-iteration)
//! groups = 8          # colour groups of gauss-seidel
//! block_size = 0      # block gauss-seidel: constraints per block (0 off; >1024: cpu only)
//! block_sweeps = 1    # sweeps of each block per iteration (1 to 8)
//! spring_block_sweeps = 0  # the same for implicit springs' blocks (0: as block_sweeps)
//! # rho = 0.95        # with solver = "chebyshev" only (refused with the others): its
//!                     # spectral radius estimate (lowered below 6 iterations: 0.934 at
//!                     # 5, 0.899 at 4)
//! anderson = 0        # anderson acceleration's memory (0 off, up to 8; 5 for stiff bodies)
//! minres = 0          # MINRES iterations after the sweeps (0 off, up to 200)
//! inversion_sweeps = 0 # sweeps of the inversion floor after the iterations (method volume)
//! inversion_floor = 0.1 # the fraction of its rest volume a tet is pushed back to
//! global_volume = true  # one global volume constraint per object (default: on for
//!                       # gauss-seidel, off for jacobi and chebyshev)
//! springs = "explicit"  # the paper's forces, or "implicit" (compliant constraints)
//! warm_start = false    # implicit springs start each step from the last multipliers
//! contact = "combined"  # or "split": split impulses, no rebound, about twice the solve
//! # (GPU choices such as --atomics, --device and --workgroup-size are flags, not scene keys)
//! constraint_epsilon = 1e-20 # skip a constraint whose denominator A is at or below
//!                     # this (`epsilon` before 2026-12-06)
//! gravity = 9.81      # m/s^2, along -Y (the up axis is +Y; the floor is y = 0), or a
//!                     # vector [0.0, 0.0, -9.81] (then a plane collider is the ground)
//! frames = 400
//!
//! [[object]]
//! mesh = "meshes/sphere"     # tet mesh: .node/.ele prefix, .vtk, .vtu, .msh or .mesh; or a
//!                            # surface (.ply/.obj/.off/.stl); relative to the scene file
//! method = "volume"
//! fit_size = 1.0             # m, largest bounding-box side (omit to keep the mesh's size)
//! rotation = [0.7071, -0.7071, 0.0, 0.0] # [w, x, y, z], about the mesh's bounding-box
//!                            # centre before fit_size and drop_height (here a Z-up part
//!                            # stood on the floor: -90 degrees about X); omit: as in the file
//! drop_height = 0.1          # m, lowest node above y = 0 (omit to keep the position)
//! offset = [0.0, 0.0, 0.0]   # m, added after fit_size and drop_height (objects start apart)
//! velocity = [0.0, 0.0, 0.0] # m/s, initial
//! material = { ks = 5000.0, kd = 15.0, node_mass = 1.0 }   # or density = 1000.0 (kg/m^3)
//! # or a material in physical units, instead of ks and kd:
//! # material = { youngs_modulus = 1e5, poisson_ratio = 0.45, density = 1000.0, damping = 0.003 }
//! pin = { nodes = [0, 1], box = { min = [-1, 0, -1], max = [1, 0.12, 1] } }
//! # A pin may move: its nodes follow a motion (as a collider's, below) rigidly about their
//! # centroid, e.g. pin = { box = { .. }, motion = { keyframes = [{ t = 0.0 },
//! #   { t = 0.5, translation = [0.3, 0, 0] }] } }  (a motion that holds no node is an error).
//! # Several pins, each fixed or with its own motion (keys object[0].pin[1].motion...):
//! #   pin = [{ box = { .. } }, { box = { .. }, motion = { .. } }]   or [[object.pin]] tables
//! self_contact = false       # whether its surface collides with itself (different objects
//!                            # always collide with each other)
//!
//! [[collider]]
//! type = "floor"             # the plane y = 0 (the fast path; at most one)
//! friction = 0.0             # in [0, 1]: Coulomb's mu (at most this fraction of the sliding
//!                            # removed per step)
//!
//! # Kinematic colliders (any number, in this order): every type below also takes
//! # friction (in [0, 1], default 0: the fraction of a touching node's sliding removed per
//! # step, at most friction x the push's normal velocity: Coulomb's bound), thickness (m, >= 0, default 0: nodes are kept this far
//! # out) and an optional motion of its declared pose, either
//! #   motion = { velocity = [0, -0.1, 0], angular_velocity = [0, 1, 0] }  # m/s, rad/s
//! # (turning about the collider's centre) or keyframes in increasing time (translations
//! # linear, rotations slerped, the last key held):
//! #   motion = { keyframes = [{ t = 0.0 }, { t = 1.0, translation = [0, -0.2, 0],
//! #                                         rotation = [1, 0, 0, 0] }] }
//! # (translation: displacement of the centre, default [0, 0, 0]; rotation about the centre,
//! # default none). Quaternions are [w, x, y, z], unit within 1e-3 (then normalised).
//! [[collider]]
//! type = "plane"             # the half-space normal . x <= distance
//! normal = [0.1, 1.0, 0.0]   # need not be unit
//! distance = 0.0             # m, of the plane from the origin along the unit normal
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
//! mesh = "tool.off"          # file, sampled as a signed distance grid; it turns about the
//! cells = 48                 # centre of its bounds; cells along its longest side (8 to 512)
//!
//! [[grab]]                  # a handle (forceps, a gripper): holds the free nodes within
//! point = [0.0, 0.6, 0.0]    # radius (m) of point (m) at the start, moves them with its
//! radius = 0.05              # motion (as a collider's), hard or through a spring
//! motion = { velocity = [0.0, 0.2, 0.0] }  # stiffness (N/m), and lets go at release (s)
//!
//! [output]
//! json = "out/metrics.json"  # the run records (`metrics` is accepted too)
//! out_dir = "out/frames"     # the deformed mesh every `every` frames
//! every = 10                 # these three need `dir`
//! format = "vtu"             # ply (default), obj, vtk or vtu (+ METHOD.pvd time series)
//! units = "input"            # simulation (default) or input: the mesh file's units
//! ```

use std::path::{Path, PathBuf};

use glam::{DQuat, DVec3};
use serde::Deserialize;

use crate::overrides::{MaterialOverrides, SolverOverrides};

mod collider;
mod grab;
mod pin;
mod text;
pub use text::{scene_json, scene_toml};

use collider::mesh_grid;
pub use collider::{Collider, KeyframeSpec, MotionSpec, DEFAULT_CELLS, QUATERNION_TOLERANCE};
pub use grab::GrabSpec;
pub use pin::{Aabb, Pin, Pins};

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
    /// Handles holding nodes (`[[grab]]`, applied in order after the objects are placed).
    #[serde(rename = "grab", default)]
    pub grabs: Vec<GrabSpec>,
    /// What to write.
    #[serde(default)]
    pub output: Output,
    /// Warnings of the text it was read from: old key names ([`crate::renamed`]).
    #[serde(skip)]
    pub warnings: Vec<String>,
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
    /// Simulation method; absent: [`material_method`] of the object's parameters (the
    /// finite elements for a material given by its Young's modulus, else `volume`).
    #[serde(default)]
    pub method: Option<Method>,
    /// Largest bounding-box side after scaling [m]; absent keeps the mesh's size.
    #[serde(default)]
    pub fit_size: Option<f64>,
    /// Height of the lowest node above `y = 0` [m], centred in X and Z; absent keeps the
    /// mesh where it is.
    #[serde(default)]
    pub drop_height: Option<f64>,
    /// Turns the mesh about the centre of its bounding box before it is placed (a unit
    /// quaternion `[w, x, y, z]`, as colliders and keyframes take); absent: as in the file.
    #[serde(default)]
    pub rotation: Option<[f64; 4]>,
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

/// The method of an object that names none, from its parameters `params`: `neo-hookean`,
/// the finite elements, for a material given by its Young's modulus, unless the parameters
/// ask for what only the spring methods take (implicit or warm-started springs, another
/// solver, MINRES, Anderson, blocks, inversion sweeps, a relaxation); `volume` otherwise,
/// the paper's method that holds the volume (issue 51: a material should act as its E and
/// nu say wherever the caller did not choose otherwise).
pub fn material_method(params: &SimParams) -> Method {
    let elastic = SimParams {
        method: Method::NeoHookean,
        ..params.clone()
    };
    match params.youngs_modulus.is_some() && elastic.validate().is_ok() {
        true => Method::NeoHookean,
        false => Method::Volume,
    }
}

/// `[output]`: files to write.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// The run records as JSON (`metrics` in older scenes).
    #[serde(alias = "metrics")]
    pub json: Option<PathBuf>,
    /// Folder for the deformed mesh every `every` frames (the flag's name, `--out-dir`;
    /// `dir` and `surface_dir` before 2026-12-06, still read with a warning).
    #[serde(rename = "out_dir", alias = "dir", alias = "surface_dir")]
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
        let scene = Scene::parse(&text).map_err(|e| match e {
            Error::Param { key, message } => {
                Error::param(key, format!("{message} (in {})", path.display()))
            }
            other => other,
        })?;
        Ok(scene.relative_to(path.parent().unwrap_or(Path::new("."))))
    }

    /// The scene with its relative paths (meshes, mesh colliders, outputs) taken relative
    /// to the folder `base`.
    pub fn relative_to(mut self, base: &Path) -> Scene {
        let scene = &mut self;
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
        self
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
        let tables: toml::Value = toml::from_str(text)
            .map_err(|e| Error::param("scene", format!("not TOML: {}", e.message())))?;
        Ok(Scene {
            warnings: crate::renamed::scene_warnings(&tables),
            ..scene
        })
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
            .check(|name| format!("output.{name}"), "output.out_dir")?;
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
            self.rotation_for(i)?;
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
        for (k, grab) in self.grabs.iter().enumerate() {
            let key = format!("grab[{k}]");
            grab.grab(&key)?.validate(&key)?;
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
            method: o.method.unwrap_or(Method::Volume),
            floor: floor.is_some(),
            friction: floor.unwrap_or(0.0),
            ..self.base.clone()
        };
        self.solver.apply(&mut params);
        o.material.apply(&mut params);
        if o.method.is_none() {
            params.method = material_method(&params);
        }
        params
    }

    /// The rotation of object `index` (normalised; the identity when none is given), or an
    /// error naming `object[i].rotation` unless it is a unit quaternion.
    pub fn rotation_for(&self, index: usize) -> Result<DQuat> {
        match self.objects[index].rotation {
            Some(q) => collider::quaternion(&format!("object[{index}].rotation"), q),
            None => Ok(DQuat::IDENTITY),
        }
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

/// Where a [`SimParams`] key lives in a scene file.
fn scene_key(object: usize, key: &str) -> String {
    match key {
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
mod tests;

#[cfg(test)]
mod collider_tests;

#[cfg(test)]
mod pin_tests;
