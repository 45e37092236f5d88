//! Chebyshev never loses control (issue 22, item 2): with too few iterations for its `rho`
//! the extrapolation used to leave some constraint modes reversed by more than a third of
//! their violation at the end of a step, and such a mode grows from step to step (in free
//! fall, before any contact). At 5 iterations x 2 substeps (rho 0.95, global constraint on,
//! the bundled sphere's seed drop, 300 frames) the average local volume error was 5.1 %
//! (`cpu-ref`) and 12.3 % (`cpu`), against 0.27 % at 10 iterations x 1 substep. The weights
//! now use at most `chebyshev_rho_limit` of the iteration count (0.934 at 5 iterations):
//! 0.22 % on every backend. The run record and `tetrasim run`'s header say when `rho` was
//! lowered.

mod gpu_support;

use std::process::Command;

use gpu_support::{bundled_sphere, for_each_backend};
use tetrasim::metrics::{local_error_pct, RecordFacts, RunRecord};
use tetrasim::params::{chebyshev_rho_limit, Method, Solver};
use tetrasim::problem::Problem;
use tetrasim::{Model, ModelBuilder, SimParams};

const FRAMES: u32 = 300;

/// Chebyshev with the global constraint, `iterations` x `substeps` in frames of 1 ms.
fn chebyshev(iterations: u32, substeps: u32) -> SimParams {
    SimParams {
        method: Method::Volume,
        solver: Solver::Chebyshev,
        global_volume: Some(true),
        iterations,
        substeps,
        dt: 1e-3 / f64::from(substeps),
        ..SimParams::default()
    }
}

/// Per backend: the average and the largest local volume error over the run [%].
fn local_errors(model: &Model, params: &SimParams) -> Vec<(String, f64, f64)> {
    let rest = model.total_rest_volume();
    let mut out = Vec::new();
    for_each_backend(model, params, |name, backend| {
        let (mut sum, mut max) = (0.0, 0.0f64);
        for _ in 0..FRAMES {
            backend.step_frame().unwrap();
            let pct = local_error_pct(backend.volume().unwrap(), rest);
            sum += pct;
            max = max.max(pct);
        }
        out.push((name.to_string(), sum / f64::from(FRAMES), max));
    });
    out
}

#[test]
fn five_iterations_in_two_substeps_stay_as_accurate_as_ten_in_one() {
    let model = ModelBuilder::new(&bundled_sphere()).build().unwrap();
    let few = local_errors(&model, &chebyshev(5, 2));
    let many = local_errors(&model, &chebyshev(10, 1));
    for ((name, avg, max), (_, avg10, max10)) in few.iter().zip(&many) {
        println!(
            "{name}: chebyshev+global 5 it x 2 substeps: local error {avg:.3} % (max \
             {max:.3}); 10 it x 1: {avg10:.3} % (max {max10:.3})"
        );
        // Measured: 0.219 % (max 0.589) against 0.266 % (max 0.754) on cpu-ref and cpu;
        // without the limit 5.1 % (cpu-ref) and 12.3 % (cpu), max 18 to 20 %.
        assert!(avg <= &(1.5 * avg10), "{name}: {avg} % against {avg10} %");
        assert!(
            max <= &(1.5 * max10),
            "{name}: max {max} % against {max10} %"
        );
    }
}

#[test]
fn the_record_says_when_rho_was_lowered() {
    let model = ModelBuilder::new(&bundled_sphere()).build().unwrap();
    let facts = |params: &SimParams| RecordFacts::of(&Problem::new(&model, params).unwrap());
    let lowered = facts(&chebyshev(5, 2)).chebyshev_rho.unwrap();
    assert_eq!(lowered, chebyshev_rho_limit(5));
    assert!((lowered - 0.9337).abs() < 1e-4, "{lowered}");
    // Enough iterations for the default rho, or another solver: nothing to say.
    assert_eq!(facts(&chebyshev(10, 1)).chebyshev_rho, None);
    let gauss_seidel = SimParams {
        solver: Solver::GaussSeidel,
        ..chebyshev(5, 2)
    };
    assert_eq!(facts(&gauss_seidel).chebyshev_rho, None);
}

#[test]
fn tetrasim_run_reports_the_lowered_rho() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("run.json");
    let sphere = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere");
    let output = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args([
            "run",
            "--method",
            "volume",
            "--backend",
            "cpu-ref",
            "--frames",
            "2",
        ])
        .args(["--solver", "chebyshev", "--iterations", "5", "--quiet"])
        .arg("--mesh")
        .arg(&sphere)
        .arg("--json")
        .arg(&json)
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr),
    );
    assert!(output.status.success(), "{stderr}");
    let text = format!("{stdout}{stderr}");
    assert!(
        text.contains("chebyshev (rho 0.95, lowered to 0.9337 for 5 iterations)"),
        "{text}"
    );
    let records: Vec<RunRecord> =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(
        records[0].params.rho, 0.95,
        "the record keeps the asked rho"
    );
    assert_eq!(
        records[0].derived.chebyshev_rho,
        Some(chebyshev_rho_limit(5))
    );
}
