//! The team's result does not depend on its size: states after a drop onto the floor are
//! bit-identical for teams of 1, 2, 3 and 4 threads (every solver, MINRES, the finite
//! elements, implicit and explicit springs), and the 4-thread run follows the `cpu-ref`
//! backend within the tolerance of `tests/cpu_matches_reference.rs`. The teams are built
//! with their size given, past the cap on small meshes
//! ([`crate::backend::cpu::team::Team::for_work`]). So is a backend that changes teams from
//! frame to frame while it times them ([`crate::backend::cpu::team_choice::TeamChoice`]).

use super::*;
use crate::backend::cpu::ReferenceBackend;
use crate::model::ModelBuilder;
use crate::params::Placement;

/// Frames of each run: the drop from 1 cm lands after about 45.
const FRAMES: u32 = 80;

/// Of `tests/cpu_matches_reference.rs`: every node within this many bounding-box diagonals.
const TOLERANCE: f64 = 1e-5;

/// A box of 9 x 7 x 8 cells (720 nodes), 1 m across, 1 cm above the floor, its nodes
/// moving at up to 5 cm/s in a fixed pattern so that the drop is not symmetric.
fn model() -> Model {
    let mesh = crate::mesh::grid::box_tets(glam::DVec3::ZERO, 0.1, [9, 7, 8]);
    let mut model = ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.01),
        })
        .build()
        .expect("a model of the box");
    for (i, v) in model.velocities.iter_mut().enumerate() {
        let pattern = |k: usize| ((i * k) % 11) as f64 / 10.0 - 0.5;
        *v = glam::DVec3::new(pattern(3), pattern(5), pattern(7)) * 0.1;
    }
    model
}

/// The state after [`FRAMES`] frames on a team of `threads`.
fn run(problem: &Problem, threads: usize) -> State {
    run_choosing(problem, &[threads])
}

/// The state after [`FRAMES`] frames on teams of the candidate `sizes`, each in turn while
/// the backend times them ([`TeamChoice`](crate::backend::cpu::team_choice::TeamChoice)).
fn run_choosing(problem: &Problem, sizes: &[usize]) -> State {
    let mut backend = ParallelBackend::from_problem(problem).with_team_sizes(sizes);
    for frame in 0..FRAMES {
        backend
            .step_frame()
            .unwrap_or_else(|e| panic!("frame {frame} on teams of {sizes:?}: {e}"));
    }
    backend.state().expect("the state")
}

/// A state as bits.
fn bits(state: &State) -> Vec<[u64; 3]> {
    (state.positions.iter().chain(&state.velocities))
        .map(|p| p.to_array().map(f64::to_bits))
        .collect()
}

#[test]
fn teams_of_any_size_give_the_same_bits() {
    let model = model();
    let params = SimParams::default();
    let cases = [
        ("gauss-seidel + global (default)", params.clone()),
        (
            "jacobi",
            SimParams {
                solver: Solver::Jacobi,
                ..params.clone()
            },
        ),
        (
            "chebyshev",
            SimParams {
                solver: Solver::Chebyshev,
                ..params.clone()
            },
        ),
        (
            "distance, 3 groups",
            SimParams {
                method: Method::Distance,
                groups: 3,
                ..params.clone()
            },
        ),
        (
            "anderson 5",
            SimParams {
                anderson: 5,
                ..params.clone()
            },
        ),
        (
            "block gauss-seidel, blocks of 96",
            SimParams {
                block_size: 96,
                ..params.clone()
            },
        ),
        (
            "2 sweeps, then MINRES 20",
            SimParams {
                iterations: 2,
                minres: 20,
                ..params.clone()
            },
        ),
        (
            "implicit springs, warm-started",
            SimParams {
                springs: SpringKind::Implicit,
                warm_start: true,
                ..params.clone()
            },
        ),
    ];
    for (name, params) in cases {
        same_bits_on_any_team(name, &Problem::new(&model, &params).expect("a problem"));
    }
}

/// Asserts that `problem` lands on the floor and ends with the same bits on teams of 1 to
/// 4 threads, and on teams of 4, 2 and 1 in turn.
fn same_bits_on_any_team(name: &str, problem: &Problem) {
    let one = run(problem, 1);
    assert!(
        one.positions.iter().any(|p| p.y.abs() < 1e-6),
        "{name}: never touched the floor"
    );
    for threads in 2..=4 {
        assert!(
            bits(&run(problem, threads)) == bits(&one),
            "{name}: {threads} threads differ from 1"
        );
    }
    assert!(
        bits(&run_choosing(problem, &[4, 2, 1])) == bits(&one),
        "{name}: teams of 4, 2 and 1 in turn differ from 1"
    );
}

/// The finite elements too (their conjugate gradients' sums, the coarse level, and the
/// rigid-part correction sized on the floor: the box lands after about 45 frames).
#[test]
fn teams_of_any_size_give_the_same_bits_on_the_finite_elements() {
    let params = SimParams {
        method: Method::NeoHookean,
        youngs_modulus: Some(1e6),
        poisson_ratio: Some(0.3),
        mass: crate::params::MassMode::Density { density: 1000.0 },
        ..SimParams::default()
    };
    // The box of `model`, its masses from the material, moving as there.
    let mesh = crate::mesh::grid::box_tets(glam::DVec3::ZERO, 0.1, [9, 7, 8]);
    let placement = Placement {
        fit_size: Some(1.0),
        drop_height: Some(0.01),
    };
    let model = Model {
        velocities: model().velocities,
        ..(ModelBuilder::new(&mesh).placement(placement))
            .material(&params)
            .build()
            .expect("a model of the box")
    };
    let problem = Problem::new(&model, &params).expect("a problem");
    same_bits_on_any_team("neo-hookean", &problem);
}

#[test]
fn a_team_of_four_follows_cpu_ref() {
    follows_cpu_ref(SimParams::default());
}

/// Anderson acceleration on the team follows `cpu-ref`'s, and changes the result well
/// beyond the tolerance (so a team that skipped it would fail).
#[test]
fn a_team_of_four_follows_cpu_ref_with_anderson() {
    let on = follows_cpu_ref(SimParams {
        anderson: 5,
        ..SimParams::default()
    });
    let off = follows_cpu_ref(SimParams::default());
    let d = (on.positions.iter().zip(&off.positions))
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f64::max);
    let diag = model().bounds_diagonal();
    assert!(
        d > 20.0 * TOLERANCE * diag,
        "anderson moved nodes only {d:e} m"
    );
}

/// The 4-thread run under `params` against `cpu-ref`'s; `cpu-ref`'s state.
fn follows_cpu_ref(params: SimParams) -> State {
    let model = model();
    let problem = Problem::new(&model, &params).expect("a problem");
    let fast = run(&problem, 4);
    let mut reference = ReferenceBackend::new(&model, &params).expect("cpu-ref");
    for _ in 0..FRAMES {
        reference.step_frame().expect("a cpu-ref frame");
    }
    let reference = reference.state().expect("the cpu-ref state");
    let diag = model.bounds_diagonal();
    let d = (reference.positions.iter().zip(&fast.positions))
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f64::max);
    assert!(d < TOLERANCE * diag, "{d:e} m, diagonal {diag} m");
    reference
}
