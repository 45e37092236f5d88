//! The trade measured on physics (issue 51, item 5): springs and finite elements on one
//! front against a reference we did not write. A cantilever 0.6 x 0.1 x 0.1 m of 288 tets
//! (E 10 MPa, 1000 kg/m^3, pinned at x = 0, sagging under its own weight) runs at each
//! setting until it is at rest; its displacement field is compared node by node with
//! scikit-fem's linear P1 solution on the same tets (`tests/data/fem/`, made by
//! `scripts/fem_reference.py`), compiled into the binary.

use std::time::Instant;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::pareto::pareto_front;
use super::simulate::Backends;
use tetrasim::error::{Error, Result};
use tetrasim::mesh::grid::box_tets;
use tetrasim::model::{Model, ModelBuilder};
use tetrasim::params::{MassMode, Method, Placement, SimParams, SpringKind};

/// The beam's cells along x, y, z (0.05 m cubes of 6 tets).
pub const CELLS: [usize; 3] = [12, 2, 2];
/// Young's modulus [Pa].
pub const YOUNGS: f64 = 1e7;
/// Density [kg/m^3].
pub const DENSITY: f64 = 1000.0;
/// At rest: no node faster than this [m/s] for [`STILL_FRAMES`] frames.
pub const STILL: f64 = 2e-3;
/// Frames without motion that count as rest (longer than the beams' slowest swing).
pub const STILL_FRAMES: u32 = 200;

/// scikit-fem's displacements of the beam, per Poisson's ratio: per node its rest position
/// and displacement [m], in the engine's node order.
const REFERENCES: [(f64, &str); 2] = [
    (
        0.3,
        include_str!("../../tests/data/fem/beam_12x2x2_nu0.30.txt"),
    ),
    (
        0.45,
        include_str!("../../tests/data/fem/beam_12x2x2_nu0.45.txt"),
    ),
];

/// One setting's result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CantileverPoint {
    /// Method name.
    pub method: String,
    /// Backend name.
    pub backend: String,
    /// The material's Poisson's ratio.
    pub poisson_ratio: f64,
    /// Solver iterations per step.
    pub iterations: u32,
    /// Frames run.
    pub frames: u32,
    /// Whether the beam came to rest within them.
    pub at_rest: bool,
    /// `|u - u_fem| / |u_fem|` over all nodes [%].
    pub field_error_pct: f64,
    /// The tip's mean sag [mm].
    pub tip_sag_mm: f64,
    /// scikit-fem's tip sag [mm].
    pub fem_tip_sag_mm: f64,
    /// Wall time per frame over the run [ms].
    pub ms_per_frame: f64,
    /// On the front of (cost, field error) among the points of its Poisson's ratio.
    pub pareto: bool,
}

/// The beam's parameters for `method` at `iterations`: the material from E, nu and the
/// density (implicit springs for the spring methods), gravity, no floor.
pub fn params(method: Method, nu: f64, iterations: u32) -> SimParams {
    SimParams {
        method,
        iterations,
        springs: match method {
            Method::NeoHookean => SpringKind::Explicit,
            _ => SpringKind::Implicit,
        },
        youngs_modulus: Some(YOUNGS),
        poisson_ratio: Some(nu),
        mass: MassMode::Density { density: DENSITY },
        floor: false,
        ..SimParams::default()
    }
}

/// The beam under `params`, pinned at x = 0, unplaced (metres as built).
pub fn beam(params: &SimParams) -> Result<Model> {
    let mesh = box_tets(DVec3::ZERO, 0.6 / CELLS[0] as f64, CELLS);
    let unplaced = Placement {
        fit_size: None,
        drop_height: None,
    };
    (ModelBuilder::new(&mesh).placement(unplaced))
        .material(params)
        .pinned_in_box(DVec3::splat(-1.0), DVec3::new(1e-9, 1.0, 1.0))
        .build()
}

/// scikit-fem's field at Poisson's ratio `nu` (0.3 or 0.45).
fn reference(nu: f64) -> Result<Vec<(DVec3, DVec3)>> {
    let (_, text) = (REFERENCES.iter())
        .find(|(r, _)| (r - nu).abs() < 1e-9)
        .ok_or_else(|| Error::Param {
            key: "poisson_ratio".into(),
            message: format!("the cantilever's references are at nu 0.3 and 0.45, not {nu}"),
        })?;
    Ok((text.lines())
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l
                .split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect();
            (DVec3::new(v[0], v[1], v[2]), DVec3::new(v[3], v[4], v[5]))
        })
        .collect())
}

/// Runs every method at every iteration count at each Poisson's ratio on `backend`, at most
/// `most` frames each; `progress` sees each point.
pub fn run_cantilever(
    methods: &[Method],
    iterations: &[u32],
    ratios: &[f64],
    backend: &str,
    most: u32,
    backends: &mut Backends,
    progress: &mut dyn FnMut(&CantileverPoint),
) -> Result<Vec<CantileverPoint>> {
    let mut points = Vec::new();
    for &nu in ratios {
        let fem = reference(nu)?;
        let first = points.len();
        for &method in methods {
            for &it in iterations {
                let params = params(method, nu, it);
                let model = beam(&params)?;
                let point = settle(&model, &params, backend, most, &fem, backends)?;
                progress(&point);
                points.push(point);
            }
        }
        let costs: Vec<(f64, f64)> = (points[first..].iter())
            .map(|p| (p.ms_per_frame, p.field_error_pct))
            .collect();
        for k in pareto_front(&costs) {
            points[first + k].pareto = true;
        }
    }
    Ok(points)
}

/// One setting: run until at rest (or `most` frames), then the field against `fem`.
fn settle(
    model: &Model,
    params: &SimParams,
    backend: &str,
    most: u32,
    fem: &[(DVec3, DVec3)],
    backends: &mut Backends,
) -> Result<CantileverPoint> {
    let mut solver = backends.create(backend, model, params)?;
    let (mut still_since, mut frames, mut at_rest) = (0, 0, false);
    let start = Instant::now();
    while frames < most && !at_rest {
        solver.step_frame()?;
        frames += 1;
        if frames % 10 == 0 {
            let state = solver.state()?;
            let fastest = (state.velocities.iter()).fold(0.0f64, |m, v| m.max(v.length()));
            still_since = if fastest < STILL { still_since + 10 } else { 0 };
            at_rest = still_since >= STILL_FRAMES;
        }
    }
    let ms_per_frame = 1e3 * start.elapsed().as_secs_f64() / f64::from(frames.max(1));
    let state = solver.state()?;
    let (mut diff, mut norm, mut tip, mut fem_tip, mut ends) = (0.0, 0.0, 0.0, 0.0, 0);
    for ((x, x0), (_, uf)) in state.positions.iter().zip(&model.positions).zip(fem) {
        let u = *x - *x0;
        diff += (u - *uf).length_squared();
        norm += uf.length_squared();
        if (x0.x - 0.6).abs() < 1e-9 {
            (tip, fem_tip, ends) = (tip - u.y, fem_tip - uf.y, ends + 1);
        }
    }
    Ok(CantileverPoint {
        method: params.method.to_string(),
        backend: backend.to_string(),
        poisson_ratio: params.poisson_ratio.unwrap_or(0.0),
        iterations: params.iterations,
        frames,
        at_rest,
        field_error_pct: 100.0 * (diff / norm).sqrt(),
        tip_sag_mm: 1e3 * tip / f64::from(ends),
        fem_tip_sag_mm: 1e3 * fem_tip / f64::from(ends),
        ms_per_frame,
        pareto: false,
    })
}

/// The points as a Markdown table, front marked.
pub fn table(points: &[CantileverPoint]) -> String {
    let mut out = String::from(
        "| nu | method | iterations | frames | at rest | field error % | tip sag mm (FEM) | ms/frame | front |\n\
         | ---: | --- | ---: | ---: | --- | ---: | ---: | ---: | --- |\n",
    );
    for p in points {
        out += &format!(
            "| {} | {} | {} | {} | {} | {:.2} | {:.3} ({:.3}) | {:.3} | {} |\n",
            p.poisson_ratio,
            p.method,
            p.iterations,
            p.frames,
            if p.at_rest { "yes" } else { "no" },
            p.field_error_pct,
            p.tip_sag_mm,
            p.fem_tip_sag_mm,
            p.ms_per_frame,
            if p.pareto { "*" } else { "" }
        );
    }
    out
}
