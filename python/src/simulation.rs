//! `tetrasim.Simulation`: one model under one parameter set on one backend, stepped frame by
//! frame through the engine's frame driver (the same as `tetrasim run`), with the state as
//! numpy arrays and the run record as JSON.

use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Instant;

use numpy::{PyArray1, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyFileNotFoundError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use tetrasim::backend::vulkan::EngineOptions;
use tetrasim::backend::{Backend, Reactions, State};
use tetrasim::metrics::RunRecord;
use tetrasim::model::{Model, ModelBuilder};
use tetrasim::params::{Accuracy, Placement, SimParams};
use tetrasim::problem::Problem;
use tetrasim::sim::{Advance, BackendFactory, Checkpoint};

use crate::arrays::{points_from_numpy, points_to_numpy};
use crate::mesh::Mesh;
use crate::{to_py, DivergedError};

/// The default parameters (`SimParams`) as JSON: every run parameter by its name.
#[pyfunction]
pub fn default_params() -> PyResult<String> {
    serde_json::to_string(&SimParams::default()).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The method of a body given the parameters `params_json` that names none, by its name:
/// the scene's rule (`tetrascene::scene::material_method`: the finite elements for a
/// material given by its Young's modulus unless the parameters ask for springs).
#[pyfunction]
pub fn material_method(params_json: &str) -> PyResult<&'static str> {
    Ok(tetrascene::scene::material_method(&parse_params(params_json)?).name())
}

/// The default parameters with the speed/accuracy dial's level `accuracy` (`fast`,
/// `balanced`, `accurate`) written on them, as JSON: the base Python's keywords then
/// override ([`tetrasim::params::Accuracy`]).
#[pyfunction]
pub fn accuracy_params(accuracy: &str) -> PyResult<String> {
    let level: Accuracy = serde_json::from_value(serde_json::Value::from(accuracy)).map_err(|_| {
        PyValueError::new_err(format!(
            "invalid parameter `accuracy` = {accuracy:?}: one of \"fast\", \"balanced\", \"accurate\""
        ))
    })?;
    let mut params = SimParams::default();
    level.apply(&mut params);
    serde_json::to_string(&params).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// `json` (the keys of `SimParams`) as parameters; an error names the first key whose value
/// is wrong.
fn parse_params(json: &str) -> PyResult<SimParams> {
    let error = match serde_json::from_str::<SimParams>(json) {
        Ok(params) => return Ok(params),
        Err(e) => e,
    };
    let given: serde_json::Map<String, serde_json::Value> = serde_json::from_str(json)
        .map_err(|e| PyValueError::new_err(format!("invalid parameters: {e}")))?;
    let base = serde_json::to_value(SimParams::default())
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    for (key, value) in given {
        let mut trial = base.clone();
        trial[&key] = value.clone();
        if let Err(e) = serde_json::from_value::<SimParams>(trial) {
            return Err(PyValueError::new_err(format!(
                "invalid parameter `{key}` = {value}: {e}"
            )));
        }
    }
    Err(PyValueError::new_err(format!(
        "invalid parameters: {error}"
    )))
}

/// A simulation of one mesh. Built by the Python layer's `tetrasim.Simulation`, which turns
/// keyword parameters into `params_json` (the keys of `SimParams`).
#[pyclass(module = "tetrasim", name = "_Simulation")]
pub struct Simulation {
    model: Model,
    /// In a mutex only to be `Sync` (PyO3's classes are); `&mut self` reaches it unlocked.
    /// `None` once closed.
    backend: Mutex<Option<Box<dyn Backend>>>,
    driver: tetrasim::sim::Simulation,
    record: RunRecord,
    /// When the simulation was made (the record's `wall_s` counts from here).
    created: Instant,
}

impl Simulation {
    /// `model` under `params` on `backend`, before its first frame.
    fn of_model(
        py: Python<'_>,
        model: Model,
        params: &SimParams,
        label: &str,
        backend: &str,
        device: Option<&str>,
    ) -> PyResult<Self> {
        let options = engine_options(backend, device)?;
        let problem = Problem::new(&model, params).map_err(to_py)?;
        let backend = py
            .allow_threads(|| BackendFactory::new(options).create(backend, &problem))
            .map_err(to_py)?;
        let record = RunRecord::new(&problem, label, 0, backend.name());
        Ok(Simulation {
            driver: tetrasim::sim::Simulation::new(&model, params),
            model,
            backend: Mutex::new(Some(backend)),
            record,
            created: Instant::now(),
        })
    }

    /// The scene `load` gives, staged as `tetrasim run --scene` stages it (without the GIL;
    /// its old key names raised as `DeprecationWarning`s), on `backend`, and its frames.
    fn of_scene(
        py: Python<'_>,
        load: impl FnOnce() -> tetrasim::Result<tetrascene::scene::Scene> + Send,
        backend: &str,
        device: Option<&str>,
    ) -> PyResult<(Self, u32)> {
        let (staged, warnings) = py
            .allow_threads(|| {
                let scene = load()?;
                Ok::<_, tetrasim::Error>((tetrascene::launch::stage(&scene)?, scene.warnings))
            })
            .map_err(to_py)?;
        warn_renamed(py, &warnings)?;
        let (model, params, label) = (staged.model, &staged.params, &staged.label);
        let sim = Simulation::of_model(py, model, params, label, backend, device)?;
        Ok((sim, staged.frames))
    }

    /// The forces out of the last step ([`Backend::reactions`]); an error naming the
    /// backend where it does not measure them.
    fn reactions(&mut self) -> PyResult<Reactions> {
        let backend = self.backend()?;
        let name = backend.name();
        backend.reactions().map_err(to_py)?.ok_or_else(|| {
            PyRuntimeError::new_err(format!(
                "the {name} backend did not measure the forces pins and colliders exert (it \
                 measures them with per-frame metrics)"
            ))
        })
    }

    fn backend(&mut self) -> PyResult<&mut Box<dyn Backend>> {
        backend_of(&mut self.backend)
    }

    /// The model simulated.
    pub(crate) fn model(&self) -> &Model {
        &self.model
    }

    /// The simulated time of one frame [s].
    pub(crate) fn frame_time(&self) -> f64 {
        self.record.params.frame_time()
    }

    /// The method's name.
    pub(crate) fn method_name(&self) -> &'static str {
        self.record.params.method.name()
    }

    /// Frames completed.
    pub(crate) fn frame(&self) -> u32 {
        self.driver.frames()
    }

    /// The backend's state now.
    pub(crate) fn state(&mut self) -> PyResult<State> {
        self.backend()?.state().map_err(to_py)
    }
}

/// The backend in `slot`; an error if the simulation was closed or a panic poisoned it.
fn backend_of(slot: &mut Mutex<Option<Box<dyn Backend>>>) -> PyResult<&mut Box<dyn Backend>> {
    slot.get_mut()
        .map_err(|_| PyRuntimeError::new_err("the backend panicked earlier and is unusable"))?
        .as_mut()
        .ok_or_else(|| {
            PyRuntimeError::new_err("the simulation is closed (its backend and GPU memory freed)")
        })
}

/// Each of a scene's `warnings` (old key names) as a Python `DeprecationWarning`.
fn warn_renamed(py: Python<'_>, warnings: &[String]) -> PyResult<()> {
    let category = py.get_type::<pyo3::exceptions::PyDeprecationWarning>();
    for warning in warnings {
        let text = warning.trim_start_matches("warning: ").replace('\0', " ");
        let message = std::ffi::CString::new(text).unwrap_or_default();
        PyErr::warn(py, &category, &message, 1)?;
    }
    Ok(())
}

/// The engine options of `backend` on `device` (a name's part or an index, as
/// `tetrasim run --device` takes it; only with `vulkan`).
fn engine_options(backend: &str, device: Option<&str>) -> PyResult<EngineOptions> {
    let mut options = EngineOptions::default();
    if let Some(device) = device {
        if backend != "vulkan" {
            return Err(PyValueError::new_err(format!(
                "`device` acts only with backend=\"vulkan\"; the backend is {backend:?}"
            )));
        }
        options.device = match device.parse() {
            Ok(selector) => selector,
            Err(never) => match never {},
        };
    }
    Ok(options)
}

#[pymethods]
impl Simulation {
    /// Places `mesh` (`fit_size` [m] across, lowest node `drop_height` [m] above the floor;
    /// `None` keeps the mesh's own size or position; turned first by the quaternion
    /// `rotation` `[w, x, y, z]` about its bounding box's centre; then moved by `offset`
    /// [m]), pins the nodes `pins` and those inside
    /// the boxes `pin_boxes` (`((x0, y0, z0), (x1, y1, z1))` [m], after placement), turns on
    /// its contact with itself if `self_contact`, prepares the problem under `params_json`
    /// and creates `backend`.
    #[new]
    // The Python keyword signature: one argument per keyword.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (mesh, params_json, backend = "cpu", fit_size = Some(1.0), drop_height = Some(0.1), pins = Vec::new(), pin_boxes = Vec::new(), offset = [0.0; 3], self_contact = false, rotation = None, device = None))]
    fn new(
        py: Python<'_>,
        mesh: &Mesh,
        params_json: &str,
        backend: &str,
        fit_size: Option<f64>,
        drop_height: Option<f64>,
        pins: Vec<u32>,
        pin_boxes: Vec<([f64; 3], [f64; 3])>,
        offset: [f64; 3],
        self_contact: bool,
        rotation: Option<[f64; 4]>,
        device: Option<&str>,
    ) -> PyResult<Self> {
        let params = parse_params(params_json)?;
        let n = mesh.inner.nodes.len();
        if let Some(&bad) = pins.iter().find(|&&i| i as usize >= n) {
            return Err(PyValueError::new_err(format!(
                "`pins` holds node {bad}, outside 0..{n}"
            )));
        }
        let mut builder = ModelBuilder::new(&mesh.inner)
            .placement(Placement {
                fit_size,
                drop_height,
            })
            .rotation(
                rotation.map_or(tetrasim::glam::DQuat::IDENTITY, |[w, x, y, z]| {
                    tetrasim::glam::DQuat::from_xyzw(x, y, z, w)
                }),
            )
            .offset(offset.into())
            .mass(params.mass)
            .pinned(pins)
            .self_contact(self_contact);
        for (lo, hi) in pin_boxes {
            builder = builder.pinned_in_box(lo.into(), hi.into());
        }
        let model = builder.build().map_err(to_py)?;
        Simulation::of_model(py, model, &params, &mesh.label, backend, device)
    }

    /// The scene file `path` (objects, materials, pins, velocities, colliders, `[solver]`;
    /// its `[output]` is the command line's and not written here) staged as `tetrasim run
    /// --scene` stages it, on `backend`; also returns the frames the scene asks for.
    #[staticmethod]
    #[pyo3(signature = (path, backend = "cpu", device = None))]
    fn from_scene(
        py: Python<'_>,
        path: PathBuf,
        backend: &str,
        device: Option<&str>,
    ) -> PyResult<(Self, u32)> {
        if !path.exists() {
            return Err(PyFileNotFoundError::new_err(format!(
                "{}: the file does not exist",
                path.display()
            )));
        }
        let load = || tetrascene::scene::Scene::load(&path);
        Simulation::of_scene(py, load, backend, device)
    }

    /// A scene given as text (TOML, as a scene file; relative paths taken from the folder
    /// `base`), staged as `from_scene` stages a file; also returns its frames.
    #[staticmethod]
    #[pyo3(signature = (text, base, backend = "cpu", device = None))]
    fn from_scene_text(
        py: Python<'_>,
        text: &str,
        base: PathBuf,
        backend: &str,
        device: Option<&str>,
    ) -> PyResult<(Self, u32)> {
        let load = || Ok(tetrascene::scene::Scene::parse(text)?.relative_to(&base));
        Simulation::of_scene(py, load, backend, device)
    }

    /// Advances `frames` frames (each `substeps` time steps) without holding the GIL,
    /// measuring the volume after each. Raises `DivergedError` when the run diverges (the
    /// frames before it stay in the record).
    #[pyo3(signature = (frames = 1))]
    fn step(&mut self, py: Python<'_>, frames: u32) -> PyResult<()> {
        let backend = backend_of(&mut self.backend)?;
        let driver = &mut self.driver;
        let result = py.allow_threads(|| {
            for _ in 0..frames {
                if driver.advance(backend.as_mut(), true)? == Advance::Stopped {
                    break;
                }
            }
            Ok::<_, tetrasim::Error>(())
        });
        result.map_err(to_py)?;
        match &self.driver.divergence {
            Some(d) => Err(DivergedError::new_err(d.clone())),
            None => Ok(()),
        }
    }

    /// Node positions [m], (n, 3) float64 (a copy read back from the backend).
    #[getter]
    fn positions<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let state = self.backend()?.state().map_err(to_py)?;
        Ok(points_to_numpy(py, &state.positions))
    }

    /// Node velocities [m/s], (n, 3) float64 (a copy).
    #[getter]
    fn velocities<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let state = self.backend()?.state().map_err(to_py)?;
        Ok(points_to_numpy(py, &state.velocities))
    }

    /// Replaces every node's position [m] and velocity [m/s] ((n, 3) arrays; `velocities`
    /// `None` keeps the current ones). Pinned nodes stay where they are put and move at the
    /// velocity they are given. Raises `ValueError` on a wrong shape or a non-finite value.
    #[pyo3(signature = (positions, velocities = None))]
    fn set_state(
        &mut self,
        positions: PyReadonlyArray2<'_, f64>,
        velocities: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<()> {
        let n = self.model.node_count();
        let positions = points_from_numpy(&positions, "positions", Some(n))?;
        let velocities = match velocities {
            Some(v) => points_from_numpy(&v, "velocities", Some(n))?,
            None => self.backend()?.state().map_err(to_py)?.velocities,
        };
        let state = State {
            positions,
            velocities,
        };
        self.backend()?.set_state(&state).map_err(to_py)
    }

    /// The total volume over the rest volume now (1.0: kept).
    #[getter]
    fn volume_ratio(&mut self) -> PyResult<f64> {
        let sample = self.backend()?.volume().map_err(to_py)?;
        Ok(sample.volume / self.model.total_rest_volume())
    }

    /// The force [N] the pinned nodes (pins and clamps) exerted on the bodies in the last
    /// step, (3,) float64: a body hanging at rest from its pins is held by its weight.
    #[getter]
    fn pin_force<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let reactions = self.reactions()?;
        Ok(PyArray1::from_slice(py, &reactions.pin.to_array()))
    }

    /// The floor's force [N] on the bodies in the last step, (3,) float64 (zeros without a
    /// floor).
    #[getter]
    fn floor_force<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let reactions = self.reactions()?;
        Ok(PyArray1::from_slice(py, &reactions.floor.to_array()))
    }

    /// Each kinematic collider's force [N] on the bodies in the last step, (colliders, 3)
    /// float64, in the scene's order (the floor is `floor_force`).
    #[getter]
    fn collider_forces<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let reactions = self.reactions()?;
        Ok(points_to_numpy(py, &reactions.colliders))
    }

    /// Each clamp's force [N] on the bodies in the last step, (clamps, 3) float64, in the
    /// scene's order (each a share of `pin_force`).
    #[getter]
    fn clamp_forces<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let reactions = self.reactions()?;
        Ok(points_to_numpy(py, &reactions.clamps))
    }

    /// Frames completed.
    #[getter]
    fn frames(&self) -> u32 {
        self.driver.frames()
    }

    /// Simulated time [s].
    #[getter]
    fn time(&self) -> f64 {
        self.driver.time()
    }

    /// Saves the run to the checkpoint file `path` (through a temporary file): its state,
    /// what its steps carry and its record so far; `load` on a simulation built the same
    /// way continues it bit for bit.
    fn save(&mut self, path: PathBuf) -> PyResult<()> {
        let backend = backend_of(&mut self.backend)?;
        let params = &self.record.params;
        let checkpoint =
            Checkpoint::take(&self.model, params, backend.as_mut(), &self.driver).map_err(to_py)?;
        checkpoint.write(&path).map_err(to_py)
    }

    /// Resumes the checkpoint at `path`, saved by a simulation built the same way (mesh,
    /// placement, parameters, backend); refuses one of another run, naming what differs.
    fn load(&mut self, path: PathBuf) -> PyResult<()> {
        let checkpoint = Checkpoint::read(&path).map_err(to_py)?;
        let backend = backend_of(&mut self.backend)?;
        let params = &self.record.params;
        checkpoint
            .resume(&self.model, params, backend.as_mut(), &mut self.driver)
            .map_err(to_py)
    }

    /// Frees the backend (on `vulkan` its device memory and objects); every later call
    /// that needs it raises. Closing twice is harmless.
    fn close(&mut self) -> PyResult<()> {
        let slot = (self.backend.get_mut())
            .map_err(|_| PyRuntimeError::new_err("the backend panicked earlier"))?;
        drop(slot.take());
        Ok(())
    }

    /// The backend's name (`cpu-ref`, `cpu` or `vulkan`).
    #[getter(backend)]
    fn backend_name(&mut self) -> PyResult<&'static str> {
        Ok(self.backend()?.name())
    }

    /// The run record so far as JSON (what `tetrasim run --json` writes for one method).
    fn record_json(&mut self) -> PyResult<String> {
        let mut record = self.record.clone();
        let frames = self.driver.frames();
        record.frames = frames;
        self.driver.fill_record(&mut record);
        record.ms_per_frame = match frames {
            0 => 0.0,
            _ => 1e3 * self.driver.stepping_s / f64::from(frames),
        };
        record.wall_s = self.created.elapsed().as_secs_f64();
        if let Some(gpu) = self.backend()?.gpu_report().map_err(to_py)? {
            record.device = Some(gpu.device);
            record.atomics = Some(gpu.atomics);
            record.passes = Some(gpu.passes);
        }
        serde_json::to_string(&record).map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Writes the deformed mesh to `path` as `tetrasim run --format` does, the format from
    /// the extension (`.ply`, `.obj`, `.vtk`, `.vtu`, `.usda`: a one-sample stage); the tet
    /// formats carry the fields `displacement`, `velocity`, `volume_ratio`, `pinned` and
    /// `inverted`.
    fn write(&mut self, path: PathBuf) -> PyResult<()> {
        let state = self.backend()?.state().map_err(to_py)?;
        tetrasim::output::write_state(&path, &self.model, &state).map_err(to_py)
    }
}
