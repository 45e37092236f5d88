//! Log-log PNG charts of the trade-off and scaling studies, drawn with `plotters` into a
//! pixel buffer and written as PNG through a temporary file. Text uses DejaVu Sans from the
//! `dejavu` crate (registered once with plotters' `ab_glyph` font backend), so the plots
//! render the same headless, with no system fonts.

use std::path::Path;
use std::sync::OnceLock;

use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

use tetrasim::error::{Error, Result};

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesKind {
    /// Filled dots in the series colour.
    Points,
    /// Dots joined by a line, in the series colour.
    Line,
    /// The Pareto front: a black line through black rings drawn over the other series.
    Front,
}

/// One named set of points `(x, y)`; points with a non-positive or non-finite coordinate
/// cannot be shown on log axes and are left out. An empty label adds no legend entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub kind: SeriesKind,
}

/// A chart with logarithmic axes.
#[derive(Debug, Clone, PartialEq)]
pub struct LogChart {
    /// Caption.
    pub title: String,
    /// X axis description (with unit).
    pub x_label: String,
    /// Y axis description (with unit).
    pub y_label: String,
    /// Series, drawn in order.
    pub series: Vec<Series>,
}

/// Default plot size [px].
pub const PLOT_SIZE: (u32, u32) = (800, 560);

const FONT: &str = "sans-serif";

/// Series colours (ColorBrewer Set1 without its yellow, which is unreadable on white).
const COLOURS: [RGBColor; 7] = [
    RGBColor(228, 26, 28),
    RGBColor(55, 126, 184),
    RGBColor(77, 175, 74),
    RGBColor(152, 78, 163),
    RGBColor(255, 127, 0),
    RGBColor(166, 86, 40),
    RGBColor(247, 129, 191),
];

fn register_fonts() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && register_font(FONT, FontStyle::Bold, dejavu::sans::bold()).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(Error::param(
            "plot",
            "the bundled DejaVu Sans font could not be registered with plotters",
        ))
    }
}

fn visible(p: &(f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite() && p.0 > 0.0 && p.1 > 0.0
}

/// A tick label: integers without decimals, small values in exponent form.
fn tick(v: f64) -> String {
    let a = v.abs();
    if a >= 1e6 || (a > 0.0 && a < 0.01) {
        format!("{v:.0e}")
    } else if a >= 10.0 {
        format!("{v:.0}")
    } else if a >= 1.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    }
}

/// Range covering `values` with a margin of a fifth of a decade each side.
fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !(lo.is_finite() && hi > 0.0) {
        return (1.0, 10.0);
    }
    let (lo, hi) = if hi / lo < 10f64.powf(0.5) {
        (lo / 2.0, hi * 2.0)
    } else {
        (lo, hi)
    };
    (lo / 10f64.powf(0.2), hi * 10f64.powf(0.2))
}

/// Renders `chart` to RGB pixels of `size` (width, height) [px].
pub fn render(chart: &LogChart, size: (u32, u32)) -> Result<Vec<u8>> {
    register_fonts()?;
    let mut buf = vec![255u8; size.0 as usize * size.1 as usize * 3];
    draw(chart, &mut buf, size)
        .map_err(|e| Error::param("plot", format!("{}: {e}", chart.title)))?;
    Ok(buf)
}

fn draw(
    chart: &LogChart,
    buf: &mut [u8],
    size: (u32, u32),
) -> std::result::Result<(), Box<dyn std::error::Error>> {
    let root = BitMapBackend::with_buffer(buf, size).into_drawing_area();
    root.fill(&WHITE)?;
    let points = || {
        chart
            .series
            .iter()
            .flat_map(|s| s.points.iter().filter(|p| visible(p)))
    };
    let (x0, x1) = log_range(points().map(|p| p.0));
    let (y0, y1) = log_range(points().map(|p| p.1));
    let mut ctx = ChartBuilder::on(&root)
        .caption(&chart.title, (FONT, 20))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    ctx.configure_mesh()
        .x_desc(&chart.x_label)
        .y_desc(&chart.y_label)
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 15))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .draw()?;
    let mut colour_index = 0;
    for s in &chart.series {
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(visible).collect();
        match s.kind {
            SeriesKind::Front => {
                let style = ShapeStyle::from(&BLACK).stroke_width(2);
                ctx.draw_series(LineSeries::new(pts.clone(), style))?;
                let rings = ctx.draw_series(pts.iter().map(|&p| Circle::new(p, 7, style)))?;
                if !s.label.is_empty() {
                    rings
                        .label(&s.label)
                        .legend(move |(x, y)| Circle::new((x + 10, y), 6, style));
                }
            }
            SeriesKind::Points | SeriesKind::Line => {
                let colour = COLOURS[colour_index % COLOURS.len()];
                colour_index += 1;
                if s.kind == SeriesKind::Line {
                    ctx.draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))?;
                }
                ctx.draw_series(pts.iter().map(|&p| Circle::new(p, 4, colour.filled())))?
                    .label(&s.label)
                    .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
            }
        }
    }
    ctx.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 13))
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    root.present()?;
    Ok(())
}

/// Renders `chart` at `size` and writes it to `path` as an 8-bit RGB PNG (through a
/// temporary file and a rename).
pub fn write_png(path: &Path, chart: &LogChart, size: (u32, u32)) -> Result<()> {
    let pixels = render(chart, size)?;
    Ok(tetrasim::mesh::io::write_atomic(path, |w| {
        let mut encoder = png::Encoder::new(w, size.0, size.1);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
        writer
            .write_image_data(&pixels)
            .map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)
    })?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_short() {
        assert_eq!(
            [tick(1000.0), tick(2.5), tick(0.25), tick(0.001), tick(2e6)],
            ["1000", "2.5", "0.25", "1e-3", "2e6"].map(String::from)
        );
    }

    #[test]
    fn log_range_pads_and_handles_empty() {
        assert_eq!(log_range(std::iter::empty()), (1.0, 10.0));
        let (lo, hi) = log_range([1.0, 100.0].into_iter());
        assert!(
            lo < 1.0 && lo > 0.5 && hi > 100.0 && hi < 200.0,
            "{lo} {hi}"
        );
    }

    #[test]
    fn text_is_drawn() {
        // Two charts differing only in their caption's letters differ in pixels: glyphs are
        // rasterised headless.
        let series = vec![Series {
            label: "a".into(),
            points: vec![(1.0, 2.0), (10.0, 0.5)],
            kind: SeriesKind::Line,
        }];
        let chart = |title: &str| LogChart {
            title: title.into(),
            x_label: String::new(),
            y_label: String::new(),
            series: series.clone(),
        };
        let a = render(&chart("AAAA"), (300, 200)).unwrap();
        let b = render(&chart("OOOO"), (300, 200)).unwrap();
        let differing = a.iter().zip(&b).filter(|(a, b)| a != b).count();
        assert!(differing > 100, "{differing} pixels differ");
    }
}
