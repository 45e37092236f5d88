//! The parameters' validation: the combinations refused, with the key they name.

use super::*;

#[test]
fn split_contact_refuses_warm_start_and_chebyshev() {
    let split = SimParams {
        contact: ContactMode::Split,
        ..SimParams::default()
    };
    split.validate().expect("split contact with the defaults");
    let warm = SimParams {
        springs: SpringKind::Implicit,
        warm_start: true,
        ..split.clone()
    };
    let chebyshev = SimParams {
        solver: Solver::Chebyshev,
        ..split
    };
    for (params, says) in [(warm, "warm_start"), (chebyshev, "chebyshev")] {
        let message = params.validate().unwrap_err().to_string();
        assert!(
            message.contains("contact") && message.contains(says),
            "{message}"
        );
    }
}

#[test]
fn anderson_needs_iterations_a_small_memory_and_no_chebyshev() {
    let on = SimParams {
        anderson: 5,
        ..SimParams::default()
    };
    on.validate().expect("anderson with the defaults");
    let cases = [
        (
            SimParams {
                anderson: ANDERSON_MAX_MEMORY + 1,
                ..on.clone()
            },
            "at most 8",
        ),
        (
            SimParams {
                method: Method::Mss,
                ..on.clone()
            },
            "no",
        ),
        (
            SimParams {
                solver: Solver::Chebyshev,
                ..on.clone()
            },
            "chebyshev",
        ),
    ];
    for (params, says) in cases {
        let message = params.validate().unwrap_err().to_string();
        assert!(
            message.contains("anderson") && message.contains(says),
            "{message}"
        );
    }
}

#[test]
fn inversion_sweeps_need_the_volume_method_and_a_floor_in_range() {
    let on = SimParams {
        inversion_sweeps: 4,
        ..SimParams::default()
    };
    on.validate().expect("inversion sweeps with the defaults");
    let cases = [
        (
            SimParams {
                inversion_sweeps: MAX_INVERSION_SWEEPS + 1,
                ..on.clone()
            },
            "inversion_sweeps",
            "at most 64",
        ),
        (
            SimParams {
                method: Method::Distance,
                ..on.clone()
            },
            "inversion_sweeps",
            "method volume",
        ),
        (
            SimParams {
                inversion_floor: 0.0,
                ..on.clone()
            },
            "inversion_floor",
            "(0, 1]",
        ),
        (
            SimParams {
                inversion_floor: 1.5,
                ..on.clone()
            },
            "inversion_floor",
            "(0, 1]",
        ),
    ];
    for (params, key, says) in cases {
        let message = params.validate().unwrap_err().to_string();
        assert!(message.contains(key) && message.contains(says), "{message}");
    }
}

#[test]
fn blocks_need_gauss_seidel_and_constraints() {
    let on = SimParams {
        block_size: 256,
        ..SimParams::default()
    };
    on.validate().expect("blocks with the defaults");
    assert!(on.solves_in_blocks());
    let thread_blocks = SimParams {
        block_size: MAX_WORKGROUP_BLOCK * 40,
        ..on.clone()
    };
    thread_blocks
        .validate()
        .expect("thread blocks (cpu backends)");
    let swept = SimParams {
        block_sweeps: MAX_BLOCK_SWEEPS,
        ..on.clone()
    };
    swept.validate().expect("blocks swept 8 times");
    for (params, says) in [
        (
            SimParams {
                block_sweeps: 0,
                ..on.clone()
            },
            "1 to 8",
        ),
        (
            SimParams {
                block_sweeps: 2,
                ..SimParams::default()
            },
            "set block_size",
        ),
        (
            SimParams {
                spring_block_sweeps: 9,
                ..on.clone()
            },
            "0 to 8",
        ),
        (
            SimParams {
                spring_block_sweeps: 2,
                springs: SpringKind::Implicit,
                ..SimParams::default()
            },
            "set block_size",
        ),
        (
            SimParams {
                spring_block_sweeps: 1,
                springs: SpringKind::Explicit,
                ..on.clone()
            },
            "springs = explicit",
        ),
    ] {
        let message = params.validate().unwrap_err().to_string();
        assert!(
            message.contains("block_sweeps") && message.contains(says),
            "{message}"
        );
    }
    // The springs' blocks take their own sweeps when given, the others' otherwise.
    let springs = SimParams {
        block_sweeps: 3,
        spring_block_sweeps: 1,
        springs: SpringKind::Implicit,
        ..on.clone()
    };
    springs
        .validate()
        .expect("volumes swept 3 times, springs once");
    assert_eq!((springs.spring_sweeps(), springs.block_sweeps), (1, 3));
    let same = SimParams {
        spring_block_sweeps: 0,
        ..springs.clone()
    };
    assert_eq!(same.spring_sweeps(), 3, "0: as block_sweeps");
    let cases = [
        (
            SimParams {
                block_size: MAX_BLOCK_SIZE + 1,
                ..on.clone()
            },
            "at most 16777216",
        ),
        (
            SimParams {
                solver: Solver::Chebyshev,
                ..on.clone()
            },
            "solver chebyshev",
        ),
        (
            SimParams {
                method: Method::Mss,
                ..on.clone()
            },
            "method mss",
        ),
    ];
    for (params, says) in cases {
        let message = params.validate().unwrap_err().to_string();
        assert!(
            message.contains("block_size") && message.contains(says),
            "{message}"
        );
    }
}

#[test]
fn minres_needs_constraints_and_at_most_its_limit() {
    let on = SimParams {
        minres: 40,
        ..SimParams::default()
    };
    on.validate().expect("minres with the defaults");
    let cases = [
        (
            SimParams {
                minres: MINRES_MAX_ITERATIONS + 1,
                ..on.clone()
            },
            "at most 200",
        ),
        (
            SimParams {
                method: Method::Mss,
                ..on.clone()
            },
            "explicit springs has none",
        ),
    ];
    for (params, says) in cases {
        let message = params.validate().unwrap_err().to_string();
        assert!(
            message.contains("minres") && message.contains(says),
            "{message}"
        );
    }
}
