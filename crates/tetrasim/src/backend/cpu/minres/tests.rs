//! The solve's unit tests: it converges, leaves held rows to the sweeps, and gives the
//! same bits on any team.

use glam::DVec3;

use super::*;

/// A chain of `n` nodes in 3D with a distance-like row per neighbour pair and per
/// second neighbour, hard and compliant, with residuals, and a wide row over all.
fn chain(n: usize) -> (StepRows, Vec<f64>) {
    let mut rows = StepRows::new();
    for i in 0..n - 1 {
        for step in [1, 2] {
            if i + step < n {
                let g = DVec3::new(1.0 + 0.1 * i as f64, 0.3 * step as f64, -0.2);
                let soft = if i % 3 == 0 { 0.05 } else { 0.0 };
                let nodes = [i as u32, (i + step) as u32];
                rows.push(&nodes, &[g, -g], soft, (i as f64 * 0.7).sin());
            }
        }
    }
    let all: Vec<u32> = (0..n as u32).collect();
    let grads: Vec<DVec3> = (0..n)
        .map(|i| DVec3::new(0.0, 0.01 * i as f64, 0.02))
        .collect();
    rows.push(&all, &grads, 0.0, 0.3);
    let inv_mass = (0..n).map(|i| 1.0 / (1.0 + (i % 4) as f64)).collect();
    (rows, inv_mass)
}

/// The residual's norm in the preconditioner's metric, which MINRES minimises.
fn residual_after(rows: &StepRows, mobility: &[Mobility], x: &[f64]) -> f64 {
    let mut inverse = vec![0.0; rows.len()];
    rows.preconditioner(0..rows.len(), mobility, &mut inverse);
    let mut u = vec![DVec3::ZERO; mobility.len()];
    rows.each(|j, i, g| u[i as usize] += g * x[j as usize]);
    let u: Vec<DVec3> = (u.iter().zip(mobility))
        .map(|(&u, m)| m.rounded::<DVec3>().apply(u))
        .collect();
    let mut q: Vec<f64> = (x.iter().zip(rows.softness()))
        .map(|(x, s)| x * s)
        .collect();
    rows.gather(0..rows.len(), &u, &mut q);
    let terms = rows.residual().iter().zip(&q).zip(&inverse);
    terms
        .map(|((r, q), inverse)| (r - q).powi(2) * inverse)
        .sum::<f64>()
        .sqrt()
}

fn solve(team: &Team, rows: &StepRows, mobility: &[Mobility], iterations: u32) -> Vec<f64> {
    let mut minres = Minres::default();
    minres.solve(team, rows, mobility, iterations);
    minres.increments().to_vec()
}

#[test]
fn minres_solves_the_step_system_and_never_lets_its_residual_grow() {
    let (rows, inv_mass) = chain(40);
    let mobility: Vec<Mobility> = inv_mass.iter().map(|&w| Mobility::free(w)).collect();
    let start = residual_after(&rows, &mobility, &vec![0.0; rows.len()]);
    let mut last = start;
    let team = Team::default();
    for iterations in [1, 2, 4, 8, 16, 32] {
        let x = solve(&team, &rows, &mobility, iterations);
        let r = residual_after(&rows, &mobility, &x);
        assert!(
            r <= last * (1.0 + 1e-9),
            "{iterations} iterations: {r} after {last}"
        );
        last = r;
    }
    let x = solve(&team, &rows, &mobility, 200);
    let r = residual_after(&rows, &mobility, &x);
    assert!(r < 1e-8 * start, "converged residual {r} of {start}");
}

#[test]
fn rows_held_by_the_floor_are_left_to_the_sweeps() {
    let (rows, inv_mass) = chain(6);
    let mut mobility: Vec<Mobility> = inv_mass.iter().map(|&w| Mobility::free(w)).collect();
    // Nodes 0 and 1 held entirely: the row between them has no mobility left.
    mobility[0].inv_mass = 0.0;
    mobility[1].inv_mass = 0.0;
    let x = solve(&Team::default(), &rows, &mobility, 50);
    assert_eq!(x[0], 0.0);
    assert!(x[1..].iter().any(|&d| d != 0.0));
}

/// Teams of 1 to 4 give the same bits, over more chunks than members, with a memory
/// reused from a smaller solve (another shape) and from the same rows.
#[test]
fn teams_of_any_size_give_the_same_bits() {
    let (rows, inv_mass) = chain(700);
    assert!(rows.len() > 4 * CHUNK);
    let mobility: Vec<Mobility> = inv_mass.iter().map(|&w| Mobility::free(w)).collect();
    let one = solve(&Team::default(), &rows, &mobility, 30);
    assert!(one.iter().any(|&d| d != 0.0));
    for size in 2..=4 {
        let mut minres = Minres::default();
        let (small, _) = chain(30);
        minres.solve(&Team::with_size(size), &small, &mobility, 5);
        minres.solve(&Team::with_size(size), &rows, &mobility, 30);
        assert!(minres.increments() == one, "a team of {size} differs");
        // Again, the transpose's shape kept from the last solve.
        minres.solve(&Team::with_size(size), &rows, &mobility, 30);
        assert!(
            minres.increments() == one,
            "a team of {size} differs the second time"
        );
    }
}
