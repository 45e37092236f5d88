//! The simulation's GPU buffers (the paper's Table 1 plus what each method needs), uploaded
//! once from the [`Model`]. Exactly the buffers of the [`EnginePlan`] are created, and each
//! one's size is checked against the plan.

use std::collections::BTreeMap;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::plan::{BufferId, EnginePlan};
use crate::backend::State;
use crate::contact::BodyContact;
use crate::gpu::layout::{vec4, GpuGlobalObject, GpuSpring};
use crate::gpu::{Buffer, Context, Uploads};
use crate::model::{ConstraintKind, GlobalVolume, Model, Sweep};
use crate::problem::Problem;
use crate::{Error, Result};

/// Device-local state and rest data, plus the host-visible copy of the volume partials.
pub(crate) struct SimBuffers {
    /// vec4 per node: position [m], w = inverse mass [1/kg].
    pub positions: Buffer,
    /// vec4 per node: velocity [m/s], w = mass [kg].
    pub velocities: Buffer,
    /// vec4 per node: the step's force F [N] (starts as m g).
    pub forces: Buffer,
    /// One [`GpuSpring`] per spring (with its stiffness).
    pub springs: Buffer,
    /// float per spring: its damping [N s/m].
    pub spring_damping: Buffer,
    /// uvec4 per tet.
    pub tets: Buffer,
    /// float per tet: rest volume [m^3] (the volume constraints' and the local volume
    /// error's; every method).
    pub rest_volumes: Buffer,
    /// Every other buffer the plan builds, by its id: what only some scenes need
    /// (compliances, multipliers, degrees, the gather path's, Chebyshev's, the global volume
    /// constraints', the node-spring adjacency, the colliders').
    pub optional: BTreeMap<BufferId, Buffer>,
    /// One [`crate::gpu::layout::VolumePartial`] per volume_sum workgroup (their host-visible
    /// copies belong to the frames that write them: `super::FrameSlot`).
    pub partials: Buffer,
    /// Divergence status: `[flags, first bad node, speed limit (f32 bits), fastest speed of
    /// a too-fast node (f32 bits)]`, then, when the frame measures contact, its contact
    /// words ([`super::plan::CONTACT_STATUS_BYTES`]).
    pub status: Buffer,
}

/// Initial `status`: no flags, no bad node (`u32::MAX`), the speed limit [m/s], no speed.
pub(crate) fn initial_status(speed_limit: f32) -> [u32; 4] {
    [0, u32::MAX, speed_limit.to_bits(), 0]
}

fn bytes<T: bytemuck::Pod>(v: &[T]) -> &[u8] {
    bytemuck::cast_slice(v)
}

fn floats(v: &[f64]) -> Vec<f32> {
    v.iter().map(|&x| x as f32).collect()
}

impl SimBuffers {
    /// Overwrites positions and velocities with `state`, keeping the model's inverse masses
    /// and masses in the `w` components (see [`crate::backend::Backend::set_state`]); with
    /// `gravity` (the finite elements, whose next step starts from the last one's forces),
    /// the forces become gravity's alone.
    pub fn upload_state(
        &self,
        state: &State,
        inv_mass: &[f64],
        mass: &[f64],
        gravity: Option<glam::DVec3>,
    ) -> Result<()> {
        let positions: Vec<[f32; 4]> = state
            .positions
            .iter()
            .zip(inv_mass)
            .map(|(&p, &w)| vec4(p, w))
            .collect();
        let velocities: Vec<[f32; 4]> = state
            .velocities
            .iter()
            .zip(mass)
            .map(|(&v, &m)| vec4(v, m))
            .collect();
        let mut uploads = Uploads::default();
        uploads.write(&self.positions, bytes(&positions))?;
        uploads.write(&self.velocities, bytes(&velocities))?;
        // A new state starts without warm-start multipliers (the implicit springs' stored
        // values count in iteration 0 only with `warm_start`; zeroing is harmless otherwise).
        if let Some(multipliers) = self.optional.get(&BufferId::SpringMultipliers) {
            uploads.zero(multipliers);
        }
        if let Some(g) = gravity {
            let forces: Vec<[f32; 4]> = mass.iter().map(|&m| vec4(g * m, 0.0)).collect();
            uploads.write(&self.forces, bytes(&forces))?;
        }
        uploads.submit(self.positions.context())
    }

    /// Uploads the problem's model as `plan` (made for it) says, with its constraint sweeps,
    /// per-element material and global volume constraints; its divergence speed limit
    /// [m/s] goes into `status`.
    pub fn new(ctx: &Arc<Context>, problem: &Problem, plan: &EnginePlan) -> Result<Self> {
        let (model, params) = (&problem.model, &problem.params);
        let (sweeps, global) = (&problem.sweeps, problem.global.as_ref());
        let speed_limit = problem.speed_limit as f32;
        let n = model.node_count();
        let material = &problem.material;
        let positions: Vec<[f32; 4]> = model
            .positions
            .iter()
            .zip(&model.inv_mass)
            .map(|(&p, &w)| vec4(p, w))
            .collect();
        let velocities: Vec<[f32; 4]> = model
            .velocities
            .iter()
            .zip(&model.mass)
            .map(|(&v, &m)| vec4(v, m))
            .collect();
        let forces: Vec<[f32; 4]> = model
            .mass
            .iter()
            .map(|&m| (params.gravity * m).as_vec3().extend(0.0).to_array())
            .collect();
        let springs: Vec<GpuSpring> = model
            .springs
            .iter()
            .zip(&model.rest_length)
            .zip(&material.spring_stiffness)
            .map(|((s, &l), &k)| GpuSpring {
                a: s[0],
                b: s[1],
                rest: l as f32,
                stiffness: k as f32,
            })
            .collect();
        // Per group (of every sweep, in order) and node: its constraint count d_k within
        // the group as a float; the shaders turn it into the A scale and apply weight of
        // `ConstraintCombine::node_factors` (push constant `combine`).
        let degrees = plan.has(BufferId::Degrees).then(|| {
            sweeps
                .iter()
                .flat_map(|w| w.groups.degree.iter().map(|&c| c as f32))
                .collect::<Vec<f32>>()
        });
        // Every initial upload goes into one batch: one staging buffer, one submit, one wait
        // (after the struct below owns every destination buffer).
        let mut up = Uploads::default();
        let mut upload = |id: BufferId, data: &[u8]| up.with_data(ctx, id.name(), data);
        let positions_buffer = upload(BufferId::Positions, bytes(&positions))?;
        let velocities_buffer = upload(BufferId::Velocities, bytes(&velocities))?;
        let forces_buffer = upload(BufferId::Forces, bytes(&forces))?;
        let springs_buffer = upload(BufferId::Springs, bytes(&springs))?;
        let spring_damping = upload(
            BufferId::SpringDamping,
            bytes(&floats(&material.spring_damping)),
        )?;
        let tets_buffer = upload(BufferId::Tets, bytes(&model.tets))?;
        let rest_volumes = upload(BufferId::RestVolumes, bytes(&floats(&model.rest_volume)))?;
        // With contact measures, the contact words follow (0: each frame zeroes them again).
        let mut status = initial_status(speed_limit).to_vec();
        if plan.measures_contact() {
            status.extend([0; 4]);
        }
        let status_buffer = upload(BufferId::Status, bytes(&status))?;
        let mut optional = Optional {
            ctx,
            up,
            plan,
            built: BTreeMap::new(),
        };
        if let Some(degrees) = degrees {
            optional.data(BufferId::Degrees, bytes(&degrees))?;
        }
        optional.data(
            BufferId::VolumeCompliance,
            bytes(&floats(&material.volume_compliance)),
        )?;
        optional.data(
            BufferId::NodeSpringOffsets,
            bytes(&model.node_springs.offsets),
        )?;
        optional.data(BufferId::NodeSpringItems, bytes(&model.node_springs.items))?;
        optional.zeroed(BufferId::ConstraintSum, (n * 16) as u64)?;
        optional.zeroed(BufferId::ChebyshevBefore, (n * 16) as u64)?;
        optional.zeroed(BufferId::SplitVelocities, (n * 16) as u64)?;
        // Anderson's history and sums: iteration 0 writes x, iteration 1 f and g, before any
        // read; zeroed all the same, at the plan's sizes.
        for id in [
            BufferId::AndersonHistory,
            BufferId::AndersonSums,
            BufferId::AndersonMultipliers,
        ] {
            let bytes = plan.buffer(id).map_or(0, |b| b.bytes);
            optional.zeroed(id, bytes)?;
        }
        // The multipliers need no initial values (iteration 0 writes before any read), but
        // for warm-started implicit springs, whose first step starts from 0: zeroed.
        optional.zeroed(
            BufferId::SpringMultipliers,
            (4 * model.springs.len()).max(4) as u64,
        )?;
        optional.zeroed(
            BufferId::VolumeMultipliers,
            (4 * model.tets.len()).max(4) as u64,
        )?;
        if plan.schedule.gather {
            gather_buffers(&mut optional, model, sweeps)?;
        }
        block_buffers(&mut optional, sweeps)?;
        if let Some(g) = global.filter(|_| plan.global.is_some()) {
            global_buffers(&mut optional, g)?;
        }
        if let Some(m) = plan.minres_counts() {
            let transpose = super::minres::transpose(model, global, &m);
            optional.data(BufferId::MinresTranspose, bytes(&transpose))?;
            for id in [
                BufferId::MinresGrads,
                BufferId::MinresVectors,
                BufferId::MinresNodeVectors,
                BufferId::MinresSums,
                BufferId::MinresState,
            ] {
                optional.zeroed(id, plan.buffer(id).map_or(0, |b| b.bytes))?;
            }
        }
        if plan.has(BufferId::Colliders) {
            collider_buffers(&mut optional, model)?;
        }
        if plan.has(BufferId::ClampNodes) {
            clamp_buffers(&mut optional, model)?;
        }
        if let Some(bodies) = problem.bodies.as_ref().filter(|_| plan.body.is_some()) {
            body_buffers(&mut optional, bodies, n)?;
        }
        optional.data(
            BufferId::NodeClamps,
            bytes(&super::reactions::node_clamps(model)),
        )?;
        for id in [BufferId::ReactionInputs, BufferId::ReactionPartials] {
            optional.zeroed(id, plan.buffer(id).map_or(0, |b| b.bytes))?;
        }
        if plan.elastic_counts().is_some() {
            let data = super::elastic::ElasticData::prepare(problem);
            for (id, data) in data.uploads() {
                optional.data(id, data)?;
            }
            for id in super::elastic::BUFFERS {
                if !optional.built.contains_key(&id) {
                    optional.zeroed(id, plan.buffer(id).map_or(0, |b| b.bytes))?;
                }
            }
        }
        let Optional { up, built, .. } = optional;
        let partials_size = plan.buffer(BufferId::Partials).map_or(0, |b| b.bytes);
        let buffers = SimBuffers {
            positions: positions_buffer,
            velocities: velocities_buffer,
            forces: forces_buffer,
            springs: springs_buffer,
            spring_damping,
            tets: tets_buffer,
            rest_volumes,
            optional: built,
            partials: Buffer::new(
                ctx,
                BufferId::Partials.name(),
                partials_size,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::GpuOnly,
            )?,
            status: status_buffer,
        };
        buffers.check_against(plan)?;
        up.submit(ctx)?;
        Ok(buffers)
    }

    /// The buffer `id`, if it was built.
    pub fn get(&self, id: BufferId) -> Option<&Buffer> {
        match id {
            BufferId::Positions => Some(&self.positions),
            BufferId::Velocities => Some(&self.velocities),
            BufferId::Forces => Some(&self.forces),
            BufferId::Springs => Some(&self.springs),
            BufferId::SpringDamping => Some(&self.spring_damping),
            BufferId::Tets => Some(&self.tets),
            BufferId::RestVolumes => Some(&self.rest_volumes),
            BufferId::Partials => Some(&self.partials),
            BufferId::Status => Some(&self.status),
            _ => self.optional.get(&id),
        }
    }

    /// Device-local bytes of every buffer built (what the plan's total must equal).
    pub fn device_bytes(&self) -> u64 {
        all_buffers()
            .filter_map(|id| self.get(id))
            .map(|b| b.size)
            .sum()
    }

    /// Fails when a buffer exists that the plan lacks, or the other way round, or when a
    /// size differs: the plan printed by `tetrasim plan` is then wrong.
    fn check_against(&self, plan: &EnginePlan) -> Result<()> {
        for id in all_buffers() {
            let built = self.get(id).map(|b| b.size);
            let planned = plan.buffer(id).map(|b| b.bytes);
            if built != planned {
                return Err(Error::Gpu(format!(
                    "engine plan mismatch for buffer `{}`: planned {planned:?} bytes, built {built:?}",
                    id.name()
                )));
            }
        }
        Ok(())
    }
}

/// The gather path's buffers for the constraint `sweeps`, each holding the sweeps one
/// after another: members in group order, zeroed contributions (a vec4 per constraint
/// corner), and the per-group node-slot CSR ([`crate::model::ConstraintGroups::node_slots`];
/// rows numbered over all sweeps' groups, items pointing into the whole contributions
/// buffer). The shaders find a sweep's part from the plan's
/// [`super::plan::EnginePlan::sweep_offsets`].
fn gather_buffers(optional: &mut Optional<'_>, model: &Model, sweeps: &[Sweep]) -> Result<()> {
    let mut members: Vec<u32> = Vec::new();
    let mut offsets: Vec<u32> = vec![0];
    let mut items: Vec<u32> = Vec::new();
    let mut slot_first = 0u32;
    for sweep in sweeps {
        let (slots, corners) = (
            ConstraintKind::node_slots(sweep, model),
            sweep.kind.arity() as u32,
        );
        let item_first = items.len() as u32;
        offsets.extend(slots.offsets[1..].iter().map(|&o| item_first + o));
        items.extend(slots.items.iter().map(|&i| slot_first + i));
        members.extend_from_slice(&sweep.groups.members.items);
        slot_first += corners * sweep.groups.members.items.len() as u32;
    }
    optional.data(BufferId::GroupMembers, bytes(&members))?;
    optional.zeroed(BufferId::Contributions, 16 * u64::from(slot_first))?;
    optional.data(BufferId::NodeSlotOffsets, bytes(&offsets))?;
    optional.data(BufferId::NodeSlotItems, bytes(&items))
}

/// Block Gauss-Seidel's buffers (`#block` variants; common/block.glsl), the blocked sweeps
/// one after another: a row per block (its first member position within its sweep, its
/// members, its first entry in the nodes, its nodes | its colours << 16), the blocks' nodes
/// (bit 31: a hub), and per member of every sweep its corners' local indices in two 16-bit
/// halves and its colour (zeros for a sweep without blocks).
fn block_buffers(optional: &mut Optional<'_>, sweeps: &[Sweep]) -> Result<()> {
    let (mut rows, mut nodes, mut corners) = (Vec::new(), Vec::new(), Vec::new());
    for sweep in sweeps {
        let Some(blocks) = &sweep.blocks else {
            corners.resize(corners.len() + sweep.groups.members.items.len(), [0u32; 4]);
            continue;
        };
        for b in 0..blocks.len() {
            let members = blocks.members(b);
            let row = blocks.nodes.row(b);
            let colours = blocks.colours[b] << 16;
            rows.push([
                members.start as u32,
                members.len() as u32,
                nodes.len() as u32,
                row.len() as u32 | colours,
            ]);
            nodes.extend(
                row.iter()
                    .map(|&k| k | (u32::from(blocks.hub[k as usize]) << 31)),
            );
        }
        corners.extend(
            (blocks.corners.iter().zip(&blocks.colour))
                .map(|(c, &colour)| [c[0] | (c[1] << 16), c[2] | (c[3] << 16), colour, 0]),
        );
    }
    if rows.is_empty() {
        return Ok(());
    }
    optional.data(BufferId::BlockRows, bytes(&rows))?;
    optional.data(BufferId::BlockNodes, bytes(&nodes))?;
    optional.data(BufferId::BlockCorners, bytes(&corners))
}

/// The global volume constraints' buffers ([`GlobalVolume`]); the chunk partials as many as
/// the plan gives every object.
fn global_buffers(optional: &mut Optional<'_>, global: &GlobalVolume) -> Result<()> {
    let partials = (optional.plan.buffer(BufferId::GlobalState)).map_or(16, |b| b.bytes);
    let objects: Vec<GpuGlobalObject> = global
        .objects
        .iter()
        .map(|o| GpuGlobalObject {
            node_first: o.node_first,
            node_count: o.node_count,
            face_first: o.face_first,
            face_count: o.face_count,
            rest_volume: o.rest_volume as f32,
            pad: [0; 3],
        })
        .collect();
    let faces: Vec<[u32; 4]> = global.faces.iter().map(|f| [f[0], f[1], f[2], 0]).collect();
    optional.data(BufferId::GlobalObjects, bytes(&objects))?;
    optional.data(BufferId::SurfaceNodes, bytes(&global.nodes))?;
    optional.data(BufferId::SurfaceFaces, bytes(&faces))?;
    optional.data(BufferId::NodeFaceOffsets, bytes(&global.node_faces.offsets))?;
    optional.data(BufferId::NodeFaceItems, bytes(&global.node_faces.items))?;
    optional.zeroed(BufferId::SurfaceGradients, (16 * global.nodes.len()) as u64)?;
    optional.zeroed(BufferId::GlobalState, partials)
}

/// The kinematic colliders' buffers: zeroed contact forces, each collider's data, the mesh
/// colliders' grid samples (4 zero bytes without one), and the host-visible poses, which
/// every frame slot writes before its submit ([`super::colliders::poses`]).
fn collider_buffers(optional: &mut Optional<'_>, model: &Model) -> Result<()> {
    let (data, values) = super::colliders::static_data(&model.colliders);
    optional.zeroed(BufferId::ColliderContacts, (16 * model.node_count()) as u64)?;
    match data.is_empty() {
        true => optional.zeroed(BufferId::Colliders, 4)?,
        false => optional.data(BufferId::Colliders, bytes(&data))?,
    }
    // Each node's row among the grabbed nodes (4 zero bytes without grabs: never read).
    let grabbed = super::plan::grabbed_nodes(&model.grabs);
    match grabbed.is_empty() {
        true => optional.zeroed(BufferId::GrabNodes, 4)?,
        false => {
            let mut rows = vec![u32::MAX; model.node_count()];
            for (row, &i) in grabbed.iter().enumerate() {
                rows[i as usize] = row as u32;
            }
            optional.data(BufferId::GrabNodes, bytes(&rows))?
        }
    }
    match values.is_empty() {
        true => optional.zeroed(BufferId::ColliderGrids, 4)?,
        false => optional.data(BufferId::ColliderGrids, bytes(&values))?,
    }
    for id in [BufferId::ColliderPoses, BufferId::GrabTargets] {
        if let Some(planned) = optional.plan.buffer(id) {
            let buffer = Buffer::new(
                optional.ctx,
                id.name(),
                planned.bytes,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryLocation::CpuToGpu,
            )?;
            optional.built.insert(id, buffer);
        }
    }
    Ok(())
}

/// The clamps' buffers: each clamped node with its clamp and rest offset from the clamp's
/// centre, and the host-visible poses, which every frame slot writes before its submit
/// ([`super::colliders::clamp_poses`]).
fn clamp_buffers(optional: &mut Optional<'_>, model: &Model) -> Result<()> {
    let nodes = super::colliders::clamp_nodes(&model.clamps, &model.positions);
    optional.data(BufferId::ClampNodes, bytes(&nodes))?;
    if let Some(poses) = optional.plan.buffer(BufferId::ClampPoses) {
        let buffer = Buffer::new(
            optional.ctx,
            BufferId::ClampPoses.name(),
            poses.bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        optional.built.insert(BufferId::ClampPoses, buffer);
    }
    Ok(())
}

/// Body contact's buffers: each surface node, then each surface triangle, with its object
/// (bit 31: the object collides with itself), and the zeroed hash (its counts are 0 between
/// steps), contact records and sums.
fn body_buffers(optional: &mut Optional<'_>, bodies: &BodyContact, n: usize) -> Result<()> {
    let object = |i: u32| {
        let k = bodies.object_of[i as usize];
        let own = bodies
            .self_contact
            .get(k as usize)
            .copied()
            .unwrap_or(false);
        k | (u32::from(own) << 31)
    };
    let surface: Vec<[u32; 4]> = (bodies.nodes.iter())
        .map(|&i| [i, object(i), 0, 0])
        .chain(
            bodies
                .triangles
                .iter()
                .map(|t| [t[0], t[1], t[2], object(t[0])]),
        )
        .collect();
    optional.data(BufferId::BodySurface, bytes(&surface))?;
    for id in [BufferId::ContactHash, BufferId::Contacts] {
        let size = optional.plan.buffer(id).map_or(4, |b| b.bytes);
        optional.zeroed(id, size)?;
    }
    optional.zeroed(BufferId::ContactSums, (16 * n) as u64)
}

/// The optional buffers while they are uploaded: each is built when the plan has it.
struct Optional<'a> {
    ctx: &'a Arc<Context>,
    up: Uploads,
    plan: &'a EnginePlan,
    built: BTreeMap<BufferId, Buffer>,
}

impl Optional<'_> {
    /// Buffer `id` holding `data`, if the plan builds it.
    fn data(&mut self, id: BufferId, data: &[u8]) -> Result<()> {
        if self.plan.has(id) {
            let buffer = self.up.with_data(self.ctx, id.name(), data)?;
            self.built.insert(id, buffer);
        }
        Ok(())
    }

    /// Buffer `id` of `size` zero bytes, if the plan builds it.
    fn zeroed(&mut self, id: BufferId, size: u64) -> Result<()> {
        if self.plan.has(id) {
            let buffer = self.up.zeroed(self.ctx, id.name(), size)?;
            self.built.insert(id, buffer);
        }
        Ok(())
    }
}

/// Every buffer kind.
fn all_buffers() -> impl Iterator<Item = BufferId> {
    let extra = super::elastic::BUFFERS
        .iter()
        .chain(&super::reactions::BUFFERS);
    ALL_BUFFERS.iter().chain(extra).copied()
}

/// The buffer kinds but the finite elements' and the reactions'.
const ALL_BUFFERS: [BufferId; 53] = [
    BufferId::Positions,
    BufferId::Velocities,
    BufferId::Forces,
    BufferId::Springs,
    BufferId::SpringDamping,
    BufferId::Tets,
    BufferId::RestVolumes,
    BufferId::VolumeCompliance,
    BufferId::SpringMultipliers,
    BufferId::VolumeMultipliers,
    BufferId::ConstraintSum,
    BufferId::Degrees,
    BufferId::NodeSpringOffsets,
    BufferId::NodeSpringItems,
    BufferId::Partials,
    BufferId::Status,
    BufferId::GroupMembers,
    BufferId::Contributions,
    BufferId::NodeSlotOffsets,
    BufferId::NodeSlotItems,
    BufferId::GlobalObjects,
    BufferId::SurfaceNodes,
    BufferId::SurfaceFaces,
    BufferId::NodeFaceOffsets,
    BufferId::NodeFaceItems,
    BufferId::SurfaceGradients,
    BufferId::GlobalState,
    BufferId::ChebyshevBefore,
    BufferId::Contacts,
    BufferId::ColliderContacts,
    BufferId::Colliders,
    BufferId::ColliderGrids,
    BufferId::ColliderPoses,
    BufferId::BodySurface,
    BufferId::ContactHash,
    BufferId::ContactSums,
    BufferId::ClampNodes,
    BufferId::ClampPoses,
    BufferId::GrabNodes,
    BufferId::GrabTargets,
    BufferId::SplitVelocities,
    BufferId::AndersonHistory,
    BufferId::AndersonSums,
    BufferId::AndersonMultipliers,
    BufferId::BlockRows,
    BufferId::BlockNodes,
    BufferId::BlockCorners,
    BufferId::MinresTranspose,
    BufferId::MinresGrads,
    BufferId::MinresVectors,
    BufferId::MinresNodeVectors,
    BufferId::MinresSums,
    BufferId::MinresState,
];
