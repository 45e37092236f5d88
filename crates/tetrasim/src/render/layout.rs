//! Data layouts shared with glsl/render/common.glsl: the binding numbers of the render
//! descriptor set and the push-constant block. The tests read the compiled SPIR-V and check
//! every offset and binding against these definitions.

use bytemuck::{Pod, Zeroable};

/// Descriptor binding numbers of the render set (the `R_*` macros in common.glsl).
pub mod binding {
    /// vec4 per node: position [m] (the simulation's buffer).
    pub const POSITIONS: u32 = 0;
    /// vec4 per node: unit normal, w = colour scalar.
    pub const ATTRS: u32 = 1;
    /// uint per surface node: its node index.
    pub const SURFACE_NODES: u32 = 2;
    /// Node -> surface triangles CSR offsets.
    pub const FACE_OFFSETS: u32 = 3;
    /// Node -> surface triangles CSR items.
    pub const FACE_ITEMS: u32 = 4;
    /// 3 node indices per surface triangle (also the index buffer).
    pub const TRIANGLES: u32 = 5;
    /// Node -> tets CSR offsets.
    pub const TET_OFFSETS: u32 = 6;
    /// Node -> tets CSR items.
    pub const TET_ITEMS: u32 = 7;
    /// uvec4 per tet (the simulation's buffer).
    pub const TETS: u32 = 8;
    /// float per tet: rest volume [m^3] (the simulation's buffer).
    pub const REST_VOLUMES: u32 = 9;
    /// Node -> springs CSR offsets.
    pub const SPRING_OFFSETS: u32 = 10;
    /// Node -> springs CSR items.
    pub const SPRING_ITEMS: u32 = 11;
    /// uvec4 per spring: a, b, rest length [m] as f32 bits, stiffness (the simulation's
    /// [`crate::gpu::layout::GpuSpring`] buffer; the render reads `xyz`).
    pub const SPRINGS: u32 = 12;
    /// Collider triangles in their local frames: per vertex, vec4 position (w = collider
    /// index) and vec4 normal ([`crate::render::colliders::ColliderVertex`]).
    pub const COLLIDER_VERTICES: u32 = 13;
    /// mat4 per collider: local to world at the picture's time (host-visible).
    pub const COLLIDER_POSES: u32 = 14;
    /// Number of bindings (0..COUNT).
    pub const COUNT: u32 = 15;
}

/// The push-constant block of every render shader (`RenderPush` in common.glsl), 128 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct RenderPush {
    /// World [m] to clip space, column-major.
    pub view_proj: [[f32; 4]; 4],
    /// xyz: camera position [m]; w: height over which contact shading fades out [m].
    pub eye: [f32; 4],
    /// xyz: unit direction towards the light; w: floor half extent [m].
    pub light: [f32; 4],
    /// xz: centre of the floor quad [m]; y: shadow darkness in [0, 1]; w: grid spacing [m].
    pub floor_centre: [f32; 4],
    /// Legend bar corners as fractions of the image (x right, y down), each pair packed as
    /// two unorm16 (GLSL `unpackUnorm2x16`): `[(x0, y0), (x1, y1)]`.
    pub legend: [u32; 2],
    /// Half range of the colour map around the neutral value (V/V0 = 1, strain = 0).
    pub range: f32,
    /// Colour mode: 0 flat, 1 volume ratio, 2 spring strain.
    pub mode: u32,
}

/// Packs two fractions in [0, 1] as GLSL's `packUnorm2x16` does (first in the low half).
pub fn pack_unorm2x16(a: f32, b: f32) -> u32 {
    let q = |v: f32| (v.clamp(0.0, 1.0) * 65535.0).round() as u32;
    q(a) | (q(b) << 16)
}

#[cfg(test)]
mod tests {
    use std::mem::{offset_of, size_of};

    use super::*;
    use crate::gpu::spirv::{assert_struct_offsets, Module};

    fn module(key: &str) -> Module {
        Module::parse(crate::gpu::kernel::shader(key).unwrap()).unwrap()
    }

    #[test]
    fn push_block_is_the_guaranteed_128_bytes_and_matches_the_shaders() {
        assert_eq!(size_of::<RenderPush>(), 128);
        let rust = [
            ("view_proj", offset_of!(RenderPush, view_proj)),
            ("eye", offset_of!(RenderPush, eye)),
            ("light", offset_of!(RenderPush, light)),
            ("floor_centre", offset_of!(RenderPush, floor_centre)),
            ("legend", offset_of!(RenderPush, legend)),
            ("range", offset_of!(RenderPush, range)),
            ("mode", offset_of!(RenderPush, mode)),
        ];
        let checked = assert_struct_offsets(
            &[
                "render/legend.vert",
                "render/surface.frag",
                "render/floor.vert",
            ],
            "RenderPush",
            &rust,
        );
        assert!(checked >= 3 * rust.len(), "only {checked} members checked");
    }

    #[test]
    fn unorm_packing_matches_glsl() {
        assert_eq!(pack_unorm2x16(0.0, 1.0), 0xffff_0000);
        assert_eq!(pack_unorm2x16(0.5, 0.0), 32768);
        assert_eq!(pack_unorm2x16(-1.0, 2.0), 0xffff_0000);
    }

    #[test]
    fn bindings_match_the_shaders() {
        let expected = [
            ("Positions", binding::POSITIONS),
            ("Attrs", binding::ATTRS),
            ("SurfaceNodes", binding::SURFACE_NODES),
            ("FaceOffsets", binding::FACE_OFFSETS),
            ("FaceItems", binding::FACE_ITEMS),
            ("Triangles", binding::TRIANGLES),
            ("TetOffsets", binding::TET_OFFSETS),
            ("TetItems", binding::TET_ITEMS),
            ("Tets", binding::TETS),
            ("RestVolumes", binding::REST_VOLUMES),
            ("SpringOffsets", binding::SPRING_OFFSETS),
            ("SpringItems", binding::SPRING_ITEMS),
            ("Springs", binding::SPRINGS),
        ];
        let found = module("render/attrs.comp").block_bindings();
        for (name, b) in expected {
            assert!(
                found.contains(&(name.to_string(), b)),
                "attrs.comp: block {name} is not at binding {b}; found {found:?}"
            );
        }
        let colliders = [
            ("ColliderVertices", binding::COLLIDER_VERTICES),
            ("ColliderPoses", binding::COLLIDER_POSES),
        ];
        let found = module("render/collider.vert").block_bindings();
        for (name, b) in colliders {
            assert!(
                found.contains(&(name.to_string(), b)),
                "collider.vert: block {name} is not at binding {b}; found {found:?}"
            );
        }
        assert_eq!((expected.len() + colliders.len()) as u32, binding::COUNT);
        for key in ["render/surface.vert", "render/shadow.vert"] {
            let found = module(key).block_bindings();
            assert!(
                found.contains(&("Positions".to_string(), binding::POSITIONS)),
                "{key}: {found:?}"
            );
        }
    }
}
