//! Labels drawn on the CPU with the 8x8 bitmap font of the `font8x8` crate (compiled in, no
//! system fonts): ASCII only, scaled by whole pixels.

use super::image::Image;

/// Width of `text` drawn at `scale` [pixels] (8 per character, minus the last column gap).
pub fn width(text: &str, scale: u32) -> u32 {
    8 * scale * text.chars().count() as u32
}

/// Height of a line at `scale` [pixels].
pub fn height(scale: u32) -> u32 {
    8 * scale
}

/// Draws `text` with its top-left corner at (`x`, `y`); characters outside ASCII are drawn
/// as `?`. Pixels outside the image are skipped.
pub fn draw(image: &mut Image, x: i64, y: i64, text: &str, scale: u32, rgb: [u8; 3]) {
    let s = i64::from(scale.max(1));
    for (k, ch) in text.chars().enumerate() {
        let code = if ch.is_ascii() {
            ch as usize
        } else {
            '?' as usize
        };
        let glyph = font8x8::legacy::BASIC_LEGACY[code];
        let left = x + 8 * s * k as i64;
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8 {
                if bits & (1 << col) == 0 {
                    continue;
                }
                for dy in 0..s {
                    for dx in 0..s {
                        image.set(left + col * s + dx, y + row as i64 * s + dy, rgb);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_marks_pixels_only_inside_its_box() {
        let bg = [255, 255, 255];
        let mut img = Image::filled(40, 20, bg);
        draw(&mut img, 2, 3, "V1", 2, [0, 0, 0]);
        let mut inside = 0;
        for y in 0..20 {
            for x in 0..40 {
                if img.pixel(x, y) != Some(bg) {
                    assert!(
                        (2..2 + width("V1", 2)).contains(&x) && (3..3 + height(2)).contains(&y)
                    );
                    inside += 1;
                }
            }
        }
        assert!(inside > 20, "only {inside} pixels drawn");
    }
}
