//! TetGen 1.5 in-process: a closed triangle surface in, a tetrahedral mesh out, and every
//! failure back as a Rust error with TetGen's reason in words. The process never aborts
//! because of a bad input.
//!
//! # Why this route
//! - Debian's `libtet1.5-dev` is built without `TETLIBRARY`: TetGen's errors call `exit()`,
//!   which would end the calling program (and a minimal call aborted on an assertion).
//! - The `tritet` crate compiles the right sources with `cc`, but exposes only the quality and
//!   max-volume switches, and on an invalid surface prints TetGen's message to stdout and
//!   returns success with zero tets.
//!
//! So this crate compiles TetGen 1.5's sources itself (`build.rs`, with `cc`): the copy in
//! `tetgen/` (taken unchanged from the `tritet` 3.4.0 crate's `c_code`, AGPL-3.0; see
//! `tetgen/README.md`; `TETGEN_SRC_DIR` overrides the location). Its `tetgen.h` defines `TETLIBRARY`, so
//! TetGen throws an `int` on error; a small C++ shim (`shim/shim.cpp`) catches it (and any
//! other exception), turns TetGen's assertions into the same "internal error" exception
//! (`shim/tetgen_unit.cpp`), passes any switch string, and captures what TetGen prints so the
//! caller's stdout stays clean and the message can be put into the error.
//!
//! TetGen keeps global state (exact-arithmetic constants), so calls are serialized by a lock.
//!
//! TetGen is licensed under the AGPL (or a commercial licence); so is this crate.

use std::ffi::{c_char, c_int, CStr, CString};
use std::fmt;
use std::sync::Mutex;

#[repr(C)]
struct ShimOutput {
    code: c_int,
    status: c_int,
    num_points: c_int,
    points: *mut f64,
    num_tets: c_int,
    tets: *mut c_int,
    num_faces: c_int,
    faces: *mut c_int,
    message: *mut c_char,
}

extern "C" {
    fn tetgen_shim_tetrahedralize(
        switches: *const c_char,
        points: *const f64,
        num_points: c_int,
        triangles: *const c_int,
        num_triangles: c_int,
        out: *mut ShimOutput,
    ) -> c_int;
    fn tetgen_shim_free(out: *mut ShimOutput);
}

/// TetGen's switches beyond the fixed `pQ` (PLC input, quiet).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Switches {
    /// Radius-edge ratio bound (`-q`); TetGen's useful range is about 1.1..=2.0.
    pub quality: Option<f64>,
    /// Maximum tetrahedron volume (`-a`), in the input's length unit cubed.
    pub max_volume: Option<f64>,
    /// Keep the boundary exactly as given: no Steiner points on the surface (`-Y`).
    pub preserve_surface: bool,
    /// Further switches appended verbatim (e.g. `"T1e-10"`); see TetGen's manual.
    pub extra: String,
}

impl Switches {
    /// The full switch string passed to TetGen.
    pub fn to_tetgen_string(&self) -> String {
        let mut s = String::from("pQ");
        if let Some(q) = self.quality {
            s.push_str(&format!("q{q}"));
        }
        if let Some(a) = self.max_volume {
            s.push_str(&format!("a{a:e}"));
        }
        if self.preserve_surface {
            s.push('Y');
        }
        s.push_str(&self.extra);
        s
    }
}

/// A tetrahedral mesh as TetGen produced it (0-based indices).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TetGenOutput {
    /// Node coordinates: the input points first, then Steiner points.
    pub points: Vec<[f64; 3]>,
    /// Tetrahedra; TetGen orients them positively: `((b - a) x (c - a)) . (d - a) > 0`.
    pub tets: Vec<[u32; 4]>,
    /// Boundary faces (TetGen's `.face` output).
    pub faces: Vec<[u32; 3]>,
}

/// Why TetGen failed.
#[derive(Debug, Clone, PartialEq)]
pub enum TetGenError {
    /// The input was rejected before TetGen ran (`message` says which element).
    InvalidInput(String),
    /// TetGen threw one of its error codes; `printed` is what it printed about it.
    Code {
        /// TetGen's error code.
        code: i32,
        /// What TetGen printed.
        printed: String,
    },
    /// TetGen ran but returned a non-zero status (its setup failed).
    Status {
        /// The status TetGen returned.
        status: i32,
        /// What TetGen printed.
        printed: String,
    },
    /// TetGen ran without error but produced no tetrahedra.
    NoTetrahedra {
        /// What TetGen printed.
        printed: String,
    },
}

/// TetGen's error code in words.
pub fn code_reason(code: i32) -> &'static str {
    match code {
        1 => "out of memory",
        2 => "internal error (a TetGen bug or a failed internal check)",
        3 => "the surface has self-intersecting facets",
        4 => "the input has a very small feature size (points or facets almost touching)",
        5 => "two input facets are very close to each other",
        10 => "input error (the switches or the surface are invalid)",
        _ => "unknown error",
    }
}

fn with_printed(f: &mut fmt::Formatter<'_>, printed: &str) -> fmt::Result {
    let printed = printed.trim();
    if printed.is_empty() {
        Ok(())
    } else {
        let lines: Vec<&str> = printed
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .take(6)
            .collect();
        write!(f, " (TetGen: {})", lines.join(" / "))
    }
}

impl fmt::Display for TetGenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TetGenError::InvalidInput(m) => write!(f, "invalid input for TetGen: {m}"),
            TetGenError::Code { code, printed } => {
                write!(f, "TetGen error {code}: {}", code_reason(*code))?;
                with_printed(f, printed)
            }
            TetGenError::Status { status, printed } => {
                write!(f, "TetGen returned status {status} (exact arithmetic setup failed; is the input degenerate?)")?;
                with_printed(f, printed)
            }
            TetGenError::NoTetrahedra { printed } => {
                write!(
                    f,
                    "TetGen produced no tetrahedra: the surface is probably not closed"
                )?;
                with_printed(f, printed)
            }
        }
    }
}

impl std::error::Error for TetGenError {}

static LOCK: Mutex<()> = Mutex::new(());

fn check_input(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    switches: &Switches,
) -> Result<(), TetGenError> {
    let invalid = |m: String| Err(TetGenError::InvalidInput(m));
    if let Some(q) = switches.quality {
        // Below 1 TetGen's refinement never terminates; its manual suggests >= 1.1 or so.
        if !(q.is_finite() && q >= 1.0) {
            return invalid(format!(
                "quality (radius-edge ratio) {q} must be a number >= 1.0"
            ));
        }
    }
    if let Some(a) = switches.max_volume {
        if !(a.is_finite() && a > 0.0) {
            return invalid(format!("max volume {a} must be a positive number"));
        }
    }
    if points.len() < 4 {
        return invalid(format!(
            "{} points; a closed surface needs at least 4",
            points.len()
        ));
    }
    if triangles.len() < 4 {
        return invalid(format!(
            "{} triangles; a closed surface needs at least 4",
            triangles.len()
        ));
    }
    if points.len() > c_int::MAX as usize / 3 || triangles.len() > c_int::MAX as usize / 3 {
        return invalid(format!(
            "too many points ({}) or triangles ({})",
            points.len(),
            triangles.len()
        ));
    }
    if let Some((i, p)) = points
        .iter()
        .enumerate()
        .find(|(_, p)| p.iter().any(|c| !c.is_finite()))
    {
        return invalid(format!("point {i} has a non-finite coordinate {p:?}"));
    }
    for (i, t) in triangles.iter().enumerate() {
        if let Some(v) = t.iter().find(|&&v| v as usize >= points.len()) {
            return invalid(format!(
                "triangle {i} uses vertex {v}, but there are {} points",
                points.len()
            ));
        }
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            return invalid(format!("triangle {i} repeats a vertex: {t:?}"));
        }
    }
    Ok(())
}

/// Tetrahedralizes the closed triangle surface `(points, triangles)` with TetGen.
///
/// Errors: invalid input (checked here: counts, finite coordinates, index range, repeated
/// vertices), TetGen's thrown codes with their reason in words and TetGen's printed details,
/// and an empty result ("TetGen produced no tetrahedra").
pub fn tetrahedralize(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    switches: &Switches,
) -> Result<TetGenOutput, TetGenError> {
    check_input(points, triangles, switches)?;
    let switch_string = switches.to_tetgen_string();
    let c_switches = CString::new(switch_string.clone()).map_err(|_| {
        TetGenError::InvalidInput(format!("switches {switch_string:?} contain a NUL byte"))
    })?;
    let flat_points: Vec<f64> = points.iter().flatten().copied().collect();
    let flat_tris: Vec<c_int> = triangles.iter().flatten().map(|&v| v as c_int).collect();

    let _guard = LOCK.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    // Anything Rust buffered must reach stdout before the shim redirects it.
    let _ = std::io::Write::flush(&mut std::io::stdout());
    let mut out = ShimOutput {
        code: 0,
        status: 0,
        num_points: 0,
        points: std::ptr::null_mut(),
        num_tets: 0,
        tets: std::ptr::null_mut(),
        num_faces: 0,
        faces: std::ptr::null_mut(),
        message: std::ptr::null_mut(),
    };
    // SAFETY: the arrays outlive the call and have the lengths passed; `out` is released by
    // tetgen_shim_free below after its arrays were copied (lengths as reported by the shim).
    let result = unsafe {
        tetgen_shim_tetrahedralize(
            c_switches.as_ptr(),
            flat_points.as_ptr(),
            points.len() as c_int,
            flat_tris.as_ptr(),
            triangles.len() as c_int,
            &mut out,
        );
        let printed = if out.message.is_null() {
            String::new()
        } else {
            CStr::from_ptr(out.message).to_string_lossy().into_owned()
        };
        let copied = copy_output(&out);
        let (code, status) = (out.code, out.status);
        tetgen_shim_free(&mut out);
        (copied, printed, code, status)
    };
    let (output, printed, code, status) = result;
    if code != 0 {
        return Err(TetGenError::Code { code, printed });
    }
    if status != 0 {
        return Err(TetGenError::Status { status, printed });
    }
    if output.tets.is_empty() {
        return Err(TetGenError::NoTetrahedra { printed });
    }
    Ok(output)
}

/// Copies the shim's arrays into Rust vectors.
///
/// # Safety
/// `out`'s pointers must be null or hold the number of elements its counts say.
unsafe fn copy_output(out: &ShimOutput) -> TetGenOutput {
    /// # Safety
    /// `ptr` must be null or point to `len` initialised elements that outlive `'a`.
    unsafe fn slice<'a, T>(ptr: *const T, len: usize) -> &'a [T] {
        if ptr.is_null() || len == 0 {
            &[]
        } else {
            // SAFETY: non-null, and the caller promises `len` elements behind it.
            unsafe { std::slice::from_raw_parts(ptr, len) }
        }
    }
    let n = |c: c_int| c.max(0) as usize;
    // SAFETY: the caller promises `out.points` holds `out.num_points` x 3 values.
    let points = unsafe { slice(out.points, 3 * n(out.num_points)) }
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    // SAFETY: the caller promises `out.tets` holds `out.num_tets` x 4 values.
    let tets = unsafe { slice(out.tets, 4 * n(out.num_tets)) }
        .chunks_exact(4)
        .map(|c| [c[0] as u32, c[1] as u32, c[2] as u32, c[3] as u32])
        .collect();
    // SAFETY: the caller promises `out.faces` holds `out.num_faces` x 3 values.
    let faces = unsafe { slice(out.faces, 3 * n(out.num_faces)) }
        .chunks_exact(3)
        .map(|c| [c[0] as u32, c[1] as u32, c[2] as u32])
        .collect();
    TetGenOutput {
        points,
        tets,
        faces,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let points = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        // Outward-facing triangles of the unit cube (corner index x + 2y + 4z).
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let tris = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        (points, tris)
    }

    fn signed_volume(out: &TetGenOutput, t: [u32; 4]) -> f64 {
        let p = t.map(|i| out.points[i as usize]);
        let d = |a: [f64; 3], b: [f64; 3]| [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let (u, v, w) = (d(p[0], p[1]), d(p[0], p[2]), d(p[0], p[3]));
        (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))
            / 6.0
    }

    fn volume(out: &TetGenOutput) -> f64 {
        out.tets.iter().map(|t| signed_volume(out, *t).abs()).sum()
    }

    #[test]
    fn cube_meshes_with_volume_bound() {
        let (p, t) = cube();
        let out = tetrahedralize(
            &p,
            &t,
            &Switches {
                quality: Some(1.5),
                max_volume: Some(0.01),
                ..Default::default()
            },
        )
        .unwrap();
        assert!(out.tets.len() >= 100, "{} tets", out.tets.len());
        assert!((volume(&out) - 1.0).abs() < 1e-9);
        assert!(out.faces.len() >= 12);
        assert!(out
            .tets
            .iter()
            .flatten()
            .all(|&i| (i as usize) < out.points.len()));
    }

    #[test]
    fn open_surface_is_an_error() {
        let (p, mut t) = cube();
        t.truncate(10);
        let err = tetrahedralize(&p, &t, &Switches::default()).unwrap_err();
        assert!(
            matches!(
                err,
                TetGenError::NoTetrahedra { .. } | TetGenError::Code { .. }
            ),
            "{err}"
        );
    }

    #[test]
    fn self_intersection_is_reported_with_code_3() {
        let (mut p, mut t) = cube();
        // A second cube overlapping the first one: facets cross.
        let base = p.len() as u32;
        let (q, u) = cube();
        p.extend(q.iter().map(|c| [c[0] + 0.5, c[1] + 0.5, c[2] + 0.5]));
        t.extend(u.iter().map(|f| f.map(|v| v + base)));
        let err = tetrahedralize(&p, &t, &Switches::default()).unwrap_err();
        assert!(matches!(err, TetGenError::Code { code: 3, .. }), "{err}");
        assert!(err.to_string().contains("self-intersecting"), "{err}");
    }

    #[test]
    fn bad_input_is_rejected_before_tetgen() {
        let (mut p, t) = cube();
        p[3][1] = f64::NAN;
        let err = tetrahedralize(&p, &t, &Switches::default()).unwrap_err();
        assert!(err.to_string().contains("point 3"), "{err}");
        let (p, mut t) = cube();
        t[5][2] = 99;
        let err = tetrahedralize(&p, &t, &Switches::default()).unwrap_err();
        assert!(err.to_string().contains("triangle 5"), "{err}");
    }

    #[test]
    fn bad_switch_values_are_rejected() {
        let (p, t) = cube();
        let err = tetrahedralize(
            &p,
            &t,
            &Switches {
                quality: Some(0.5),
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(err.to_string().contains("quality"), "{err}");
        let err = tetrahedralize(
            &p,
            &t,
            &Switches {
                max_volume: Some(-1.0),
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(err.to_string().contains("max volume"), "{err}");
    }

    #[test]
    fn tets_are_positively_oriented() {
        let (p, t) = cube();
        let out = tetrahedralize(
            &p,
            &t,
            &Switches {
                quality: Some(1.4),
                max_volume: Some(0.05),
                ..Default::default()
            },
        )
        .unwrap();
        let positive = out
            .tets
            .iter()
            .filter(|t| signed_volume(&out, **t) > 0.0)
            .count();
        assert_eq!(positive, out.tets.len());
    }

    #[test]
    fn switch_string() {
        let s = Switches {
            quality: Some(1.4),
            max_volume: Some(0.00025),
            preserve_surface: true,
            extra: "T1e-9".into(),
        };
        assert_eq!(s.to_tetgen_string(), "pQq1.4a2.5e-4YT1e-9");
    }
}
