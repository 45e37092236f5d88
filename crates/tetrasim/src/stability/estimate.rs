//! The explicit stability bound of the spring system under symplectic Euler, estimated from
//! stiffness, damping, masses and the spring graph (docs/STABILITY.md, "Stable-step estimate").
//!
//! Linearised at rest, the springs give `M a = -K x - C v` with `C = (kd / ks) K` (each
//! spring's damping acts along the same direction as its stiffness). Symplectic Euler on a
//! mode of `M^-1 K` with eigenvalue `lambda` is stable iff
//! `lambda dt^2 + 2 (kd / ks) lambda dt < 4`, so the largest stable step is
//!
//! ```text
//! dt_max = sqrt(beta^2 + 4 / lambda_max) - beta,   beta = kd / ks
//! ```
//!
//! (`2 / sqrt(lambda_max)` without damping). `lambda_max` is bounded from above by
//! Gershgorin's theorem on the symmetric `M^-1/2 K M^-1/2`: each spring's 3x3 block has norm
//! `ks`, so for a free node `i`
//!
//! ```text
//! lambda_max <= max_i  sum_{springs (i, j)} ks (1 / m_i + [j free] / sqrt(m_i m_j))
//! ```
//!
//! The bound is an upper bound on `lambda_max`, so `dt_max` errs on the safe side for the
//! springs alone; the constraints of `distance` and `volume` change it (the measured maps
//! of `tetrasim stability` show by how much).

use crate::model::Model;
use crate::params::{SimParams, SpringKind};

/// The stable-step estimate of a model with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepEstimate {
    /// Gershgorin bound on the largest eigenvalue of `M^-1 K` [1/s^2].
    pub lambda_max: f64,
    /// Largest stable time step [s] (`f64::INFINITY` when no free node has a spring or
    /// `ks = 0`).
    pub dt_max: f64,
    /// Node whose Gershgorin row is the largest (`None` when there is none).
    pub node: Option<u32>,
}

impl StepEstimate {
    /// Whether `dt` [s] exceeds the estimate.
    pub fn exceeded_by(&self, dt: f64) -> bool {
        dt > self.dt_max
    }

    /// One line for a warning or a divergence report.
    pub fn describe(&self, params: &SimParams) -> String {
        let springs = match params.youngs_modulus {
            Some(e) => format!("springs from E {e:e} Pa"),
            None => format!("ks {} N/m, kd {} N s/m", params.ks, params.kd),
        };
        if !params.has_springs() {
            format!(
                "method {} takes an implicit (backward Euler) step, which no stiffness limits; a \
                 diverging run is a solve that did not converge: more `iterations`, or a \
                 smaller `dt`",
                params.method
            )
        } else if params.springs == SpringKind::Implicit {
            format!("implicit springs ({springs}) do not limit the step")
        } else if self.dt_max.is_finite() {
            format!(
                "stable dt estimate {:.3e} s for {springs} (dt is {:.3e} s, {:.2}x the estimate)",
                self.dt_max,
                params.dt,
                params.dt / self.dt_max
            )
        } else {
            "no spring stiffness limits the step".to_string()
        }
    }
}

/// Gershgorin bound on `lambda_max(M^-1 K)` for the spring stiffnesses `ks` [N/m] (one per
/// spring, or one for all) over the model's free nodes, and the row that attains it.
pub fn gershgorin_lambda(model: &Model, ks: &[f64]) -> (f64, Option<u32>) {
    let mut rows = vec![0.0f64; model.node_count()];
    for (n, s) in model.springs.iter().enumerate() {
        let k = ks[n.min(ks.len() - 1)];
        let [i, j] = s.map(|a| a as usize);
        let (wi, wj) = (model.inv_mass[i], model.inv_mass[j]);
        let cross = (wi * wj).sqrt();
        rows[i] += k * (wi + cross);
        rows[j] += k * (wj + cross);
    }
    let mut best = (0.0, None);
    for (i, &r) in rows.iter().enumerate() {
        if model.inv_mass[i] > 0.0 && r > best.0 {
            best = (r, Some(i as u32));
        }
    }
    best
}

/// Largest stable step [s] for a mode of eigenvalue `lambda` [1/s^2] with damping ratio
/// `beta = kd / ks` [s]: `sqrt(beta^2 + 4 / lambda) - beta`.
pub fn dt_for(lambda: f64, beta: f64) -> f64 {
    if lambda <= 0.0 || !lambda.is_finite() {
        return f64::INFINITY;
    }
    // 4 / (sqrt(beta^2 + 4/lambda) + beta) is the same value without cancellation.
    let root = (beta * beta + 4.0 / lambda).sqrt();
    (4.0 / lambda) / (root + beta)
}

/// The stable-step estimate of `model` under `params` (each spring's stiffness and damping
/// from [`Model::element_material`]; masses and pins from the model). Implicit springs and
/// the finite elements (no springs; an implicit step) have no explicit bound: `dt_max` is
/// infinite.
pub fn estimate(model: &Model, params: &SimParams) -> StepEstimate {
    if params.springs == SpringKind::Implicit || !params.has_springs() {
        return StepEstimate {
            lambda_max: 0.0,
            dt_max: f64::INFINITY,
            node: None,
        };
    }
    let material = model.element_material(params);
    let (lambda_max, node) = gershgorin_lambda(model, &material.spring_stiffness);
    // The smallest damping ratio kd / k of any spring (the same for every spring of one
    // material): the least damped mode bounds the step.
    let beta = material
        .spring_stiffness
        .iter()
        .zip(&material.spring_damping)
        .filter(|(&k, _)| k > 0.0)
        .map(|(&k, &kd)| kd / k)
        .fold(f64::INFINITY, f64::min);
    let beta = if beta.is_finite() { beta } else { 0.0 };
    StepEstimate {
        lambda_max,
        dt_max: dt_for(lambda_max, beta),
        node,
    }
}

/// Speed [m/s] above which a node counts as diverged: `10 L / dt + 10 |v0|max + 100 |g|`,
/// with `L` the model's bounding-box diagonal. A node at that speed crosses its object ten
/// times in one step; the other terms leave room for the initial velocities and 100 s of
/// free fall, so a physical run never reaches it. Always finite and at least 1 m/s.
pub fn speed_limit(model: &Model, params: &SimParams) -> f64 {
    let v0 = model
        .velocities
        .iter()
        .map(|v| v.length())
        .fold(0.0, f64::max);
    let limit =
        10.0 * model.bounds_diagonal() / params.dt + 10.0 * v0 + 100.0 * params.gravity.length();
    if limit.is_finite() {
        limit.max(1.0)
    } else {
        f64::from(f32::MAX)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::grid::box_tets;
    use crate::params::Placement;
    use crate::ModelBuilder;
    use glam::DVec3;

    #[test]
    fn two_masses_on_one_spring_match_the_exact_eigenvalue() {
        // Two free 1 kg masses on one spring: lambda = 2 ks / m exactly, and Gershgorin's
        // row sum ks (1 + 1) is tight.
        let (lambda, node) = {
            let mesh = box_tets(DVec3::ZERO, 1.0, [1, 1, 1]);
            let mut model = ModelBuilder::new(&mesh)
                .placement(Placement {
                    fit_size: None,
                    drop_height: None,
                })
                .build()
                .unwrap();
            model.springs = vec![[0, 1]];
            gershgorin_lambda(&model, &[100.0])
        };
        assert_eq!(lambda, 200.0);
        assert_eq!(node, Some(0));
        // Undamped: 2 / sqrt(lambda).
        assert!((dt_for(200.0, 0.0) - 2.0 / 200f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn damping_shrinks_the_step_and_matches_the_modal_condition() {
        let (lambda, beta) = (1e5, 3e-3);
        let dt = dt_for(lambda, beta);
        assert!(dt < dt_for(lambda, 0.0));
        // On the boundary: lambda dt^2 + 2 beta lambda dt = 4.
        assert!((lambda * dt * dt + 2.0 * beta * lambda * dt - 4.0).abs() < 1e-9);
    }

    #[test]
    fn pinned_and_heavy_nodes_change_the_bound() {
        let mesh = box_tets(DVec3::ZERO, 0.1, [2, 2, 2]);
        let place = Placement {
            fit_size: None,
            drop_height: None,
        };
        let model = ModelBuilder::new(&mesh).placement(place).build().unwrap();
        let params = SimParams::default();
        let free = estimate(&model, &params);
        let all_pinned = ModelBuilder::new(&mesh)
            .placement(place)
            .pinned(0..mesh.nodes.len() as u32)
            .build()
            .unwrap();
        let pinned = estimate(&all_pinned, &params);
        assert_eq!(pinned.node, None);
        assert!(pinned.dt_max.is_infinite());
        // Ten times the mass: lambda / 10, dt about sqrt(10) times larger.
        let heavy = ModelBuilder::new(&mesh)
            .placement(place)
            .mass(crate::params::MassMode::PerNode { mass: 10.0 })
            .build()
            .unwrap();
        let h = estimate(&heavy, &params);
        assert!((free.lambda_max / h.lambda_max - 10.0).abs() < 1e-9);
        assert!(h.dt_max > 3.0 * free.dt_max);
        // Implicit springs: no bound; a stiffer material: a smaller step.
        let implicit = SimParams {
            springs: SpringKind::Implicit,
            ..params.clone()
        };
        assert!(estimate(&model, &implicit).dt_max.is_infinite());
        let soft = SimParams {
            youngs_modulus: Some(1e4),
            ..params.clone()
        };
        let stiff = SimParams {
            youngs_modulus: Some(1e6),
            ..params
        };
        let (soft, stiff) = (estimate(&model, &soft), estimate(&model, &stiff));
        assert!((stiff.lambda_max / soft.lambda_max - 100.0).abs() < 1e-9);
        assert!(stiff.dt_max < soft.dt_max);
    }
}
