//! Element counts and sizes a plan is made from: the model's, the global volume
//! constraints', the constraint sweeps', and the published bandwidths of some GPUs.

/// Element counts of a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlanCounts {
    /// Nodes.
    pub nodes: u32,
    /// Springs.
    pub springs: u32,
    /// Tetrahedra.
    pub tets: u32,
    /// Kinematic colliders ([`crate::model::Model::colliders`]).
    pub colliders: u32,
    /// Distance-grid samples of all mesh colliders.
    pub grid_values: u32,
    /// Clamps ([`crate::model::Model::clamps`]).
    pub clamps: u32,
    /// Nodes held by clamps.
    pub clamped: u32,
    /// Nodes held by grabs (each once).
    pub grabbed: u32,
    /// Tets whose volume constraint is compliant (a problem's material says; every tet
    /// when only the model is known).
    pub compliant_tets: u32,
}

impl PlanCounts {
    /// The counts of `model` (an error when one exceeds the engine's u32 indices).
    pub fn of(model: &crate::model::Model) -> crate::Result<Self> {
        let count = |what: &str, n: usize| {
            u32::try_from(n).map_err(|_| {
                crate::Error::Mesh(format!("{n} {what} exceed the GPU engine's u32 indices"))
            })
        };
        Ok(PlanCounts {
            nodes: count("nodes", model.node_count())?,
            springs: count("springs", model.springs.len())?,
            tets: count("tets", model.tets.len())?,
            colliders: count("colliders", model.colliders.len())?,
            clamps: count("clamps", model.clamps.len())?,
            grabbed: count("grabbed nodes", grabbed_nodes(&model.grabs).len())?,
            compliant_tets: count("tets", model.tets.len())?,
            clamped: count(
                "clamped nodes",
                model.clamps.iter().map(|c| c.nodes.len()).sum(),
            )?,
            grid_values: count(
                "collider grid samples",
                (model.colliders.iter())
                    .map(|c| match &c.shape {
                        crate::collider::Shape::Grid(g) => g.values.len(),
                        _ => 0,
                    })
                    .sum(),
            )?,
        })
    }
}

/// The nodes any of `grabs` holds, ascending, each once: the rows of the grab targets.
pub fn grabbed_nodes(grabs: &[crate::collider::Grab]) -> Vec<u32> {
    let mut nodes: Vec<u32> = grabs.iter().flat_map(|g| g.nodes.iter().copied()).collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// Peak memory bandwidth of some GPUs [bytes/s], from the vendors' data sheets, for the
/// memory-bound estimate `tetrasim plan` prints.
pub const PEAK_BANDWIDTH: [(&str, f64); 4] = [
    ("NVIDIA H100 SXM5 80GB", 3.35e12),
    ("NVIDIA A100 SXM4 80GB", 2.039e12),
    ("NVIDIA GeForce RTX 4090", 1.008e12),
    ("NVIDIA GeForce RTX 3060", 360e9),
];

/// Sizes of the global volume constraints ([`crate::model::GlobalVolume`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GlobalCounts {
    /// Objects (one constraint each).
    pub objects: u32,
    /// Surface nodes of all objects.
    pub nodes: u32,
    /// Boundary faces of all objects.
    pub faces: u32,
    /// The most surface nodes or faces of one object: the global passes give every object
    /// as many chunks (workgroups) as this needs.
    pub largest: u32,
    /// The most surface nodes of one object (MINRES's global row has an entry for each).
    pub largest_nodes: u32,
}

impl GlobalCounts {
    /// The sizes of `global`.
    pub fn of(global: &crate::model::GlobalVolume) -> Self {
        GlobalCounts {
            objects: global.objects.len() as u32,
            nodes: global.nodes.len() as u32,
            faces: global.faces.len() as u32,
            largest: global
                .objects
                .iter()
                .map(|o| o.node_count.max(o.face_count))
                .max()
                .unwrap_or(0),
            largest_nodes: global
                .objects
                .iter()
                .map(|o| o.node_count)
                .max()
                .unwrap_or(0),
        }
    }

    /// Chunks (workgroups of `workgroup_size`) per object in the global passes: each
    /// reduces its share of its object's faces and surface nodes to one partial sum.
    pub fn chunks(&self, workgroup_size: u32) -> u32 {
        self.largest.div_ceil(workgroup_size.max(1)).max(1)
    }
}

/// Where one sweep's data starts in the buffers that hold every sweep one after another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SweepOffsets {
    /// Its first group, counted over all sweeps (degrees, slot rows).
    pub group: u32,
    /// Its first position in the group members.
    pub member: u32,
    /// Its first slot in the contributions.
    pub slot: u32,
    /// Its first row in the block rows (block Gauss-Seidel).
    pub block: u32,
}

/// Sizes of body contact ([`crate::contact::BodyContact`]) and its broad phase on the GPU.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyCounts {
    /// Surface nodes (one contact record each).
    pub nodes: u32,
    /// Surface triangles.
    pub triangles: u32,
    /// Hash buckets: a power of two, at least 8 per triangle.
    pub buckets: u32,
    /// Hash items the item array holds: 64 per triangle (a triangle of the rest mesh's
    /// median edge covers at most 27 cells of twice the reach; more, from a stretched
    /// surface, fail the frame with status flag 4 rather than lose contacts silently).
    pub capacity: u32,
    /// Contact thickness [m].
    pub thickness: f64,
    /// Detection margin [m].
    pub margin: f64,
}

impl BodyCounts {
    /// The sizes of `bodies`.
    pub fn of(bodies: &crate::contact::BodyContact) -> Self {
        let triangles = bodies.triangles.len() as u32;
        BodyCounts {
            nodes: bodies.nodes.len() as u32,
            triangles,
            buckets: (8 * triangles).max(1024).next_power_of_two(),
            capacity: (64 * triangles).max(1024),
            thickness: bodies.thickness,
            margin: bodies.margin,
        }
    }

    /// The specialisation constants of the body contact passes (glsl/physics/bodies.glsl,
    /// ids 1 to 6).
    pub fn constants(&self) -> Vec<u32> {
        vec![
            self.nodes,
            self.triangles,
            self.buckets,
            self.capacity,
            (self.thickness as f32).to_bits(),
            (self.margin as f32).to_bits(),
        ]
    }
}
