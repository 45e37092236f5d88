//! Colours of the picture as 8-bit sRGB, for the CPU side (labels, sheets) and for tests that
//! check rendered pixels. The shaders hold the same values (named in their comments).

/// Background, where no floor is (`BACKGROUND` in glsl/render/floor.frag; the clear colour).
pub const BACKGROUND_RGB: [u8; 3] = [242, 245, 247];
/// The floor between grid lines (`FLOOR` in floor.frag).
pub const FLOOR_RGB: [u8; 3] = [204, 201, 194];
/// Grid lines on the floor (`GRID` in floor.frag).
pub const GRID_RGB: [u8; 3] = [173, 173, 168];
/// The object in the flat colour mode, before lighting (`FLAT` in surface.frag).
pub const FLAT_RGB: [u8; 3] = [219, 158, 107];
/// The colliders, before lighting (`STEEL` in glsl/render/collider.frag).
pub const COLLIDER_RGB: [u8; 3] = [120, 133, 148];
/// Text of labels and legends.
pub const TEXT_RGB: [u8; 3] = [20, 20, 24];

/// An sRGB byte colour as the linear floats a clear value needs.
pub fn linear(rgb: [u8; 3]) -> [f32; 4] {
    let c = |b: u8| {
        let s = f32::from(b) / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    [c(rgb[0]), c(rgb[1]), c(rgb[2]), 1.0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_round_trips_through_srgb() {
        let l = linear([0, 128, 255]);
        assert_eq!(l[0], 0.0);
        assert!((l[1] - 0.2158).abs() < 1e-3, "{l:?}");
        assert!((l[2] - 1.0).abs() < 1e-6);
    }
}
