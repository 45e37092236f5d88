//! `tradeoff`'s unit tests: the sweep's points and the solver settings' syntax.

use super::*;
use tetrasim::params::Solver;

#[test]
fn default_sweep_has_the_grid_and_the_omega_points() {
    let points = SweepSpec::default().points();
    // mss: 3 substep counts; distance and volume: 5 solvers x 6 x 3 grid + 2 omegas each.
    assert_eq!(points.len(), 3 + 2 * (5 * 18 + 2));
    let volume: Vec<_> = points
        .iter()
        .filter(|p| p.method == Method::Volume)
        .collect();
    assert!(volume
        .iter()
        .any(|p| p.iterations == 50 && p.substeps == 4 && p.omega == 1.0));
    assert_eq!(volume.iter().filter(|p| p.omega != 1.0).count(), 2);
    let labels: Vec<String> = SolverSetting::DEFAULTS.iter().map(|s| s.label()).collect();
    assert_eq!(
        labels,
        [
            "jacobi",
            "jacobi+global",
            "gauss-seidel:8",
            "gauss-seidel:8+global",
            "gauss-seidel:8+global+anderson5"
        ]
    );
    for label in &labels {
        assert_eq!(&label.parse::<SolverSetting>().unwrap().label(), label);
    }
    assert_eq!(
        "gauss-seidel".parse::<SolverSetting>().unwrap(),
        SolverSetting::new(Solver::GaussSeidel, 8, false)
    );
    assert_eq!(
        "jacobi+anderson3".parse::<SolverSetting>().unwrap(),
        SolverSetting::new(Solver::Jacobi, 1, false).with_anderson(3)
    );
    let swept = SolverSetting::new(Solver::GaussSeidel, 16, true)
        .with_anderson(5)
        .with_inversion(8);
    assert_eq!(swept.label(), "gauss-seidel:16+global+anderson5+inversion8");
    assert_eq!(swept.label().parse::<SolverSetting>().unwrap(), swept);
    assert_eq!(swept.apply(&SimParams::default()).inversion_sweeps, 8);
    let solved = SolverSetting::new(Solver::GaussSeidel, 8, true).with_minres(40);
    assert_eq!(solved.label(), "gauss-seidel:8+global+minres40");
    assert_eq!(solved.label().parse::<SolverSetting>().unwrap(), solved);
    assert_eq!(solved.apply(&SimParams::default()).minres, 40);
    for bad in [
        "gauss-seidel+minres0",
        "jacobi+minres201",
        "gauss-seidel+minres",
    ] {
        let message = bad.parse::<SolverSetting>().unwrap_err().to_string();
        assert!(
            message.contains("+minresK needs K from 1 to 200"),
            "{bad}: {message}"
        );
    }
    assert_eq!(
        "gauss-seidel:8+global+inversion4"
            .parse::<SolverSetting>()
            .unwrap(),
        SolverSetting::DEFAULTS[3].with_inversion(4)
    );
    let blocked = "gauss-seidel:block512+global+anderson5"
        .parse::<SolverSetting>()
        .unwrap();
    assert_eq!(
        blocked,
        SolverSetting::DEFAULTS[4].with_blocks(512),
        "blocks of 512"
    );
    assert_eq!(blocked.label(), "gauss-seidel:block512+global+anderson5");
    assert_eq!(blocked.apply(&SimParams::default()).block_size, 512);
    let thread_blocks = "gauss-seidel:block43000".parse::<SolverSetting>().unwrap();
    assert_eq!(thread_blocks.apply(&SimParams::default()).block_size, 43000);
    let twice = "gauss-seidel:block1024x2+global"
        .parse::<SolverSetting>()
        .unwrap();
    assert_eq!(twice.label(), "gauss-seidel:block1024x2+global");
    let params = twice.apply(&SimParams::default());
    assert_eq!((params.block_size, params.block_sweeps), (1024, 2));
    // A setting with inversion sweeps is the volume method's alone.
    let with_floor = SweepSpec {
        methods: vec![Method::Distance, Method::Volume],
        solvers: vec![SolverSetting::DEFAULTS[3], swept],
        ..SweepSpec::default()
    };
    assert!(with_floor
        .points()
        .iter()
        .all(|p| p.solver.inversion_sweeps == 0 || p.method == Method::Volume));
    assert!(with_floor
        .points()
        .iter()
        .any(|p| p.solver.inversion_sweeps == 8));
    for bad in [
        "gs",
        "jacobi:4",
        "gauss-seidel:0",
        "gauss-seidel:x+global",
        "jacobi+anderson0",
        "jacobi+anderson9",
        "chebyshev+anderson5",
        "gauss-seidel+inversion0",
        "gauss-seidel+inversion65",
        "gauss-seidel:block0",
        "gauss-seidel:block16777217+global",
        "gauss-seidel:block1024x9",
        "gauss-seidel:block1024x",
        "jacobi:block64",
    ] {
        let err = bad.parse::<SolverSetting>().unwrap_err().to_string();
        assert!(err.contains(bad), "{err}");
    }
    assert!(points
        .iter()
        .filter(|p| p.method == Method::Mss)
        .all(|p| p.iterations == 1 && p.omega == 1.0));
    assert!(SweepSpec {
        substeps: vec![0],
        ..SweepSpec::default()
    }
    .validate()
    .is_err());
}
