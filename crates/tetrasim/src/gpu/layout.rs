//! Data layouts shared with the GLSL side (glsl/common/bindings.glsl): `#[repr(C)]` Pod
//! structs that are std430-safe (vec4, never vec3 arrays), the binding numbers, and the
//! push-constant block derived from [`SimParams`]. The tests read the compiled SPIR-V and
//! check every offset and binding against these definitions.

use bytemuck::{Pod, Zeroable};

use crate::params::{ConstraintCombine, SimParams, SpringKind};

/// Descriptor binding numbers of set 0, from the one list in `gpu/bindings.rs`; build.rs
/// compiles every shader with the same numbers as the `B_*` macros.
pub mod binding {
    /// Turns the list into one documented constant per binding and [`ALL`].
    macro_rules! bindings {
        ($($(#[$doc:meta])* $name:ident = $value:expr,)*) => {
            $($(#[$doc])* pub const $name: u32 = $value;)*
            /// Every binding, by name (`B_<NAME>` in GLSL), in the list's order.
            pub const ALL: &[(&str, u32)] = &[$((stringify!($name), $value)),*];
        };
    }
    include!("bindings.rs");
}

/// The push-constant block of every pass (`PushConstants` in bindings.glsl), 100 bytes
/// used, padded to 112 (a multiple of the `vec3`'s 16-byte alignment).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct PushConstants {
    /// Time step [s].
    pub dt: f32,
    /// Relaxation of the combined constraint forces.
    pub omega: f32,
    /// The current sweep's first position in the group members (gather path; each spring
    /// has its own stiffness and damping in the buffers, so none is pushed).
    pub member_first: u32,
    /// The current sweep's first slot in the contributions (gather path).
    pub slot_first: u32,
    /// Gravity's acceleration [m/s^2] (a `vec3` at a 16-byte offset).
    pub gravity: [f32; 3],
    /// Fraction of tangential velocity removed on floor contact.
    pub friction: f32,
    /// 1 when the floor `y = 0` exists.
    pub floor_on: u32,
    /// Nodes.
    pub node_count: u32,
    /// Springs.
    pub spring_count: u32,
    /// Tetrahedra.
    pub tet_count: u32,
    /// A constraint is skipped when its `A` is at or below this (`constraint_epsilon`).
    pub epsilon: f32,
    /// How constraint forces are combined: [`combine::SCALED`], [`combine::SUM`] or
    /// [`combine::AVERAGE`] (`ConstraintCombine`).
    pub combine: u32,
    /// The constraint group being solved, counted over all sweeps of an iteration (one
    /// group per sweep for Jacobi); selects the degrees and slots.
    pub group: u32,
    /// First position of the group in its sweep's group-ordered constraints (gather path).
    pub group_first: u32,
    /// Constraints in the group (gather path).
    pub group_count: u32,
    /// The iteration's Chebyshev weight (solver `chebyshev`; 1 otherwise).
    pub chebyshev_weight: f32,
    /// The constraint iteration within the step: in iteration 0 the compliant constraints
    /// take their multipliers so far as 0 (and overwrite the last step's), so the
    /// multiplier buffers need no reset.
    pub iteration: u32,
    /// 1 when implicit springs are warm-started (`warm_start`): in iteration 0 a spring's
    /// multiplier so far is its stored value, the last step's, which `spring_warm_start`
    /// applied as a force at the start of the step.
    pub warm_start: u32,
    /// The current substep's first entry in the collider poses
    /// ([`binding::COLLIDER_POSES`]): `(frame slot * substeps + substep) * colliders`.
    pub collider_first: u32,
    /// The step's row in the host-written per-step arrays (clamp poses):
    /// `frame slot * substeps + substep`.
    pub step_row: u32,
    /// The step's first row in the grab targets ([`binding::GRAB_TARGETS`]):
    /// `step_row * grabbed nodes`.
    pub grab_first: u32,
    /// Which of the step's solves the dispatch belongs to: [`phase::FULL`], or
    /// [`phase::VELOCITY`] in split contact's velocity solve (glsl/physics/solve.glsl).
    pub phase: u32,
    /// The current sweep's first row in the block rows ([`binding::BLOCK_ROWS`]; block
    /// Gauss-Seidel).
    pub block_first: u32,
    /// Padding to a multiple of 16 bytes (not in the shader's block).
    pub pad: [u32; 3],
}

/// Values of [`PushConstants::phase`] (the `PHASE_*` macros in glsl/physics/solve.glsl).
pub mod phase {
    use crate::physics::Solve;

    /// The full solve.
    pub const FULL: u32 = 0;
    /// Split contact's velocity solve.
    pub const VELOCITY: u32 = 1;

    /// The value for `solve`.
    pub fn of(solve: Solve) -> u32 {
        match solve {
            Solve::Full => FULL,
            Solve::Velocity => VELOCITY,
        }
    }
}

/// Values of [`PushConstants::combine`] (the `COMBINE_*` macros in bindings.glsl).
pub mod combine {
    /// Momentum-conserving scaling.
    pub const SCALED: u32 = 0;
    /// Plain summation.
    pub const SUM: u32 = 1;
    /// Per-node averaging (first edition).
    pub const AVERAGE: u32 = 2;
}

impl PushConstants {
    /// The block for `params` and the model's element counts (f64 values rounded to f32).
    pub fn new(params: &SimParams, nodes: usize, springs: usize, tets: usize) -> Self {
        PushConstants {
            dt: params.dt as f32,
            omega: params.omega as f32,
            member_first: 0,
            slot_first: 0,
            gravity: params.gravity.as_vec3().to_array(),
            friction: params.friction as f32,
            floor_on: u32::from(params.floor),
            node_count: nodes as u32,
            spring_count: springs as u32,
            tet_count: tets as u32,
            epsilon: params.constraint_epsilon as f32,
            combine: match params.combine {
                ConstraintCombine::Scaled => combine::SCALED,
                ConstraintCombine::Sum => combine::SUM,
                ConstraintCombine::Average => combine::AVERAGE,
            },
            group: 0,
            group_first: 0,
            group_count: 0,
            chebyshev_weight: 1.0,
            iteration: 0,
            warm_start: u32::from(params.springs == SpringKind::Implicit && params.warm_start),
            collider_first: 0,
            step_row: 0,
            grab_first: 0,
            phase: phase::FULL,
            block_first: 0,
            pad: [0; 3],
        }
    }
}

/// One spring (`Spring` in bindings.glsl): node indices, rest length [m] and stiffness
/// [N/m], 16 bytes (one 128-bit load). The stiffness fills what was padding; the damping,
/// which the `distance` pass never reads, is a float buffer of its own
/// ([`binding::SPRING_DAMPING`]) rather than growing every spring to 32 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuSpring {
    /// First node.
    pub a: u32,
    /// Second node.
    pub b: u32,
    /// Rest length [m].
    pub rest: f32,
    /// Stiffness `k_e` [N/m] ([`crate::model::ElementMaterial::spring_stiffness`]).
    pub stiffness: f32,
}

/// One object's global volume constraint (`GlobalObject` in bindings.glsl), 32 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuGlobalObject {
    /// First position of its surface nodes.
    pub node_first: u32,
    /// Number of its surface nodes.
    pub node_count: u32,
    /// First position of its faces.
    pub face_first: u32,
    /// Number of its faces.
    pub face_count: u32,
    /// Its rest volume [m^3].
    pub rest_volume: f32,
    /// Padding to 32 bytes.
    pub pad: [u32; 3],
}

/// One kinematic collider's static data (`Collider` in glsl/physics/contact.glsl), 64 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuCollider {
    /// [`crate::collider::Shape::code`].
    pub shape: u32,
    /// No point within the contact thickness is farther from its centre [m]
    /// ([`crate::collider::Shape::bound`] + thickness; infinite for a plane).
    pub reach: f32,
    /// Fraction of the tangential velocity relative to its surface removed per step.
    pub friction: f32,
    /// Contact thickness [m].
    pub thickness: f32,
    /// Sizes [m]: sphere `(radius)`, box `(half extents)`, capsule `(half length,
    /// radius)`; 0 elsewhere.
    pub size: [f32; 4],
    /// Mesh collider: its grid's origin (local frame) [m] and cell [m].
    pub grid_origin: [f32; 4],
    /// Mesh collider: samples along X, Y, Z and its first sample in the grids buffer.
    pub grid_dims: [u32; 4],
}

/// One collider's placement over one step (`ColliderPose` in glsl/physics/contact.glsl),
/// 64 bytes, computed on the host in f64: the end pose, and the start pose relative to it
/// (so the shader's surface velocity has no cancellation between two nearly equal poses).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuColliderPose {
    /// The end pose's position [m] (w 0).
    pub end_position: [f32; 4],
    /// The end pose's rotation (x, y, z, w).
    pub end_rotation: [f32; 4],
    /// End position minus start position [m] (w 0).
    pub moved: [f32; 4],
    /// `start.rotation * end.rotation^-1` (x, y, z, w).
    pub turned: [f32; 4],
}

/// One clamped node (`ClampNode` in glsl/passes/clamp_drive.comp), 32 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuClampNode {
    /// The node.
    pub node: u32,
    /// Its clamp (index into the model's clamps).
    pub clamp: u32,
    /// Padding.
    pub pad: [u32; 2],
    /// Its rest position minus the clamp's centre [m] (w 0).
    pub offset: [f32; 4],
}

/// One clamp's pose at the end of one step (`ClampPose` in glsl/passes/clamp_drive.comp),
/// 32 bytes, computed on the host in f64: a clamped node's target is
/// `position + rotation * offset`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuClampPose {
    /// The clamp's centre plus its translation [m] (w 0).
    pub position: [f32; 4],
    /// Its rotation (x, y, z, w).
    pub rotation: [f32; 4],
}

/// One volume_sum workgroup's result (`VolumePartial` in bindings.glsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct VolumePartial {
    /// Sum of the group's signed tet volumes [m^3].
    pub volume: f32,
    /// Tets of the group with signed volume <= 0.
    pub inverted: u32,
    /// Sum of the group's `|V_t - V0_t|` [m^3] (the local volume error).
    pub local_error: f32,
    /// Padding to 16 bytes.
    pub pad: u32,
}

/// A vec4 of f32 from an f64 vector and a w component.
pub fn vec4(v: glam::DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;
    use std::mem::{offset_of, size_of};

    use super::*;
    use crate::gpu::spirv::{assert_struct_offsets, Module};

    fn module(key: &str) -> Module {
        let bytes = crate::shaders::SHADERS
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, b)| *b)
            .unwrap();
        Module::parse(bytes).unwrap()
    }

    #[test]
    fn sizes_are_std430_multiples_of_16() {
        assert_eq!(size_of::<PushConstants>(), 112);
        assert_eq!(size_of::<GpuSpring>(), 16);
        assert_eq!(size_of::<VolumePartial>(), 16);
        assert_eq!(size_of::<GpuGlobalObject>(), 32);
        assert_eq!(size_of::<GpuCollider>(), 64);
        assert_eq!(size_of::<GpuColliderPose>(), 64);
    }

    #[test]
    fn push_constant_offsets_match_the_shader() {
        let rust = [
            ("dt", offset_of!(PushConstants, dt)),
            ("omega", offset_of!(PushConstants, omega)),
            ("member_first", offset_of!(PushConstants, member_first)),
            ("slot_first", offset_of!(PushConstants, slot_first)),
            ("gravity", offset_of!(PushConstants, gravity)),
            ("friction", offset_of!(PushConstants, friction)),
            ("floor_on", offset_of!(PushConstants, floor_on)),
            ("node_count", offset_of!(PushConstants, node_count)),
            ("spring_count", offset_of!(PushConstants, spring_count)),
            ("tet_count", offset_of!(PushConstants, tet_count)),
            ("epsilon", offset_of!(PushConstants, epsilon)),
            ("combine", offset_of!(PushConstants, combine)),
            ("group", offset_of!(PushConstants, group)),
            ("group_first", offset_of!(PushConstants, group_first)),
            ("group_count", offset_of!(PushConstants, group_count)),
            (
                "chebyshev_weight",
                offset_of!(PushConstants, chebyshev_weight),
            ),
            ("iteration", offset_of!(PushConstants, iteration)),
            ("warm_start", offset_of!(PushConstants, warm_start)),
            ("collider_first", offset_of!(PushConstants, collider_first)),
            ("step_row", offset_of!(PushConstants, step_row)),
            ("grab_first", offset_of!(PushConstants, grab_first)),
            ("phase", offset_of!(PushConstants, phase)),
            ("block_first", offset_of!(PushConstants, block_first)),
        ];
        // integrate uses floor_on/friction/gravity, volume_sum the tet count: together they
        // name most members; every member the shader keeps must sit where Rust puts it.
        let checked = assert_struct_offsets(
            &[
                "passes/integrate.comp",
                "passes/integrate.comp#colliders",
                "passes/volume.comp#ext",
                "passes/spring_scatter.comp#cas",
                "passes/volume.comp#gather",
                "passes/constraint_apply.comp#chebyshev",
                "passes/spring_constraint.comp#gather",
                "passes/volume.comp#block",
            ],
            "PushConstants",
            &rust,
        );
        assert!(checked >= 19);
    }

    #[test]
    fn spring_and_partial_offsets_match_the_shader() {
        let springs: HashMap<_, _> = module("passes/distance.comp#ext")
            .struct_offsets("Spring")
            .into_iter()
            .collect();
        assert_eq!(springs.get("a"), Some(&(offset_of!(GpuSpring, a) as u32)));
        assert_eq!(springs.get("b"), Some(&(offset_of!(GpuSpring, b) as u32)));
        assert_eq!(
            springs.get("rest"),
            Some(&(offset_of!(GpuSpring, rest) as u32))
        );
        let scatter: HashMap<_, _> = module("passes/spring_scatter.comp#cas")
            .struct_offsets("Spring")
            .into_iter()
            .collect();
        assert_eq!(
            scatter.get("stiffness"),
            Some(&(offset_of!(GpuSpring, stiffness) as u32))
        );
        let partials: HashMap<_, _> = module("passes/volume_sum.comp")
            .struct_offsets("VolumePartial")
            .into_iter()
            .collect();
        assert_eq!(
            partials.get("volume"),
            Some(&(offset_of!(VolumePartial, volume) as u32))
        );
        assert_eq!(
            partials.get("inverted"),
            Some(&(offset_of!(VolumePartial, inverted) as u32))
        );
        assert_eq!(
            partials.get("local_error"),
            Some(&(offset_of!(VolumePartial, local_error) as u32))
        );
        let objects: HashMap<_, _> = module("passes/global_volume_prepare.comp")
            .struct_offsets("GlobalObject")
            .into_iter()
            .collect();
        for (name, offset) in [
            ("node_first", offset_of!(GpuGlobalObject, node_first)),
            ("node_count", offset_of!(GpuGlobalObject, node_count)),
            ("face_first", offset_of!(GpuGlobalObject, face_first)),
            ("face_count", offset_of!(GpuGlobalObject, face_count)),
            ("rest_volume", offset_of!(GpuGlobalObject, rest_volume)),
        ] {
            assert_eq!(objects.get(name), Some(&(offset as u32)), "{name}");
        }
        assert_eq!(
            module("passes/global_volume.comp").array_stride("GlobalObjects"),
            Some(size_of::<GpuGlobalObject>() as u32)
        );
        assert_eq!(
            module("passes/volume_sum.comp").array_stride("Partials"),
            Some(size_of::<VolumePartial>() as u32)
        );
        assert_eq!(
            module("passes/distance.comp#ext").array_stride("Springs"),
            Some(size_of::<GpuSpring>() as u32)
        );
        assert_eq!(
            module("passes/integrate.comp").array_stride("Positions"),
            Some(16)
        );
    }

    #[test]
    fn collider_offsets_match_the_shader() {
        let m = module("passes/integrate.comp#colliders");
        let colliders: HashMap<_, _> = m.struct_offsets("Collider").into_iter().collect();
        for (name, offset) in [
            ("shape", offset_of!(GpuCollider, shape)),
            ("reach", offset_of!(GpuCollider, reach)),
            ("friction", offset_of!(GpuCollider, friction)),
            ("thickness", offset_of!(GpuCollider, thickness)),
            ("size", offset_of!(GpuCollider, size)),
            ("grid_origin", offset_of!(GpuCollider, grid_origin)),
            ("grid_dims", offset_of!(GpuCollider, grid_dims)),
        ] {
            assert_eq!(colliders.get(name), Some(&(offset as u32)), "{name}");
        }
        let poses: HashMap<_, _> = m.struct_offsets("ColliderPose").into_iter().collect();
        for (name, offset) in [
            ("end_position", offset_of!(GpuColliderPose, end_position)),
            ("end_rotation", offset_of!(GpuColliderPose, end_rotation)),
            ("moved", offset_of!(GpuColliderPose, moved)),
            ("turned", offset_of!(GpuColliderPose, turned)),
        ] {
            assert_eq!(poses.get(name), Some(&(offset as u32)), "{name}");
        }
        assert_eq!(
            m.array_stride("Colliders"),
            Some(size_of::<GpuCollider>() as u32)
        );
        assert_eq!(
            m.array_stride("ColliderPoses"),
            Some(size_of::<GpuColliderPose>() as u32)
        );
    }

    #[test]
    fn the_binding_list_numbers_every_buffer_once() {
        let mut numbers: Vec<u32> = binding::ALL.iter().map(|&(_, n)| n).collect();
        numbers.sort_unstable();
        let dense: Vec<u32> = (0..binding::ALL.len() as u32).collect();
        assert_eq!(numbers, dense, "{:?}", binding::ALL);
        assert!(binding::ALL.contains(&("STATUS", binding::STATUS)));
    }

    #[test]
    fn every_pass_uses_the_rust_binding_numbers() {
        let expected: HashMap<&str, u32> = [
            ("Positions", binding::POSITIONS),
            ("Velocities", binding::VELOCITIES),
            ("Forces", binding::FORCES),
            ("ForcesF", binding::FORCES),
            ("ForcesU", binding::FORCES),
            ("Sum", binding::CONSTRAINT_SUM),
            ("SumF", binding::CONSTRAINT_SUM),
            ("SumU", binding::CONSTRAINT_SUM),
            ("Springs", binding::SPRINGS),
            ("Tets", binding::TETS),
            ("RestVolumes", binding::REST_VOLUMES),
            ("Degrees", binding::CONSTRAINT_DEGREE),
            ("NodeSpringOffsets", binding::NODE_SPRING_OFFSETS),
            ("NodeSpringItems", binding::NODE_SPRING_ITEMS),
            ("Partials", binding::VOLUME_PARTIALS),
            ("Status", binding::STATUS),
            ("Members", binding::GROUP_MEMBERS),
            ("Contributions", binding::CONTRIBUTIONS),
            ("NodeSlotOffsets", binding::NODE_SLOT_OFFSETS),
            ("NodeSlotItems", binding::NODE_SLOT_ITEMS),
            ("GlobalObjects", binding::GLOBAL_OBJECTS),
            ("SurfaceNodes", binding::SURFACE_NODES),
            ("SurfaceFaces", binding::SURFACE_FACES),
            ("NodeFaceOffsets", binding::NODE_FACE_OFFSETS),
            ("NodeFaceItems", binding::NODE_FACE_ITEMS),
            ("SurfaceGradients", binding::SURFACE_GRADIENTS),
            ("GlobalState", binding::GLOBAL_STATE),
            ("ChebyshevBefore", binding::CHEBYSHEV_BEFORE),
            ("SpringDamping", binding::SPRING_DAMPING),
            ("VolumeCompliance", binding::VOLUME_COMPLIANCE),
            ("SpringMultipliers", binding::SPRING_MULTIPLIERS),
            ("VolumeMultipliers", binding::VOLUME_MULTIPLIERS),
            ("Contacts", binding::CONTACTS),
            ("ColliderContacts", binding::COLLIDER_CONTACTS),
            ("Colliders", binding::COLLIDERS),
            ("ColliderGrids", binding::COLLIDER_GRIDS),
            ("ColliderPoses", binding::COLLIDER_POSES),
            ("BodySurface", binding::BODY_SURFACE),
            ("ContactHash", binding::CONTACT_HASH),
            ("ContactSumsF", binding::CONTACT_SUMS),
            ("ContactSumsU", binding::CONTACT_SUMS),
            ("ContactSums", binding::CONTACT_SUMS),
            ("ClampNodes", binding::CLAMP_NODES),
            ("ClampPoses", binding::CLAMP_POSES),
            ("GrabNodes", binding::GRAB_NODES),
            ("GrabTargets", binding::GRAB_TARGETS),
            ("SplitVelocities", binding::SPLIT_VELOCITIES),
            ("AndersonHistory", binding::ANDERSON_HISTORY),
            ("AndersonSums", binding::ANDERSON_SUMS),
            ("AndersonMultipliers", binding::ANDERSON_MULTIPLIERS),
            ("BlockRows", binding::BLOCK_ROWS),
            ("BlockNodes", binding::BLOCK_NODES),
            ("BlockCorners", binding::BLOCK_CORNERS),
            ("MinresTranspose", binding::MINRES_TRANSPOSE),
            ("MinresGrads", binding::MINRES_GRADS),
            ("MinresVectors", binding::MINRES_VECTORS),
            ("MinresNodeVectors", binding::MINRES_NODE_VECTORS),
            ("MinresSums", binding::MINRES_SUMS),
            ("MinresDone", binding::MINRES_SUMS),
            ("MinresState", binding::MINRES_STATE),
            ("ElasticTets", binding::ELASTIC_TETS),
            ("NodeTetOffsets", binding::NODE_TET_OFFSETS),
            ("NodeTetItems", binding::NODE_TET_ITEMS),
            ("CoarseMatrix", binding::COARSE_MATRIX),
            ("CoarseVector", binding::COARSE_VECTOR),
            ("ElasticLinearBuffer", binding::ELASTIC_LINEAR),
            ("ElasticCornersBuffer", binding::ELASTIC_CORNERS),
            ("ElasticNodesBuffer", binding::ELASTIC_NODES),
            ("ElasticStateF", binding::ELASTIC_STATE),
            ("ElasticStateU", binding::ELASTIC_STATE),
            ("CoarseAggregates", binding::COARSE_AGGREGATES),
            ("CoarseModes", binding::COARSE_MODES),
            ("CoarseIndex", binding::COARSE_INDEX),
            ("CoarseScratch", binding::COARSE_SCRATCH),
            ("ElasticObjectsU", binding::ELASTIC_OBJECTS),
            ("ElasticObjectsF", binding::ELASTIC_OBJECTS),
            ("ReactionInputs", binding::REACTION_INPUTS),
            ("ReactionPartials", binding::REACTION_PARTIALS),
            ("NodeClamps", binding::NODE_CLAMPS),
        ]
        .into_iter()
        .collect();
        let mut seen = 0;
        for (key, bytes) in crate::shaders::SHADERS
            .iter()
            .filter(|(k, _)| k.starts_with("passes/"))
        {
            for (block, number) in Module::parse(bytes).unwrap().block_bindings() {
                assert_eq!(
                    expected.get(block.as_str()),
                    Some(&number),
                    "{key}: block `{block}`"
                );
                seen += 1;
            }
        }
        assert!(seen >= 25, "only {seen} bindings found");
    }
}
