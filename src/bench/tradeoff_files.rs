//! The files of `tetrasim tradeoff`: CSV, JSON, the Markdown report and the two PNG plots
//! (cost against volume error and against position error, Pareto fronts marked).

use std::path::{Path, PathBuf};

use super::plot::{write_png, LogChart, Series, SeriesKind, PLOT_SIZE};
use super::report::report;
use super::tradeoff::{position_point, volume_point, TradeoffRecord};
use tetrasim::error::{Error, Result};

fn chart(records: &[TradeoffRecord], volume: bool) -> LogChart {
    let point = if volume { volume_point } else { position_point };
    let mut methods: Vec<&str> = records.iter().map(|r| r.method.as_str()).collect();
    methods.dedup();
    let mut labels: Vec<String> = Vec::new();
    for r in records {
        if !labels.contains(&r.series()) {
            labels.push(r.series());
        }
    }
    let mut series: Vec<Series> = labels
        .iter()
        .map(|label| Series {
            label: label.clone(),
            points: records
                .iter()
                .filter(|r| r.series() == *label)
                .map(point)
                .collect(),
            kind: SeriesKind::Points,
        })
        .collect();
    // One front over all settings for the volume error; one per method for the position
    // error (each method has its own reference).
    let groups: Vec<Option<&str>> = if volume {
        vec![None]
    } else {
        methods.iter().map(|m| Some(*m)).collect()
    };
    for (k, group) in groups.into_iter().enumerate() {
        let mut front: Vec<(f64, f64)> = records
            .iter()
            .filter(|r| group.map_or(true, |m| r.method == m))
            .filter(|r| {
                if volume {
                    r.pareto_volume
                } else {
                    r.pareto_position
                }
            })
            .map(point)
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        series.push(Series {
            label: if k == 0 {
                "Pareto front".into()
            } else {
                String::new()
            },
            points: front,
            kind: SeriesKind::Front,
        });
    }
    let mesh = records
        .first()
        .map_or("?", |r| r.mesh.rsplit('/').next().unwrap_or(&r.mesh));
    let backend = records.first().map_or("?", |r| r.backend.as_str());
    LogChart {
        title: format!(
            "{mesh}: cost vs {} ({backend})",
            if volume {
                "volume error"
            } else {
                "position error"
            }
        ),
        x_label: format!("ms per frame ({backend}, median)"),
        y_label: if volume {
            "max |V/V0 - 1| [%]".into()
        } else {
            "RMS node error / bbox diagonal".into()
        },
        series,
    }
}

/// Files written by [`write_outputs`].
pub const OUTPUT_FILES: [&str; 5] = [
    "tradeoff.csv",
    "tradeoff.json",
    "report.md",
    "cost_vs_volume_error.png",
    "cost_vs_position_error.png",
];

/// Writes the CSV, JSON, report and plots into `dir` (created if missing); returns the paths.
pub fn write_outputs(dir: &Path, records: &[TradeoffRecord]) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let paths: Vec<PathBuf> = OUTPUT_FILES.iter().map(|f| dir.join(f)).collect();
    write_csv(&paths[0], records)?;
    let json = serde_json::to_string_pretty(records)
        .map_err(|e| Error::param("json", format!("cannot serialise the records: {e}")))?;
    crate::runner::write_atomically(&paths[1], json.as_bytes())?;
    crate::runner::write_atomically(&paths[2], report(records).as_bytes())?;
    write_png(&paths[3], &chart(records, true), PLOT_SIZE)?;
    write_png(&paths[4], &chart(records, false), PLOT_SIZE)?;
    Ok(paths)
}

/// Writes serialisable rows as CSV with a header (through a temporary file and a rename).
pub fn write_csv<T: serde::Serialize>(path: &Path, rows: &[T]) -> Result<()> {
    Ok(tetrasim::mesh::io::write_atomic(path, |w| {
        let mut writer = csv::Writer::from_writer(w);
        for row in rows {
            writer.serialize(row).map_err(std::io::Error::other)?;
        }
        writer.flush()
    })?)
}
