//! TetGen as a pipeline stage: switches from the options, and the search for a volume bound
//! (and, when the surface alone would give too many tets, a simplification) that lands near
//! `--target-tets`.
//!
//! The target mode keeps the surface as given (`-Y`): otherwise the quality bound refines
//! the surface itself and the count depends mostly on the face count. Only when a volume
//! bound adds no tet at all under `-Y` (it happens on very coarse surfaces) does it go on
//! without `-Y`, unless `--preserve-surface` was asked for.
//!
//! Model: TetGen's count is about `T(a) = T0 + C * a^s` (`s` near -1), where `T0` is what
//! the surface alone needs (no volume bound) and `a` the max volume. One run without a bound
//! measures `T0` (if it is already above the target, the surface is simplified further); a
//! first bound of `0.8 V / (N - T0)` (measured on the scans) is corrected with `s = -1`, then
//! with `s` fitted on the last two runs. At most [`MAX_RUNS`] runs; the closest result wins.

use tetgen_sys::{Switches, TetGenOutput};

use super::options::PrepOptions;
use crate::error::{Error, Result};
use crate::geometry::tet_volume;
use crate::mesh::repair::{clean, untangle::untangle};
use crate::mesh::{simplify::simplify, topology, SurfaceMesh, TetMesh};

/// Most TetGen runs spent on reaching a target.
pub const MAX_RUNS: usize = 6;
/// Other simplifications tried when TetGen rejects a simplified surface.
const MAX_SIMPLIFY_RETRIES: usize = 3;
/// Stop searching once within this fraction of the target.
const GOOD_ENOUGH: f64 = 0.10;
/// Face budget as a fraction of the target tet count. With the surface kept (`-Y`) TetGen
/// makes about two tets per face before volume refinement (measured on the bunny and the
/// horse simplified to 1.2k-5k faces with `-pq2Y`), which leaves about a third of the target
/// to the volume bound. Without `-Y` the quality bound adds Steiner points on the surface:
/// 7-14 tets per face on the same surfaces.
const FACES_PER_TET: f64 = 1.0 / 3.0;
/// A surface with at most this many faces per target tet is not simplified (it fits as is).
const MAX_FACES_PER_TET: f64 = 1.0 / 2.0;

/// A TetGen result and how it was reached.
#[derive(Debug, Clone)]
pub struct TetgenResult {
    /// The mesh, tets positively oriented, boundary faces outward.
    pub mesh: TetMesh,
    /// The switch string of the run that produced it.
    pub switches: String,
    /// TetGen runs made.
    pub runs: usize,
    /// Faces of the surface handed to TetGen (after simplification, if any).
    pub faces_meshed: usize,
    /// The surface handed to TetGen for this run (simplified, if it was).
    pub surface: SurfaceMesh,
}

/// Simplifies `surface` to about `faces` faces, then cuts out and refills any crossings or
/// non-manifold edges the collapses made.
fn simplified_surface(surface: &SurfaceMesh, faces: usize) -> SurfaceMesh {
    let mut s = simplify(surface, faces);
    untangle(&mut s, true);
    clean::drop_unreferenced(&mut s);
    s
}

/// Converts TetGen's output; tets are reoriented if TetGen ever gives a negative one.
pub fn to_tet_mesh(out: TetGenOutput) -> TetMesh {
    let nodes: Vec<glam::DVec3> = out
        .points
        .iter()
        .map(|p| glam::DVec3::from_array(*p))
        .collect();
    let tets: Vec<[u32; 4]> = out
        .tets
        .iter()
        .map(|&t| {
            let p = t.map(|i| nodes[i as usize]);
            if tet_volume(p) < 0.0 {
                [t[0], t[1], t[3], t[2]]
            } else {
                t
            }
        })
        .collect();
    let faces = topology::boundary_faces(&tets);
    TetMesh { nodes, tets, faces }
}

fn run(surface: &SurfaceMesh, switches: &Switches) -> Result<TetMesh> {
    let points: Vec<[f64; 3]> = surface.vertices.iter().map(|p| p.to_array()).collect();
    tetgen_sys::tetrahedralize(&points, &surface.triangles, switches)
        .map(to_tet_mesh)
        .map_err(|e| Error::Meshing(e.to_string()))
}

fn base_switches(options: &PrepOptions) -> Switches {
    Switches {
        quality: options.quality,
        max_volume: options.max_volume,
        preserve_surface: options.preserve_surface,
        extra: String::new(),
    }
}

/// Meshes `surface` with the options' switches, no target.
pub fn mesh_plain(surface: &SurfaceMesh, options: &PrepOptions) -> Result<TetgenResult> {
    let switches = base_switches(options);
    let mesh = run(surface, &switches)?;
    Ok(TetgenResult {
        mesh,
        switches: switches.to_tetgen_string(),
        runs: 1,
        faces_meshed: surface.triangles.len(),
        surface: surface.clone(),
    })
}

/// Meshes `surface` (enclosing `volume`) aiming at `target` tets. `progress` gets a line
/// per run.
pub fn mesh_for_target(
    surface: &SurfaceMesh,
    volume: f64,
    target: usize,
    options: &PrepOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<TetgenResult> {
    let n = target as f64;
    let user_asked_y = options.preserve_surface;
    let mut options = &PrepOptions {
        preserve_surface: true,
        ..options.clone()
    };
    let without_y = PrepOptions {
        preserve_surface: false,
        ..options.clone()
    };
    let mut face_budget = if surface.triangles.len() as f64 <= n * MAX_FACES_PER_TET {
        surface.triangles.len()
    } else {
        ((n * FACES_PER_TET) as usize).max(4)
    };
    let mut best: Option<TetgenResult> = None;
    let mut runs = 0;
    let off = |t: usize| (t as f64 - n).abs() / n;
    let keep = |r: TetgenResult, best: &mut Option<TetgenResult>| {
        if best
            .as_ref()
            .map_or(true, |b| off(r.mesh.tets.len()) < off(b.mesh.tets.len()))
        {
            *best = Some(r);
        }
    };
    // 1. The surface (simplified to the budget) without a volume bound: T0.
    let mut current;
    let mut t0;
    let mut failures = 0;
    loop {
        let simplified = surface.triangles.len() > face_budget;
        current = if simplified {
            progress(&format!(
                "simplifying {} -> {} faces",
                surface.triangles.len(),
                face_budget
            ));
            simplified_surface(surface, face_budget)
        } else {
            surface.clone()
        };
        let switches = Switches {
            max_volume: None,
            ..base_switches(options)
        };
        runs += 1;
        let mesh = match run(&current, &switches) {
            Ok(mesh) => {
                let faces = current.triangles.len();
                let tets = mesh.tets.len();
                progress(&format!(
                    "TetGen run {runs}: -{} on {faces} faces -> {tets} tets",
                    switches.to_tetgen_string()
                ));
                mesh
            }
            // A simplified surface can fold onto itself where the original did not: try
            // another face count.
            Err(e) if simplified && failures < MAX_SIMPLIFY_RETRIES => {
                failures += 1;
                progress(&format!(
                    "TetGen failed on the simplified surface ({e}); simplifying differently"
                ));
                face_budget = (face_budget as f64 * 0.85) as usize;
                continue;
            }
            Err(e) => return Err(e),
        };
        t0 = mesh.tets.len();
        keep(
            TetgenResult {
                mesh,
                switches: switches.to_tetgen_string(),
                runs,
                faces_meshed: current.triangles.len(),
                surface: current.clone(),
            },
            &mut best,
        );
        if t0 as f64 <= n * (1.0 + GOOD_ENOUGH)
            || current.triangles.len() <= 4
            || runs >= MAX_RUNS / 2
        {
            break;
        }
        // The surface alone gives too many tets: fewer faces, in proportion.
        face_budget = ((current.triangles.len() as f64 * 0.9 * n / t0 as f64) as usize).max(4);
    }
    // 2. Volume bounds. The count added by the bound, T - T0, follows a power of the bound
    //    (about 1 / a); the exponent is fitted on the last two runs (log-log secant).
    if off(t0) > GOOD_ENOUGH && (t0 as f64) < n {
        let need = n - t0 as f64;
        let mut a = 0.8 * volume / need;
        let mut history: Vec<(f64, f64)> = Vec::new(); // (ln a, ln(T - T0))
        while runs < MAX_RUNS {
            let switches = Switches {
                max_volume: Some(a),
                ..base_switches(options)
            };
            runs += 1;
            let mesh = run(&current, &switches)?;
            let t = mesh.tets.len();
            progress(&format!(
                "TetGen run {runs}: -{} -> {t} tets",
                switches.to_tetgen_string()
            ));
            keep(
                TetgenResult {
                    mesh,
                    switches: switches.to_tetgen_string(),
                    runs,
                    faces_meshed: current.triangles.len(),
                    surface: current.clone(),
                },
                &mut best,
            );
            if off(t) <= GOOD_ENOUGH {
                break;
            }
            if t <= t0 {
                if options.preserve_surface && !user_asked_y {
                    // With -Y TetGen may find no admissible point at all (e.g. the 12-face
                    // cube, whose tets all share one circumsphere): let it refine the surface.
                    progress("the volume bound added no tets with -Y; meshing without -Y");
                    options = &without_y;
                } else {
                    a /= 4.0;
                }
                continue;
            }
            history.push((a.ln(), ((t - t0) as f64).ln()));
            let slope = match history.as_slice() {
                [.., (a1, t1), (a2, t2)] if (a2 - a1).abs() > 1e-9 => {
                    ((t2 - t1) / (a2 - a1)).clamp(-3.0, -0.3)
                }
                _ => -1.0,
            };
            let (la, lt) = history[history.len() - 1];
            a = (la + (need.ln() - lt) / slope).exp();
        }
    }
    let mut result = best.ok_or_else(|| Error::Meshing("TetGen was not run".into()))?;
    result.runs = runs;
    Ok(result)
}
