//! Files written during a run: the deformed mesh every few frames, for ParaView, MeshLab or
//! any viewer that reads a mesh sequence. Each file is the engine's
//! [`tetrasim::output::write_frame`]; this module names them, makes the folder and keeps the
//! ParaView time series.
//!
//! | `--format` | files | content |
//! | --- | --- | --- |
//! | `ply` | `METHOD_FFFFF.ply` | boundary surface, per-vertex `quality` = V/V0 of the node |
//! | `obj` | `METHOD_FFFFF.obj` | boundary surface |
//! | `vtk` | `METHOD_FFFFF.vtk` | tet mesh with the fields below (legacy ASCII VTK) |
//! | `vtu` | `METHOD_FFFFF.vtu` + `METHOD.pvd` | tet mesh with the fields below; the `.pvd` gives each file its simulated time |
//! | `usd` | `METHOD.usda` | one animated USD stage: each body's surface, points and `volume_ratio` time-sampled at the frames written; written when the run ends ([`tetrasim::output::UsdSeries`]) |
//!
//! Fields of the tet formats: point data `displacement` (from the start), `velocity`,
//! `volume_ratio` (the node's incident tets: sum of V over sum of V0) and `pinned` (1 for a
//! pinned node); cell data `volume_ratio` (V/V0 of the tet) and `inverted` (1 when V <= 0).
//!
//! [`OutputUnits::Input`] writes positions, displacements and velocities in the mesh file's
//! units and frame (undoing `fit_size` and `drop_height`), so frames overlay the scan.

use std::path::{Path, PathBuf};

use tetrasim::backend::State;
use tetrasim::error::{Error, Result};
use tetrasim::mesh::io;
use tetrasim::model::Model;
pub use tetrasim::output::{write_frame, OutputFormat, OutputUnits, UsdSeries};
use tetrasim::params::Method;

/// Periodic output of the deformed mesh.
#[derive(Debug, Clone)]
pub struct FrameOutput {
    /// Folder to write into (created if missing).
    pub dir: PathBuf,
    /// Write every this many frames (and the initial state, as frame 0); at least 1.
    pub every: u32,
    /// File format.
    pub format: OutputFormat,
    /// Units and frame of the positions.
    pub units: OutputUnits,
}

impl FrameOutput {
    /// Checks `every` and creates the folder (with its parents).
    pub fn new(
        dir: impl Into<PathBuf>,
        every: u32,
        format: OutputFormat,
        units: OutputUnits,
    ) -> Result<Self> {
        if every == 0 {
            return Err(Error::param("every", "must be at least 1"));
        }
        if format == OutputFormat::Usd && units == OutputUnits::Input {
            return Err(Error::param(
                "units",
                "usd writes metres in the simulation's frame (units = simulation); `input` \
                 acts on the per-frame formats",
            ));
        }
        let dir = dir.into();
        create_dir(&dir)?;
        Ok(FrameOutput {
            dir,
            every,
            format,
            units,
        })
    }

    /// The file name of `method` at `frame`.
    pub fn file_name(&self, method: Method, frame: u32) -> String {
        format!("{}_{frame:05}.{}", method.name(), self.format.extension())
    }

    /// The file of `method` at `frame`.
    pub fn path(&self, method: Method, frame: u32) -> PathBuf {
        self.dir.join(self.file_name(method, frame))
    }

    /// The ParaView collection of `method` (written with [`OutputFormat::Vtu`]).
    pub fn pvd_path(&self, method: Method) -> PathBuf {
        self.dir.join(format!("{}.pvd", method.name()))
    }

    /// The USD stage of `method` (written with [`OutputFormat::Usd`]).
    pub fn usd_path(&self, method: Method) -> PathBuf {
        self.dir.join(format!("{}.usda", method.name()))
    }

    /// The recorder of one run of `method` on `model`, frames `frame_time` [s] apart.
    pub fn recorder<'a>(
        &'a self,
        model: &'a Model,
        method: Method,
        frame_time: f64,
    ) -> Recorder<'a> {
        let usd = (self.format == OutputFormat::Usd).then(|| {
            let doc = format!("tetrasim {}: {} s per frame", method.name(), frame_time);
            UsdSeries::new(model, frame_time, &doc)
        });
        Recorder {
            out: self,
            model,
            method,
            frame_time,
            usd,
        }
    }

    /// Writes the mesh of `model` in `state` for `method` at `frame`; `frame_time` is the
    /// simulated time of one frame [s] (for the `.pvd`). With [`OutputFormat::Vtu`] the
    /// method's `.pvd` is rewritten to list every frame written so far. A USD stage holds
    /// the whole run: it is written by a [`Recorder`], not frame by frame.
    fn write(
        &self,
        model: &Model,
        method: Method,
        frame: u32,
        frame_time: f64,
        state: &State,
    ) -> Result<()> {
        let path = self.path(method, frame);
        write_frame(&path, self.format, self.units, model, state)?;
        if self.format == OutputFormat::Vtu {
            let entries: Vec<(f64, String)> = (0..=frame)
                .step_by(self.every as usize)
                .map(|f| (f64::from(f) * frame_time, self.file_name(method, f)))
                .collect();
            io::write_pvd(self.pvd_path(method), &entries)?;
        }
        Ok(())
    }
}

/// The files of one run: each frame's file as it comes (and the `.pvd`), or the USD stage,
/// whose frames are kept until [`Recorder::finish`] writes it.
pub struct Recorder<'a> {
    out: &'a FrameOutput,
    model: &'a Model,
    method: Method,
    frame_time: f64,
    usd: Option<UsdSeries>,
}

impl Recorder<'_> {
    /// Records `state` as frame `frame`.
    pub fn record(&mut self, frame: u32, state: &State) -> Result<()> {
        match &mut self.usd {
            Some(stage) => {
                stage.add(frame, self.model, state);
                Ok(())
            }
            None => (self.out).write(self.model, self.method, frame, self.frame_time, state),
        }
    }

    /// Writes what waits for the run's end (the USD stage).
    pub fn finish(self) -> Result<()> {
        match &self.usd {
            Some(stage) => stage.write(&self.out.usd_path(self.method)),
            None => Ok(()),
        }
    }
}

/// The periodic mesh output a scene's `[output]` asks for (its folder created), if any.
pub fn frame_output(output: &tetrascene::scene::Output) -> Result<Option<FrameOutput>> {
    output
        .dir
        .as_ref()
        .map(|dir| {
            FrameOutput::new(
                dir,
                output.every.unwrap_or(tetrascene::scene::DEFAULT_EVERY),
                output.format.unwrap_or_default(),
                output.units.unwrap_or_default(),
            )
        })
        .transpose()
}

/// Creates a scene's output folders (and the JSON file's folder) before any work starts, or
/// says why one cannot be; refuses a JSON path that is a folder.
pub fn prepare_outputs(output: &tetrascene::scene::Output) -> Result<()> {
    if let Some(path) = &output.json {
        prepare_output_file(path)?;
    }
    if let Some(dir) = &output.dir {
        create_dir(dir)?;
    }
    Ok(())
}

/// Creates `dir` and its parents, or says why it cannot (e.g. a file is in the way).
pub fn create_dir(dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        return Err(Error::io(
            dir,
            std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                "exists and is not a folder",
            ),
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))
}

/// Prepares to write the file `path` later: creates its folder (with parents), or says why
/// it cannot; refuses a `path` that is a folder. Run before any work starts, so a long run
/// does not fail at its end.
pub fn prepare_output_file(path: &Path) -> Result<()> {
    if path.is_dir() {
        return Err(Error::io(
            path,
            std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                "is a folder; give a file name",
            ),
        ));
    }
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => create_dir(dir),
        _ => Ok(()),
    }
}

/// Writes `bytes` to `path` through a temporary file and a rename.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    Ok(io::write_atomic(path, |w| w.write_all(bytes))?)
}
