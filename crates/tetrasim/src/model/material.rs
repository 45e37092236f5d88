//! Per-element material constants (physics.md, "Material in physical units"): each spring's
//! stiffness and damping and each tet's volume compliance, from the paper's uniform `ks`,
//! `kd` or from a Young's modulus and Poisson's ratio. Every backend reads springs and
//! volume constraints through these, so objects of one scene may have different materials.

use std::collections::HashMap;

use super::Model;
use crate::params::{SimParams, DEFAULT_DAMPING_TIME};

/// The material of every spring and tet of a model.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementMaterial {
    /// Per spring: stiffness `k_e` [N/m] (explicit force `k_e (l - L)`; compliance `1 / k_e`
    /// of an implicit spring).
    pub spring_stiffness: Vec<f64>,
    /// Per spring: damping [N s/m] along the spring.
    pub spring_damping: Vec<f64>,
    /// Per tet: compliance `alpha_t` of its volume constraint [m^3/Pa]; 0 is the paper's hard
    /// constraint.
    pub volume_compliance: Vec<f64>,
    /// Per tet: Lame's `(mu, lambda)` [Pa] of the finite elements (zeros without a Young's
    /// modulus and a Poisson's ratio below 0.5).
    pub tet_lame: Vec<[f64; 2]>,
    /// Per tet: the damping time `beta` [s] of the finite elements' stiffness-proportional
    /// damping.
    pub tet_damping: Vec<f64>,
}

impl ElementMaterial {
    /// The material `params` describes on `model`'s springs and tets: `ks`, `kd` on every
    /// spring and hard volume constraints; or, with a Young's modulus `E`, Van Gelder's
    /// stiffness `k_e = E sum_(t at e) V0_t / L_e^2`, damping `beta k_e` (`beta` =
    /// `params.damping`, default 3 ms) and, with a Poisson's ratio `nu < 0.5`, the volume
    /// compliance `alpha_t = V0_t / K` with the bulk modulus `K = E / (3 (1 - 2 nu))`.
    pub fn new(model: &Model, params: &SimParams) -> Self {
        let springs = model.springs.len();
        let Some(e) = params.youngs_modulus else {
            return ElementMaterial {
                spring_stiffness: vec![params.ks; springs],
                spring_damping: vec![params.kd; springs],
                volume_compliance: vec![0.0; model.tets.len()],
                tet_lame: vec![[0.0; 2]; model.tets.len()],
                tet_damping: vec![0.0; model.tets.len()],
            };
        };
        let stiffness: Vec<f64> = edge_volumes(model)
            .iter()
            .zip(&model.rest_length)
            .map(|(&v, &l)| e * v / (l * l))
            .collect();
        let beta = params.damping.unwrap_or(DEFAULT_DAMPING_TIME);
        let compliance = match params.poisson_ratio {
            Some(nu) if nu < 0.5 => {
                let bulk = bulk_modulus(e, nu);
                model.rest_volume.iter().map(|&v| v / bulk).collect()
            }
            _ => vec![0.0; model.tets.len()],
        };
        let lame = match params.poisson_ratio {
            Some(nu) if nu < 0.5 => crate::physics::lame(e, nu),
            _ => (0.0, 0.0),
        };
        ElementMaterial {
            spring_damping: stiffness.iter().map(|&k| beta * k).collect(),
            spring_stiffness: stiffness,
            volume_compliance: compliance,
            tet_lame: vec![[lame.0, lame.1]; model.tets.len()],
            tet_damping: vec![beta; model.tets.len()],
        }
    }

    /// Whether some volume constraint is compliant.
    pub fn has_compliant_volumes(&self) -> bool {
        self.volume_compliance.iter().any(|&a| a > 0.0)
    }

    /// The material of `a`'s elements followed by `b`'s (as [`Model::concat`] orders them).
    pub fn concat(a: &Self, b: &Self) -> Self {
        let join = |x: &[f64], y: &[f64]| [x, y].concat();
        ElementMaterial {
            spring_stiffness: join(&a.spring_stiffness, &b.spring_stiffness),
            spring_damping: join(&a.spring_damping, &b.spring_damping),
            volume_compliance: join(&a.volume_compliance, &b.volume_compliance),
            tet_lame: [&a.tet_lame[..], &b.tet_lame[..]].concat(),
            tet_damping: join(&a.tet_damping, &b.tet_damping),
        }
    }
}

/// The bulk modulus `K = E / (3 (1 - 2 nu))` [Pa] (infinite at `nu = 0.5`).
pub fn bulk_modulus(youngs_modulus: f64, poisson_ratio: f64) -> f64 {
    youngs_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio))
}

/// Per spring, the summed rest volume of the tets that share its edge [m^3].
fn edge_volumes(model: &Model) -> Vec<f64> {
    let index: HashMap<[u32; 2], usize> = model
        .springs
        .iter()
        .enumerate()
        .map(|(s, &e)| (e, s))
        .collect();
    let mut volume = vec![0.0; model.springs.len()];
    for (tet, &v) in model.tets.iter().zip(&model.rest_volume) {
        for a in 0..4 {
            for b in a + 1..4 {
                let (i, j) = (tet[a].min(tet[b]), tet[a].max(tet[b]));
                if let Some(&s) = index.get(&[i, j]).or_else(|| index.get(&[j, i])) {
                    volume[s] += v;
                }
            }
        }
    }
    volume
}
