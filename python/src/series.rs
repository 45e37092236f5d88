//! `tetrasim.Series`: a simulation's frames as one series of files, added as the script
//! steps: a USD stage (`.usda`: every body's surface, its points and volume ratio
//! time-sampled, written when the series closes) or a folder of per-frame files as
//! `tetrasim run --format` writes them (`vtu` with a ParaView `.pvd` time series rewritten
//! at each frame, `vtk`, `ply`, `obj`).

use std::path::PathBuf;

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use tetrasim::output::{write_frame, OutputFormat, OutputUnits, UsdSeries};

use crate::simulation::Simulation;
use crate::to_py;

/// Where the frames go.
enum Target {
    /// The stage, written to `path` by `close`.
    Usd { stage: UsdSeries, path: PathBuf },
    /// One file per frame in `dir` (`frame_FFFFF.EXT`), and for `vtu` `dir/series.pvd`
    /// listing them with their simulated times.
    Files {
        dir: PathBuf,
        format: OutputFormat,
        entries: Vec<(f64, String)>,
    },
}

/// A series of one simulation's frames. Built by the Python layer's `tetrasim.Series`.
#[pyclass(module = "tetrasim", name = "_Series")]
pub struct Series {
    target: Target,
    /// The frames added (increasing).
    added: Vec<u32>,
    closed: bool,
}

#[pymethods]
impl Series {
    /// A series of `sim`'s frames at `path`: a `.usda` file, or a folder (made with its
    /// parents) of `format` files (`vtu`, `vtk`, `ply` or `obj`).
    #[new]
    #[pyo3(signature = (sim, path, format = None))]
    fn new(sim: &Simulation, path: PathBuf, format: Option<&str>) -> PyResult<Self> {
        let usd = path.extension().is_some_and(|e| e == "usda");
        let target = match (usd, format) {
            (true, None | Some("usd")) => {
                let doc = format!("tetrasim {} from Python", sim.method_name());
                let stage = UsdSeries::new(sim.model(), sim.frame_time(), &doc);
                Target::Usd { stage, path }
            }
            (true, Some(other)) => {
                return Err(PyValueError::new_err(format!(
                    "`{}` is a USD stage; `format` = {other:?} names a folder's files",
                    path.display()
                )))
            }
            (false, format) => {
                let format = match format.unwrap_or("vtu") {
                    "vtu" => OutputFormat::Vtu,
                    "vtk" => OutputFormat::Vtk,
                    "ply" => OutputFormat::Ply,
                    "obj" => OutputFormat::Obj,
                    other => {
                        return Err(PyValueError::new_err(format!(
                            "unknown `format` {other:?}: give \"vtu\", \"vtk\", \"ply\" or \
                             \"obj\" for a folder, or a path ending in .usda for a USD stage"
                        )))
                    }
                };
                std::fs::create_dir_all(&path).map_err(|e| to_py(tetrasim::Error::io(&path, e)))?;
                Target::Files {
                    dir: path,
                    format,
                    entries: Vec::new(),
                }
            }
        };
        Ok(Series {
            target,
            added: Vec::new(),
            closed: false,
        })
    }

    /// Adds `sim`'s current state as its current frame (`sim.frames`).
    fn add(&mut self, sim: &mut Simulation) -> PyResult<()> {
        if self.closed {
            return Err(PyRuntimeError::new_err("the series is closed"));
        }
        let frame = sim.frame();
        if let Some(&last) = self.added.last().filter(|&&last| frame <= last) {
            return Err(PyValueError::new_err(format!(
                "frame {frame} does not follow the last one added ({last}): step the \
                 simulation between adds"
            )));
        }
        let state = sim.state()?;
        match &mut self.target {
            Target::Usd { stage, .. } => stage.add(frame, sim.model(), &state),
            Target::Files {
                dir,
                format,
                entries,
            } => {
                let name = format!("frame_{frame:05}.{}", format.extension());
                write_frame(
                    &dir.join(&name),
                    *format,
                    OutputUnits::Simulation,
                    sim.model(),
                    &state,
                )
                .map_err(to_py)?;
                if *format == OutputFormat::Vtu {
                    entries.push((f64::from(frame) * sim.frame_time(), name));
                    tetrasim::mesh::io::write_pvd(dir.join("series.pvd"), entries)
                        .map_err(|e| to_py(e.into()))?;
                }
            }
        }
        self.added.push(frame);
        Ok(())
    }

    /// Writes what waits for the end (the USD stage); later adds are refused.
    fn close(&mut self) -> PyResult<()> {
        if !self.closed {
            if let Target::Usd { stage, path } = &self.target {
                stage.write(path).map_err(to_py)?;
            }
            self.closed = true;
        }
        Ok(())
    }

    /// The frames added so far.
    #[getter]
    fn frames(&self) -> Vec<u32> {
        self.added.clone()
    }
}
