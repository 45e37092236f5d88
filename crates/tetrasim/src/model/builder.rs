//! [`ModelBuilder`]: a [`Model`] from a tet mesh (placement, orientation, springs, masses,
//! pins, adjacency), validated once.

use glam::{DQuat, DVec3};

use super::*;

/// Builds a [`Model`] from a tet mesh: placement, orientation, springs, masses, adjacency.
#[derive(Debug, Clone)]
pub struct ModelBuilder<'a> {
    mesh: &'a TetMesh,
    placement: Placement,
    mass: MassMode,
    pinned: Vec<u32>,
    pin_boxes: Vec<(DVec3, DVec3)>,
    pin_motion: crate::collider::Motion,
    self_contact: bool,
    velocity: DVec3,
    offset: DVec3,
    rotation: DQuat,
    material: Option<SimParams>,
}

impl<'a> ModelBuilder<'a> {
    /// A builder with the default placement (`seed`) and unit node masses.
    pub fn new(mesh: &'a TetMesh) -> Self {
        ModelBuilder {
            mesh,
            placement: Placement::default(),
            mass: MassMode::PerNode { mass: 1.0 },
            pinned: Vec::new(),
            pin_boxes: Vec::new(),
            pin_motion: crate::collider::Motion::Fixed,
            self_contact: false,
            velocity: DVec3::ZERO,
            offset: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            material: None,
        }
    }

    /// Gives the model its own per-element material, the one `params` describe (their
    /// `ks`, `kd` or Young's modulus, Poisson's ratio and damping; see
    /// [`ElementMaterial::new`]), and the masses of `params.mass`. Without it the solver's
    /// parameters decide.
    pub fn material(mut self, params: &SimParams) -> Self {
        self.mass = params.mass;
        self.material = Some(params.clone());
        self
    }

    /// Where to put the mesh.
    pub fn placement(mut self, placement: Placement) -> Self {
        self.placement = placement;
        self
    }

    /// Moves the placed mesh by `offset` [m] (after `fit_size` and `drop_height`; pin boxes
    /// and the recorded placement see the moved mesh), so that objects start apart.
    pub fn offset(mut self, offset: DVec3) -> Self {
        self.offset = offset;
        self
    }

    /// Turns the mesh by `rotation` about the centre of its bounding box before it is
    /// placed (`fit_size` and `drop_height` then see the turned mesh): a Z-up part turned
    /// -90 degrees about X stands on the floor `y = 0`. Normalised by [`Self::build`].
    pub fn rotation(mut self, rotation: DQuat) -> Self {
        self.rotation = rotation;
        self
    }

    /// How to assign node masses.
    pub fn mass(mut self, mass: MassMode) -> Self {
        self.mass = mass;
        self
    }

    /// Nodes that never move (inverse mass 0).
    pub fn pinned(mut self, nodes: impl IntoIterator<Item = u32>) -> Self {
        self.pinned.extend(nodes);
        self
    }

    /// Also pins every node inside the axis-aligned box `[lo, hi]` (placed coordinates, m).
    pub fn pinned_in_box(mut self, lo: DVec3, hi: DVec3) -> Self {
        self.pin_boxes.push((lo, hi));
        self
    }

    /// Moves every node pinned by [`Self::pinned`] and [`Self::pinned_in_box`] rigidly with
    /// `motion` about their centroid (a clamp; [`crate::collider::Clamp`]). The motion is
    /// checked by [`Self::build`] (named `pin.motion`).
    pub fn pin_motion(mut self, motion: crate::collider::Motion) -> Self {
        self.pin_motion = motion;
        self
    }

    /// Whether the object's surface collides with itself (off by default).
    pub fn self_contact(mut self, on: bool) -> Self {
        self.self_contact = on;
        self
    }

    /// Initial velocity of every free node [m/s] (pinned nodes start at rest).
    pub fn velocity(mut self, velocity: DVec3) -> Self {
        self.velocity = velocity;
        self
    }

    /// Validates the mesh and computes all rest data.
    pub fn build(self) -> Result<Model> {
        let mesh = self.mesh;
        let n = mesh.nodes.len();
        if n == 0 || mesh.tets.is_empty() {
            return Err(Error::Mesh(format!(
                "the mesh is empty ({n} nodes, {} tets)",
                mesh.tets.len()
            )));
        }
        if let Some(i) = mesh.nodes.iter().position(|p| !p.is_finite()) {
            return Err(Error::Mesh(format!(
                "node {i} has a non-finite coordinate {:?}",
                mesh.nodes[i]
            )));
        }
        for (t, tet) in mesh.tets.iter().enumerate() {
            if let Some(&bad) = tet.iter().find(|&&v| v as usize >= n) {
                return Err(Error::Mesh(format!(
                    "tet {t} refers to node {bad}, but there are {n} nodes"
                )));
            }
        }
        let turn = turn_about_centre(&mesh.nodes, self.rotation)?;
        let turned: Vec<DVec3> = mesh.nodes.iter().map(|&p| turn.apply(p)).collect();
        let placed = place(&turned, self.placement)?;
        let mut placement = Similarity {
            scale: placed.scale,
            rotation: turn.rotation,
            offset: turn.offset * placed.scale + placed.offset,
        };
        if !self.offset.is_finite() {
            return Err(Error::param(
                "offset",
                format!("must be finite, not {:?}", self.offset),
            ));
        }
        placement.offset += self.offset;
        let positions: Vec<DVec3> = mesh.nodes.iter().map(|&p| placement.apply(p)).collect();
        let diag = bounds_of(&positions)
            .map(|(lo, hi)| (hi - lo).length())
            .unwrap_or(0.0);
        let degenerate = 1e-14 * diag.powi(3);

        let mut tets = mesh.tets.clone();
        let mut rest_volume = Vec::with_capacity(tets.len());
        for (t, tet) in tets.iter_mut().enumerate() {
            let p = tet.map(|v| positions[v as usize]);
            let mut v = tet_volume(p);
            if v.abs() <= degenerate {
                return Err(Error::Mesh(format!(
                    "tet {t} {tet:?} is degenerate (volume {v:e} m^3)"
                )));
            }
            if v < 0.0 {
                tet.swap(2, 3);
                v = -v;
            }
            rest_volume.push(v);
        }

        let springs = topology::unique_edges(&tets);
        let rest_length = springs
            .iter()
            .map(|s| positions[s[0] as usize].distance(positions[s[1] as usize]))
            .collect();

        let mass = match self.mass {
            MassMode::PerNode { mass } => vec![mass; n],
            MassMode::Density { density } => {
                let mut m = vec![0.0; n];
                for (tet, v) in tets.iter().zip(&rest_volume) {
                    for &i in tet {
                        m[i as usize] += density * v / 4.0;
                    }
                }
                m
            }
        };
        let mut inv_mass: Vec<f64> = mass
            .iter()
            .map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 })
            .collect();
        for &p in &self.pinned {
            let slot = inv_mass.get_mut(p as usize).ok_or_else(|| {
                Error::Mesh(format!("pinned node {p} does not exist ({n} nodes)"))
            })?;
            *slot = 0.0;
        }
        for (i, p) in positions.iter().enumerate() {
            if self
                .pin_boxes
                .iter()
                .any(|(lo, hi)| p.cmpge(*lo).all() && p.cmple(*hi).all())
            {
                inv_mass[i] = 0.0;
            }
        }
        if !self.velocity.is_finite() {
            return Err(Error::param(
                "velocity",
                format!("must be finite, got {}", self.velocity),
            ));
        }
        let velocities = inv_mass
            .iter()
            .map(|&w| if w > 0.0 { self.velocity } else { DVec3::ZERO })
            .collect();
        self.pin_motion.validate("pin.motion")?;
        let held: Vec<u32> = (0..n as u32)
            .filter(|&i| inv_mass[i as usize] == 0.0 && mass[i as usize] > 0.0)
            .collect();
        let clamps = match (self.pin_motion.is_moving(), held.is_empty()) {
            (true, false) => vec![crate::collider::Clamp {
                centre: held.iter().map(|&i| positions[i as usize]).sum::<DVec3>()
                    / held.len() as f64,
                nodes: held,
                motion: self.pin_motion.clone(),
            }],
            (true, true) => {
                return Err(Error::param(
                    "pin.motion",
                    "moves no node: the pin holds none (give `nodes` or a `box` that \
                     contains nodes)",
                ))
            }
            (false, _) => Vec::new(),
        };

        let node_springs = adjacency(n, springs.iter().map(|s| s.as_slice()));
        let mut tet_degree = vec![0u32; n];
        for tet in &tets {
            for &i in tet {
                tet_degree[i as usize] += 1;
            }
        }
        let surface = if mesh.faces.is_empty() {
            topology::boundary_faces(&tets)
        } else {
            mesh.faces.clone()
        };

        let mut model = Model {
            positions,
            velocities,
            mass,
            inv_mass,
            springs,
            rest_length,
            tets,
            rest_volume,
            node_springs,
            tet_degree,
            surface,
            objects: vec![0, n as u32],
            placements: vec![placement],
            material: None,
            colliders: Vec::new(),
            clamps,
            self_contact: vec![self.self_contact],
            grabs: Vec::new(),
        };
        model.material = self
            .material
            .map(|params| ElementMaterial::new(&model, &params));
        Ok(model)
    }
}

/// The rotation `rotation` (normalised) about the centre of `nodes`' bounding box; an error
/// naming `rotation` for a quaternion that is not finite or has no length.
fn turn_about_centre(nodes: &[DVec3], rotation: DQuat) -> Result<Similarity> {
    let length = rotation.length();
    if !rotation.is_finite() || length < 1e-9 {
        return Err(Error::param(
            "rotation",
            format!(
                "must be a finite, non-zero quaternion [w, x, y, z], got {:?}",
                [rotation.w, rotation.x, rotation.y, rotation.z]
            ),
        ));
    }
    let rotation = rotation / length;
    if rotation == DQuat::IDENTITY {
        return Ok(Similarity::IDENTITY);
    }
    let (lo, hi) = bounds_of(nodes).ok_or_else(|| Error::Mesh("the mesh has no nodes".into()))?;
    let centre = (lo + hi) * 0.5;
    Ok(Similarity {
        scale: 1.0,
        rotation,
        offset: centre - rotation * centre,
    })
}

/// The map that applies a [`Placement`] to a point set.
fn place(nodes: &[DVec3], placement: Placement) -> Result<Similarity> {
    let (lo, hi) = bounds_of(nodes).ok_or_else(|| Error::Mesh("the mesh has no nodes".into()))?;
    let mut scale = 1.0;
    if let Some(size) = placement.fit_size {
        let largest = (hi - lo).max_element();
        if largest <= 0.0 {
            return Err(Error::Mesh(
                "the mesh has zero extent; it cannot be scaled".into(),
            ));
        }
        scale = size / largest;
    }
    let mut offset = DVec3::ZERO;
    if let Some(height) = placement.drop_height {
        offset.y = height - lo.y * scale;
        if placement.fit_size.is_some() {
            let centre = (lo + hi) * 0.5 * scale;
            (offset.x, offset.z) = (-centre.x, -centre.z);
        }
    }
    Ok(Similarity {
        scale,
        rotation: DQuat::IDENTITY,
        offset,
    })
}
