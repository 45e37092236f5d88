//! Heat maps of a stability sweep as PNG (plotters' bitmap backend; text drawn with the
//! DejaVu Sans font bundled by the `dejavu` crate, so no system fonts are needed).
//!
//! Columns are time steps, rows stiffnesses. A diverged cell is dark grey with `X`; a
//! stable one is coloured by its worst volume error on a log scale from green (<= 0.01 %)
//! through yellow (1 %) to red (>= 100 %) and labelled with the value. A `*` marks a dt
//! above the springs' stable-step estimate.

use std::path::Path;
use std::sync::Once;

use plotters::coord::ranged1d::SegmentValue;
use plotters::prelude::*;
use plotters::style::FontStyle;

use super::sweep::Cell;
use tetrasim::error::{Error, Result};

static FONT: Once = Once::new();

/// Makes DejaVu Sans the `sans-serif` font of plotters (once per process).
fn register_font() {
    FONT.call_once(|| {
        // The bundled font is valid TrueType; a failure would only lose the labels.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// Colour of a stable cell with worst volume error `error` [%].
pub fn error_colour(error: f64) -> RGBColor {
    let t = ((error.max(1e-2).log10() + 2.0) / 4.0).clamp(0.0, 1.0);
    // Hue 120 (green) at t = 0 to 0 (red) at t = 1.
    let hue = 120.0 * (1.0 - t);
    let (r, g, b) = hsv(hue, 0.75, 0.9);
    RGBColor(r, g, b)
}

fn hsv(h: f64, s: f64, v: f64) -> (u8, u8, u8) {
    let c = v * s;
    let x = c * (1.0 - ((h / 60.0) % 2.0 - 1.0).abs());
    let m = v - c;
    let (r, g, b) = match h {
        h if h < 60.0 => (c, x, 0.0),
        h if h < 120.0 => (x, c, 0.0),
        _ => (0.0, c, x),
    };
    let byte = |u: f64| ((u + m) * 255.0).round() as u8;
    (byte(r), byte(g), byte(b))
}

/// Colour of diverged cells.
pub const DIVERGED: RGBColor = RGBColor(64, 64, 64);

/// Writes the heat map of `method`'s cells to `path` (through a temporary file and a
/// rename). `title` goes on top.
pub fn heat_map(
    path: &Path,
    cells: &[Cell],
    method: &str,
    dts: &[f64],
    kss: &[f64],
    title: &str,
) -> Result<()> {
    register_font();
    let fail = |e: String| Error::io(path, std::io::Error::other(e));
    let tmp = path.with_extension("tmp.png");
    {
        let root = BitMapBackend::new(
            &tmp,
            (120 + 90 * dts.len() as u32, 110 + 50 * kss.len() as u32),
        )
        .into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(e.to_string()))?;
        let (nx, ny) = (dts.len() as i32, kss.len() as i32);
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(8)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(
                (0..(nx - 1).max(0)).into_segmented(),
                (0..(ny - 1).max(0)).into_segmented(),
            )
            .map_err(|e| fail(e.to_string()))?;
        let label = |values: &[f64], v: &SegmentValue<i32>| match v {
            SegmentValue::CenterOf(i) => values
                .get(*i as usize)
                .map(|x| format!("{x:.0e}"))
                .unwrap_or_default(),
            _ => String::new(),
        };
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("dt [s]")
            .y_desc("ks [N/m]")
            .x_labels(dts.len())
            .y_labels(kss.len())
            .x_label_formatter(&|v| label(dts, v))
            .y_label_formatter(&|v| label(kss, v))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| fail(e.to_string()))?;
        for c in cells.iter().filter(|c| c.method == method) {
            let (Some(i), Some(j)) = (
                dts.iter().position(|&d| d == c.dt),
                kss.iter().position(|&k| k == c.ks),
            ) else {
                continue;
            };
            let (i, j) = (i as i32, j as i32);
            let colour = if c.diverged {
                DIVERGED
            } else {
                error_colour(c.max_volume_error_pct)
            };
            let corners = [
                (SegmentValue::Exact(i), SegmentValue::Exact(j)),
                (SegmentValue::Exact(i + 1), SegmentValue::Exact(j + 1)),
            ];
            chart
                .draw_series(std::iter::once(Rectangle::new(corners, colour.filled())))
                .map_err(|e| fail(e.to_string()))?;
            let mark = if c.dt > c.dt_estimate { "*" } else { "" };
            let text = if c.diverged {
                format!("X{mark}")
            } else {
                format!("{:.2}{mark}", c.max_volume_error_pct)
            };
            let style = TextStyle::from(("sans-serif", 13).into_font())
                .color(if c.diverged { &WHITE } else { &BLACK })
                .pos(plotters::style::text_anchor::Pos::new(
                    plotters::style::text_anchor::HPos::Center,
                    plotters::style::text_anchor::VPos::Center,
                ));
            chart
                .draw_series(std::iter::once(Text::new(
                    text,
                    (SegmentValue::CenterOf(i), SegmentValue::CenterOf(j)),
                    style,
                )))
                .map_err(|e| fail(e.to_string()))?;
        }
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_run_from_green_to_red() {
        let RGBColor(r0, g0, _) = error_colour(0.0);
        let RGBColor(r1, g1, _) = error_colour(100.0);
        assert!(g0 > 200 && r0 < 80, "{r0} {g0}");
        assert!(r1 > 200 && g1 < 80, "{r1} {g1}");
    }

    #[test]
    fn heat_map_is_a_png_with_the_cell_colours() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("map.png");
        let cell = |dt: f64, diverged: bool, error: f64| Cell {
            method: "volume".into(),
            dt,
            ks: 5000.0,
            steps: 10,
            diverged,
            max_volume_error_pct: error,
            final_volume_pct: 100.0 - error,
            dt_estimate: 2e-3,
        };
        let cells = [cell(1e-3, false, 0.01), cell(1e-2, true, 0.0)];
        heat_map(&path, &cells, "volume", &[1e-3, 1e-2], &[5000.0], "test").unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        assert!(!dir.path().join("map.tmp.png").exists());
    }
}
