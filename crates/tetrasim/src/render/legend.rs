//! The legend of the colour modes: where its bar goes (the GPU draws the bar with the shader's
//! own colour map, glsl/render/legend.frag) and the labels the CPU writes beside it.

use super::image::Image;
use super::layout::pack_unorm2x16;
use super::style::TEXT_RGB;
use super::text;
use super::ColourMode;

/// The legend's placement in an image, in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegendLayout {
    /// Bar: left, top, right, bottom [pixels].
    pub bar: [u32; 4],
    /// Text scale (1 = 8 pixel glyphs).
    pub scale: u32,
}

impl LegendLayout {
    /// The legend of a `width` x `height` image: a vertical bar near the right edge.
    pub fn for_size(width: u32, height: u32) -> Self {
        let scale = if height >= 160 { 2 } else { 1 };
        let bar_w = (width / 25).clamp(10, 24);
        let margin = (width / 40).max(6);
        let top = margin + 2 * text::height(scale);
        let bottom = top + (height * 2 / 5).max(20);
        let right = width.saturating_sub(margin);
        LegendLayout {
            bar: [right.saturating_sub(bar_w), top, right, bottom.min(height)],
            scale,
        }
    }

    /// The bar's corners as fractions of the image `x0, y0, x1, y1` (y down).
    pub fn fractions(&self, width: u32, height: u32) -> [f32; 4] {
        let x = |p: u32| p as f32 / width.max(1) as f32;
        let y = |p: u32| p as f32 / height.max(1) as f32;
        [
            x(self.bar[0]),
            y(self.bar[1]),
            x(self.bar[2]),
            y(self.bar[3]),
        ]
    }

    /// [`LegendLayout::fractions`] packed for the push constants (`RenderPush::legend`).
    pub fn packed(&self, width: u32, height: u32) -> [u32; 2] {
        let [x0, y0, x1, y1] = self.fractions(width, height);
        [pack_unorm2x16(x0, y0), pack_unorm2x16(x1, y1)]
    }

    /// Writes the title above the bar and the values at its top, middle and bottom, right-
    /// aligned to its left.
    pub fn label(&self, image: &mut Image, mode: ColourMode, range: f32) {
        let (title, neutral) = match mode {
            ColourMode::Flat => return,
            ColourMode::Volume => ("V/V0", 1.0),
            ColourMode::Strain => ("strain", 0.0),
        };
        let [left, top, right, bottom] = self.bar.map(i64::from);
        let s = self.scale;
        let h = i64::from(text::height(s));
        let title_x = right - i64::from(text::width(title, s));
        text::draw(image, title_x, top - 2 * h, title, s, TEXT_RGB);
        let middle = (top + bottom) / 2;
        for (value, y) in [
            (neutral + range, top),
            (neutral, middle),
            (neutral - range, bottom),
        ] {
            let label = format_value(value, range);
            let x = left - 4 - i64::from(text::width(&label, s));
            text::draw(image, x, y - h / 2, &label, s, TEXT_RGB);
        }
    }
}

/// `value` with as many decimals as `range` needs (at least one, at most three).
pub fn format_value(value: f32, range: f32) -> String {
    let decimals = (1..=3)
        .find(|&d| {
            let scaled = range * 10f32.powi(d);
            (scaled - scaled.round()).abs() < 1e-3
        })
        .unwrap_or(3) as usize;
    format!("{value:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_get_the_decimals_the_range_needs() {
        assert_eq!(format_value(1.5, 0.5), "1.5");
        assert_eq!(format_value(0.75, 0.25), "0.75");
        assert_eq!(format_value(-0.1, 0.1), "-0.1");
    }

    #[test]
    fn the_bar_is_inside_the_image_and_leaves_room_for_labels() {
        for (w, h) in [(160, 120), (480, 360), (1920, 1080)] {
            let l = LegendLayout::for_size(w, h);
            let [x0, y0, x1, y1] = l.bar;
            assert!(
                x0 < x1 && x1 <= w && y0 < y1 && y1 <= h,
                "{w}x{h}: {:?}",
                l.bar
            );
            assert!(
                y0 >= 2 * text::height(l.scale),
                "{w}x{h}: no room for the title"
            );
            assert!(
                x0 >= text::width("0.75", l.scale),
                "{w}x{h}: no room for labels"
            );
            let f = l.fractions(w, h);
            assert!(f.iter().all(|v| (0.0..=1.0).contains(v)), "{f:?}");
        }
    }

    #[test]
    fn labels_are_drawn_left_of_the_bar() {
        let l = LegendLayout::for_size(200, 150);
        let bg = [255, 255, 255];
        let mut img = Image::filled(200, 150, bg);
        l.label(&mut img, ColourMode::Volume, 0.5);
        let marked: Vec<(u32, u32)> = (0..150)
            .flat_map(|y| (0..200).map(move |x| (x, y)))
            .filter(|&(x, y)| img.pixel(x, y) != Some(bg))
            .collect();
        assert!(marked.len() > 50);
        assert!(
            marked.iter().all(|&(x, _)| x < l.bar[2]),
            "text right of the bar"
        );
        let mut flat = Image::filled(200, 150, bg);
        l.label(&mut flat, ColourMode::Flat, 0.5);
        assert_eq!(flat, Image::filled(200, 150, bg));
    }
}
