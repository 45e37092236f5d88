//! The static model: everything about the object that does not change during a run,
//! built and validated once on the CPU from a [`TetMesh`]. Every backend reads the same model.

mod blocks;
mod builder;
mod global;
mod groups;
mod material;

pub use blocks::{BlockLimits, ConstraintBlocks, HUB_DEGREE, MAX_BLOCK_NODES};
pub use builder::ModelBuilder;

pub use global::{GlobalObject, GlobalVolume};
pub use groups::{greedy_colours, ConstraintGroups};
pub use material::{bulk_modulus, ElementMaterial};

use std::borrow::Cow;

use glam::{DQuat, DVec3};

use crate::error::{Error, Result};
use crate::mesh::{bounds_of, topology, TetMesh};
use crate::params::{MassMode, Method, Placement, SimParams, Solver, SpringKind};
use crate::physics::tet_volume;

/// Compressed sparse rows: `items[offsets[i]..offsets[i + 1]]` belong to row `i`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Csr {
    /// `rows + 1` offsets into `items`.
    pub offsets: Vec<u32>,
    /// Row entries.
    pub items: Vec<u32>,
}

impl Csr {
    /// The one CSR builder: `rows` rows filled from `pairs()`, `(row, item)` in order (a
    /// counting sort; each row keeps its items in the order `pairs` gives them). `pairs` is
    /// called twice, to count and to fill.
    pub fn from_pairs<I: Iterator<Item = (usize, u32)>>(rows: usize, pairs: impl Fn() -> I) -> Csr {
        let mut offsets = vec![0u32; rows + 1];
        for (row, _) in pairs() {
            offsets[row + 1] += 1;
        }
        for r in 0..rows {
            offsets[r + 1] += offsets[r];
        }
        let mut fill = offsets.clone();
        let mut items = vec![0u32; offsets[rows] as usize];
        for (row, item) in pairs() {
            items[fill[row] as usize] = item;
            fill[row] += 1;
        }
        Csr { offsets, items }
    }

    /// Entries of row `i`.
    pub fn row(&self, i: usize) -> &[u32] {
        &self.items[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }
}

/// Rest data of one object. Positions are the initial positions after placement.
#[derive(Debug, Clone)]
pub struct Model {
    /// Initial node positions [m].
    pub positions: Vec<DVec3>,
    /// Initial node velocities [m/s] (zero for pinned nodes). Every backend starts from them.
    pub velocities: Vec<DVec3>,
    /// Node masses [kg] (a pinned node keeps its mass here, but its inverse mass is 0).
    pub mass: Vec<f64>,
    /// Inverse masses [1/kg]; 0 pins the node.
    pub inv_mass: Vec<f64>,
    /// Springs: the unique edges of all tets, `[low, high]`.
    pub springs: Vec<[u32; 2]>,
    /// Rest length of each spring [m].
    pub rest_length: Vec<f64>,
    /// Tetrahedra, positively oriented (two indices swapped at build time where needed).
    pub tets: Vec<[u32; 4]>,
    /// Signed rest volume of each tet [m^3], all > 0.
    pub rest_volume: Vec<f64>,
    /// For each node, the springs touching it (node-centric order).
    pub node_springs: Csr,
    /// For each node, the number of tets touching it (`d_k` of the volume constraints).
    pub tet_degree: Vec<u32>,
    /// Boundary triangles, outward, for rendering and surface output.
    pub surface: Vec<[u32; 3]>,
    /// Node offsets of the objects (`objects + 1` entries): object `k` owns nodes
    /// `objects[k]..objects[k + 1]` and the tets and springs among them.
    pub objects: Vec<u32>,
    /// How each object's mesh was placed: simulation position = `placements[k]` applied to
    /// the mesh file's position (one entry per object). Outputs use it to write in the
    /// input's units and position.
    pub placements: Vec<Similarity>,
    /// The material of each spring and tet, when the builder was given one (scenes and
    /// `run` give every object its own); `None`: the solver's `ks`, `kd` and hard volume
    /// constraints ([`Model::element_material`]).
    pub material: Option<ElementMaterial>,
    /// The kinematic colliders every object meets (besides the floor of
    /// [`SimParams::floor`]); none unless a scene or [`Model::with_colliders`] adds them.
    pub colliders: Vec<crate::collider::Collider>,
    /// Pinned nodes that move (each set follows its motion from its initial positions);
    /// none unless [`ModelBuilder::pin_motion`] gives the pins a motion.
    pub clamps: Vec<crate::collider::Clamp>,
    /// Per object, whether its surface collides with itself ([`ModelBuilder::self_contact`];
    /// different objects always collide, [`crate::contact`]).
    pub self_contact: Vec<bool>,
    /// Grabs holding nodes to moving handles ([`Model::with_grab`]).
    pub grabs: Vec<crate::collider::Grab>,
}

/// A rotation, a uniform scale and a translation: `p -> scale * (rotation p) + offset`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Similarity {
    /// Uniform scale factor (> 0).
    pub scale: f64,
    /// Rotation applied first (a unit quaternion).
    pub rotation: DQuat,
    /// Translation applied after rotating and scaling.
    pub offset: DVec3,
}

impl Similarity {
    /// The identity map.
    pub const IDENTITY: Similarity = Similarity {
        scale: 1.0,
        rotation: DQuat::IDENTITY,
        offset: DVec3::ZERO,
    };

    /// The image of point `p`.
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.rotation * p * self.scale + self.offset
    }

    /// The point that maps to `p` (from simulation back to the input's frame).
    pub fn invert_point(&self, p: DVec3) -> DVec3 {
        self.rotation.inverse() * ((p - self.offset) / self.scale)
    }

    /// A displacement or velocity `v` expressed in the input's units and axes.
    pub fn invert_vector(&self, v: DVec3) -> DVec3 {
        self.rotation.inverse() * (v / self.scale)
    }
}

impl Model {
    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of springs touching each node (`d_k` of the distance constraints).
    pub fn spring_degree(&self, node: usize) -> u32 {
        self.node_springs.offsets[node + 1] - self.node_springs.offsets[node]
    }

    /// For each node, the number of the method's constraints touching it (`d_k` of the
    /// momentum-conserving scaling): springs for `distance`, tets for `volume`; `None` for
    /// the springs-only methods.
    pub fn constraint_degrees(&self, method: crate::params::Method) -> Option<Vec<u32>> {
        use crate::params::Method;
        match method {
            Method::Mss | Method::MssNode => None,
            Method::Distance => Some(
                (0..self.node_count())
                    .map(|i| self.spring_degree(i))
                    .collect(),
            ),
            Method::Volume => Some(self.tet_degree.clone()),
            Method::NeoHookean => Some(vec![1; self.node_count()]),
        }
    }

    /// The method's constraints split into the groups `solver` solves in sequence (one group
    /// for Jacobi, `groups` colour groups for Gauss-Seidel); `None` for the springs-only
    /// methods.
    pub fn constraint_groups(
        &self,
        method: crate::params::Method,
        solver: crate::params::Solver,
        groups: u32,
    ) -> Option<ConstraintGroups> {
        use crate::params::{Method, Solver};
        let n = self.node_count();
        match (method, solver) {
            (Method::Mss | Method::MssNode, _) => None,
            (Method::NeoHookean, _) => Some(ConstraintGroups::single(&node_elements(n), n)),
            (Method::Distance, Solver::Jacobi | Solver::Chebyshev) => {
                Some(ConstraintGroups::single(&self.springs, n))
            }
            (Method::Volume, Solver::Jacobi | Solver::Chebyshev) => {
                Some(ConstraintGroups::single(&self.tets, n))
            }
            (Method::Distance, Solver::GaussSeidel) => {
                Some(ConstraintGroups::coloured(&self.springs, n, groups))
            }
            (Method::Volume, Solver::GaussSeidel) => {
                Some(ConstraintGroups::coloured(&self.tets, n, groups))
            }
        }
    }

    /// The material of each spring and tet: the model's own, else the one `params` describe
    /// ([`ElementMaterial::new`]).
    pub fn element_material(&self, params: &SimParams) -> Cow<'_, ElementMaterial> {
        match &self.material {
            Some(m) => Cow::Borrowed(m),
            None => Cow::Owned(ElementMaterial::new(self, params)),
        }
    }

    /// The constraint sweeps of one iteration, in order: the implicit springs (when
    /// `params.springs` asks for them), then the method's constraints (distance or volume),
    /// each split into the groups `params.solver` solves in sequence. Empty for explicit
    /// springs-only methods.
    pub fn constraint_sweeps(&self, params: &SimParams) -> Vec<Sweep> {
        let n = self.node_count();
        let split = |kind: ConstraintKind| {
            if params.solves_in_blocks() {
                let (groups, blocks) = match kind {
                    ConstraintKind::Volume => {
                        ConstraintGroups::blocked(&self.tets, n, params.block_size)
                    }
                    _ => ConstraintGroups::blocked(&self.springs, n, params.block_size),
                };
                return Sweep {
                    kind,
                    groups,
                    blocks: Some(blocks),
                };
            }
            let groups = match (kind, params.solver) {
                (ConstraintKind::Volume, Solver::GaussSeidel) => {
                    ConstraintGroups::coloured(&self.tets, n, params.groups)
                }
                (ConstraintKind::Volume, _) => ConstraintGroups::single(&self.tets, n),
                (_, Solver::GaussSeidel) => {
                    ConstraintGroups::coloured(&self.springs, n, params.groups)
                }
                _ => ConstraintGroups::single(&self.springs, n),
            };
            Sweep {
                kind,
                groups,
                blocks: None,
            }
        };
        let mut sweeps = Vec::new();
        if params.method == Method::NeoHookean {
            sweeps.push(Sweep {
                kind: ConstraintKind::Elastic,
                groups: ConstraintGroups::single(&node_elements(n), n),
                blocks: None,
            });
        }
        if params.springs == SpringKind::Implicit && params.has_springs() {
            sweeps.push(split(ConstraintKind::Spring));
        }
        match params.method {
            Method::Distance => sweeps.push(split(ConstraintKind::Distance)),
            Method::Volume => sweeps.push(split(ConstraintKind::Volume)),
            Method::Mss | Method::MssNode | Method::NeoHookean => {}
        }
        sweeps
    }

    /// Sum of rest volumes [m^3].
    pub fn total_rest_volume(&self) -> f64 {
        self.rest_volume.iter().sum()
    }

    /// Length of the bounding-box diagonal of the initial positions [m].
    pub fn bounds_diagonal(&self) -> f64 {
        bounds_of(&self.positions)
            .map(|(lo, hi)| (hi - lo).length())
            .unwrap_or(0.0)
    }
}

/// The kind of a constraint solved in the iterations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ConstraintKind {
    /// An implicit spring: `C = |x_i - x_j| - L` with compliance `1 / k_e` and damping.
    Spring,
    /// The paper's distance constraint `C = |x_i - x_j|^2 - L^2`, hard.
    Distance,
    /// The volume constraint `C = V - V0`, hard or with the material's compliance.
    Volume,
    /// A node's Newton step on the finite elements' energy of its tets (its "constraint" is
    /// the node itself; one group of all nodes).
    Elastic,
}

impl ConstraintKind {
    /// Sweeps of each block per iteration of this kind under `params` (block Gauss-Seidel):
    /// the implicit springs' [`SimParams::spring_sweeps`], every other kind's
    /// `block_sweeps`.
    pub fn block_sweeps(self, params: &SimParams) -> u32 {
        match self {
            ConstraintKind::Spring => params.spring_sweeps(),
            _ => params.block_sweeps,
        }
    }
}

/// One kind of constraint in the groups solved one after another.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    /// What the constraints are (springs for `Spring` and `Distance`, tets for `Volume`).
    pub kind: ConstraintKind,
    /// The constraints (spring or tet indices) in their groups.
    pub groups: ConstraintGroups,
    /// Block Gauss-Seidel's blocks of the one group (`block_size > 0`).
    pub blocks: Option<ConstraintBlocks>,
}

impl Model {
    /// The same model with `colliders` added (each is checked; `collider[k]` names a bad
    /// one, counted from the model's first).
    pub fn with_colliders(
        mut self,
        colliders: impl IntoIterator<Item = crate::collider::Collider>,
    ) -> Result<Self> {
        for c in colliders {
            c.validate(&format!("collider[{}]", self.colliders.len()))?;
            self.colliders.push(c);
        }
        Ok(self)
    }

    /// The same model with `grab` holding every free node within its radius of its point
    /// (at the initial positions). Fails, naming `grab[k]`, on a bad grab or one that
    /// catches no node.
    pub fn with_grab(mut self, mut grab: crate::collider::Grab) -> Result<Self> {
        let key = format!("grab[{}]", self.grabs.len());
        grab.validate(&key)?;
        grab.nodes = (0..self.node_count() as u32)
            .filter(|&i| {
                self.inv_mass[i as usize] > 0.0
                    && self.positions[i as usize].distance(grab.point) <= grab.radius
            })
            .collect();
        if grab.nodes.is_empty() {
            return Err(Error::param(
                &key,
                format!(
                    "catches no node: no free node within {} m of {}",
                    grab.radius, grab.point
                ),
            ));
        }
        self.grabs.push(grab);
        Ok(self)
    }

    /// When the first free node would touch the floor (when `floor`) or a fixed collider,
    /// falling freely from the start state under `gravity` [m/s^2] [s]: the earlier of
    /// [`Self::floor_contact_time`] and [`crate::collider::free_fall_contact_time`]; `None`
    /// if neither is ever reached (a collider: within [`crate::collider::HORIZON_S`]).
    pub fn contact_time(&self, gravity: DVec3, floor: bool) -> Option<f64> {
        let floor = floor.then(|| self.floor_contact_time(gravity)).flatten();
        let collider = (!self.colliders.is_empty())
            .then(|| {
                let free: Vec<(DVec3, DVec3)> = self.free_nodes().map(|(p, v)| (*p, *v)).collect();
                crate::collider::free_fall_contact_time(&self.colliders, &free, gravity)
            })
            .flatten();
        floor.into_iter().chain(collider).min_by(f64::total_cmp)
    }

    /// The start position and velocity of every node that can move.
    fn free_nodes(&self) -> impl Iterator<Item = (&DVec3, &DVec3)> {
        self.positions
            .iter()
            .zip(&self.velocities)
            .zip(&self.inv_mass)
            .filter(|(_, &w)| w > 0.0)
            .map(|(pv, _)| pv)
    }

    /// When the first free node would reach the floor `y = 0` falling freely from the start
    /// state under `gravity` [m/s^2] [s]: 0 if one starts on or below it, `None` if none
    /// ever does. Exact until the first contact, since nothing but gravity acts on a body
    /// that starts at rest in its shape (an estimate for a deformed start).
    pub fn floor_contact_time(&self, gravity: DVec3) -> Option<f64> {
        // The acceleration toward the floor.
        let gravity = -gravity.y;
        self.free_nodes()
            .filter_map(|(p, v)| {
                let (y, vy) = (p.y, v.y);
                if y <= 0.0 {
                    return Some(0.0);
                }
                // y + vy t - g t^2 / 2 = 0, the first positive root.
                if gravity == 0.0 {
                    return (vy < 0.0).then(|| -y / vy);
                }
                let disc = vy * vy + 2.0 * gravity * y;
                if disc < 0.0 {
                    return None;
                }
                let t = (vy + disc.sqrt()) / gravity;
                (t > 0.0).then_some(t)
            })
            .min_by(f64::total_cmp)
    }

    /// Number of nodes that can move (inverse mass > 0).
    pub fn free_node_count(&self) -> usize {
        self.inv_mass.iter().filter(|&&w| w > 0.0).count()
    }

    /// Several models as one: nodes, springs and tets of `models[k]` follow those of
    /// `models[..k]`, indices shifted accordingly; colliders, clamps, grabs and self-contact
    /// flags are kept. The objects collide with each other ([`crate::contact`]) and share
    /// the solver, the floor and the colliders.
    pub fn concat(models: &[Model]) -> Result<Model> {
        let mut iter = models.iter();
        let mut out = iter
            .next()
            .cloned()
            .ok_or_else(|| Error::Mesh("no models to combine".into()))?;
        for m in iter {
            let nodes = u32::try_from(out.node_count())
                .map_err(|_| Error::Mesh("combined model exceeds u32 node indices".into()))?;
            let springs = out.springs.len() as u32;
            let items = out.node_springs.items.len() as u32;
            out.positions.extend_from_slice(&m.positions);
            out.velocities.extend_from_slice(&m.velocities);
            out.mass.extend_from_slice(&m.mass);
            out.inv_mass.extend_from_slice(&m.inv_mass);
            out.springs
                .extend(m.springs.iter().map(|s| s.map(|i| i + nodes)));
            out.rest_length.extend_from_slice(&m.rest_length);
            out.tets.extend(m.tets.iter().map(|t| t.map(|i| i + nodes)));
            out.rest_volume.extend_from_slice(&m.rest_volume);
            out.node_springs
                .offsets
                .extend(m.node_springs.offsets.iter().skip(1).map(|o| o + items));
            out.node_springs
                .items
                .extend(m.node_springs.items.iter().map(|s| s + springs));
            out.tet_degree.extend_from_slice(&m.tet_degree);
            out.surface
                .extend(m.surface.iter().map(|f| f.map(|i| i + nodes)));
            out.objects
                .extend(m.objects.iter().skip(1).map(|o| o + nodes));
            out.placements.extend_from_slice(&m.placements);
            out.colliders.extend_from_slice(&m.colliders);
            out.self_contact.extend_from_slice(&m.self_contact);
            out.grabs
                .extend(m.grabs.iter().map(|g| crate::collider::Grab {
                    nodes: g.nodes.iter().map(|i| i + nodes).collect(),
                    ..g.clone()
                }));
            out.clamps
                .extend(m.clamps.iter().map(|c| crate::collider::Clamp {
                    nodes: c.nodes.iter().map(|i| i + nodes).collect(),
                    ..c.clone()
                }));
            out.material = match (&out.material, &m.material) {
                (None, None) => None,
                (Some(a), Some(b)) => Some(ElementMaterial::concat(a, b)),
                _ => {
                    return Err(Error::Mesh(
                        "models with and without their own material cannot be combined".into(),
                    ))
                }
            };
        }
        Ok(out)
    }
}

/// Row `i` lists the indices of the elements that contain node `i`.
pub fn adjacency<'e>(nodes: usize, elements: impl Iterator<Item = &'e [u32]> + Clone) -> Csr {
    Csr::from_pairs(nodes, || {
        elements
            .clone()
            .enumerate()
            .flat_map(|(e, element)| element.iter().map(move |&v| (v as usize, e as u32)))
    })
}

/// The finite elements' "constraints": every node by itself, `[[i]]` (one group, all
/// nodes: the conjugate gradients update them together).
fn node_elements(nodes: usize) -> Vec<[u32; 1]> {
    (0..nodes as u32).map(|i| [i]).collect()
}
