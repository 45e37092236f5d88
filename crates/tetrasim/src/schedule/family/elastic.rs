//! Finite elements (`neo-hookean`): each step one Newton step on the stable Neo-Hookean
//! incremental potential, `(M/dt^2 + (1 + beta/dt) K) dx = b`, solved by two-level
//! preconditioned conjugate gradients, one iteration per dispatch of the `elastic` pass
//! (docs/PHYSICS.md, "Finite elements"). Its "constraints" are the nodes themselves, in one
//! group; each iteration writes one force increment per node, `m/dt^2 alpha p`. Here: the
//! per-node pieces both CPU backends share ([`ElasticNodes::newton_row`],
//! [`ElasticNodes::product`]); the tets' stiffness and its products are
//! [`crate::physics::elastic_linearise`] and [`crate::physics::elastic_product`].
//! Prepared once: each tet's shape gradients, rest volume and material
//! ([`ElasticTet`]), each node's tets and corners, masses and damping times.

use super::{Access, BufferId, PassKind};
use crate::model::{adjacency, Csr, Model};
use glam::DVec3;

use crate::physics::{
    elastic_corner, elastic_energy, elastic_product, held_block, node_block, shape_gradients,
    stable_neo_hookean, sym3_apply, sym3_inverse, Aggregates, CoarseSpace, ElasticLinear,
    ElasticTet, Real, Sym3, Vector, NO_AGGREGATE,
};
use crate::problem::Problem;

/// The largest strain change (the norm of the change of a tet's deformation gradient) a
/// conjugate-gradient step may make without a check of the incremental potential: the
/// quadratic model's error is of third order in it, far below the step's gain.
pub const TRUSTED_STRAIN: f64 = 0.01;

/// The least share of the quadratic model's predicted fall of the incremental potential
/// that a step beyond [`TRUSTED_STRAIN`] must achieve for the conjugate gradients to go on
/// with the step's linearisation (the trust region's ratio test; Nocedal and Wright,
/// "Numerical Optimization", ch. 4); below it, the next iteration begins a new Newton step.
pub const TRUSTED_RATIO: f64 = 0.5;

/// Halvings of a conjugate-gradient step before the solve gives up on its direction.
pub const MOST_HALVINGS: u32 = 8;

/// What [`backtrack`] made of a conjugate-gradient step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Backtracked {
    /// The step length taken; `None`: no halving lowered the potential (the solve ends).
    pub alpha: Option<f64>,
    /// The incremental potential where the step ends, when it was evaluated.
    pub potential: Option<f64>,
    /// The step went beyond [`TRUSTED_STRAIN`]: it was checked against the potential.
    pub checked: bool,
    /// The step went beyond the linearisation's trust (beyond [`TRUSTED_STRAIN`], and it
    /// lowered the potential by less than [`TRUSTED_RATIO`] of the model's prediction):
    /// the next iteration begins a new Newton step where the nodes then end.
    pub relinearise: bool,
}

/// The backtracking both CPU backends share (docs/PHYSICS.md, "Finite elements"): the step
/// `alpha` along a direction whose largest strain change per unit step is `strain` is taken
/// as it is when within [`TRUSTED_STRAIN`]; beyond it, it is halved (up to
/// [`MOST_HALVINGS`] times) until it lowers the incremental potential or is trusted, and
/// the linearisation is kept if the fall is at least [`TRUSTED_RATIO`] of what the
/// quadratic model predicts, `curvature a (alpha - a / 2)` for a step `a` (`curvature`:
/// the direction's `p . A p`; `alpha` the conjugate gradients' step, the model's least).
/// `potential_at(a)` is the potential with the nodes moved `a` along the direction from
/// where they end so far, whose value is `known` when the last step evaluated it.
pub fn backtrack(
    alpha: f64,
    strain: f64,
    curvature: f64,
    known: Option<f64>,
    mut potential_at: impl FnMut(f64) -> f64,
) -> Backtracked {
    let checked = alpha * strain > TRUSTED_STRAIN;
    let mut now = known;
    let mut step = alpha;
    for _ in 0..=MOST_HALVINGS {
        if step * strain <= TRUSTED_STRAIN {
            // Taken unchecked: the potential is no longer known.
            return Backtracked {
                alpha: Some(step),
                potential: None,
                checked,
                relinearise: checked,
            };
        }
        let here = *now.get_or_insert_with(|| potential_at(0.0));
        let trial = potential_at(step);
        if trial <= here {
            let predicted = curvature * step * (alpha - 0.5 * step);
            return Backtracked {
                alpha: Some(step),
                potential: Some(trial),
                checked,
                relinearise: here - trial < TRUSTED_RATIO * predicted,
            };
        }
        step *= 0.5;
    }
    Backtracked {
        alpha: None,
        potential: now,
        checked,
        relinearise: checked,
    }
}

/// The pass that solves them.
pub(super) const PASS: PassKind = PassKind::Elastic;

/// What the pass reads besides the nodes.
pub(super) fn bindings() -> Vec<(BufferId, Access)> {
    vec![
        (BufferId::Tets, Access::Read),
        (BufferId::ElasticTets, Access::Read),
        (BufferId::NodeTetOffsets, Access::Read),
        (BufferId::NodeTetItems, Access::Read),
        (BufferId::ColliderContacts, Access::Read),
    ]
}

/// The nodes as elements: `[[i]]` for every node (the slots of their force increments).
pub fn node_elements(model: &Model) -> Vec<[u32; 1]> {
    (0..model.node_count() as u32).map(|i| [i]).collect()
}

/// The finite elements' data in precision `R`.
#[derive(Debug, Clone)]
pub struct ElasticNodes<R> {
    /// Per tet: its element constants.
    pub tets: Vec<ElasticTet<R>>,
    /// Row `i`: `4 t + corner` for each tet `t` at node `i`.
    pub node_tets: Csr,
    /// Per node: its mass [kg].
    pub mass: Vec<R>,
    /// Per node: the damping time [s] of its first tet's material.
    pub damping: Vec<R>,
    /// Per node: the largest strain per unit displacement of its tets' corners at the node,
    /// `|g_a|` [1/m] (one over the tet's height above the face opposite the node;
    /// [`crate::physics::elastic_product_strain`]).
    pub reach: Vec<R>,
    /// The node ranges of the objects with no pinned node: the elastic forces on each sum to
    /// no force and no torque ([`crate::physics::RigidPart`]).
    pub free_objects: Vec<std::ops::Range<usize>>,
    /// The free nodes' aggregates: the conjugate gradients' coarse level
    /// ([`crate::physics::CoarseSpace`]).
    pub aggregates: Aggregates,
}

impl<R: Real> ElasticNodes<R> {
    /// The data of `problem`'s tets and nodes (a flat tet gets no stiffness).
    pub fn prepare(problem: &Problem) -> Self {
        let (model, material) = (&problem.model, &problem.material);
        let tets = (model.tets.iter().enumerate())
            .map(|(t, tet)| {
                let p = tet.map(|i| model.positions[i as usize]);
                let [mu, lambda] = material.tet_lame[t];
                let (mu_s, lambda_s, alpha) = stable_neo_hookean(mu, lambda);
                let shape = shape_gradients(p).unwrap_or([[0.0; 3]; 3]);
                ElasticTet {
                    shape: shape.map(|row| row.map(R::from_f64)),
                    volume: R::from_f64(model.rest_volume[t]),
                    mu: R::from_f64(mu_s),
                    lambda: R::from_f64(lambda_s),
                    alpha: R::from_f64(if lambda_s > 0.0 { alpha } else { 1.0 }),
                }
            })
            .collect();
        let by_tet = adjacency(model.node_count(), model.tets.iter().map(|t| t.as_slice()));
        let node_tets = Csr {
            offsets: by_tet.offsets.clone(),
            items: (0..model.node_count())
                .flat_map(|i| {
                    by_tet.row(i).iter().map(move |&t| {
                        let corner = model.tets[t as usize]
                            .iter()
                            .position(|&k| k as usize == i)
                            .unwrap_or(0);
                        4 * t + corner as u32
                    })
                })
                .collect(),
        };
        let damping = (0..model.node_count())
            .map(|i| {
                let beta =
                    (by_tet.row(i).first()).map_or(0.0, |&t| material.tet_damping[t as usize]);
                R::from_f64(beta)
            })
            .collect();
        // A corner's strain per unit displacement is its shape gradient's length (one over
        // the tet's height above the opposite face): the node's reach is its largest.
        let mut reach = vec![0.0f64; model.node_count()];
        for tet in &model.tets {
            let p = tet.map(|i| model.positions[i as usize]);
            let Some(g) = shape_gradients(p) else {
                continue;
            };
            let g0 = [0, 1, 2].map(|k| -(g[0][k] + g[1][k] + g[2][k]));
            for (corner, row) in [g0, g[0], g[1], g[2]].iter().enumerate() {
                let length = row.iter().map(|c| c * c).sum::<f64>().sqrt();
                let i = tet[corner] as usize;
                reach[i] = reach[i].max(length);
            }
        }
        let reach = reach.iter().map(|&r| R::from_f64(r)).collect();
        let free_objects = (model.objects.windows(2))
            .map(|w| w[0] as usize..w[1] as usize)
            .filter(|nodes| model.inv_mass[nodes.clone()].iter().all(|&w| w > 0.0))
            .collect();
        ElasticNodes {
            tets,
            node_tets,
            mass: model.mass.iter().map(|&m| R::from_f64(m)).collect(),
            damping,
            reach,
            free_objects,
            aggregates: Aggregates::group(
                &model.positions,
                &model.inv_mass,
                &model.objects,
                &model.tets,
            ),
        }
    }

    /// Node `i`'s row of the step's Newton system, linearised where each node `k` ends
    /// the step so far, `end(k)`, its elastic force so far being `phi`: the residual
    /// `b_i = -(phi + dE/dx_i + beta (K v)_i)` [N] (`v` the nodes' velocities over the
    /// step, `(end - start) / dt`, `K v` summed from its tets' corners, `rate(4 t + c)`:
    /// [`crate::physics::elastic_product`] of tet `t`'s kept stiffness and its corners'
    /// velocities, at its corner `c`; the step's equation is `b = 0`) and the inverse of
    /// its diagonal block ([`node_block`]), the conjugate
    /// gradients' preconditioner, the block stiffened along `held`, the direction a contact
    /// holds the node along (zero where none does; [`held_block`]), and that stiffening `h`.
    /// Zero for a pinned node (`w = 0`), whose position is given.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn newton_row<V: Vector<Real = R>>(
        &self,
        i: usize,
        w: R,
        dt: R,
        phi: V,
        held: V,
        tets: &[[u32; 4]],
        end: impl Fn(usize) -> V,
        rate: impl Fn(usize) -> V,
    ) -> (V, Sym3<R>, V) {
        if w <= R::ZERO {
            return (V::ZERO, [R::ZERO; 6], V::ZERO);
        }
        let (grad, hessian) = self.gradient(i, tets, &end);
        let beta = self.damping[i];
        let rate = if beta > R::ZERO {
            self.gather(i, rate)
        } else {
            V::ZERO
        };
        let (block, h) = held_block(node_block(self.mass[i], dt, beta, hessian), held);
        let inverse = sym3_inverse(block).unwrap_or([R::ZERO; 6]);
        (-(grad + rate * beta + phi), inverse, h)
    }

    /// Node `i`'s entry of the Newton matrix times the direction `p`:
    /// `m/dt^2 p_i + h (h . p_i) + (1 + beta/dt) (K p)_i` (`h`: its contact's stiffening,
    /// [`ElasticNodes::newton_row`]), `K p` summed from its tets' corners (`corner(4 t + c)`:
    /// [`crate::physics::elastic_product`] of tet `t` at its corner `c`). Zero for a pinned
    /// node (`w = 0`; the direction is zero there).
    #[inline]
    pub fn product<V: Vector<Real = R>>(
        &self,
        i: usize,
        w: R,
        dt: R,
        p: V,
        h: V,
        corner: impl Fn(usize) -> V,
    ) -> V {
        if w <= R::ZERO {
            return V::ZERO;
        }
        let k = self.gather(i, corner);
        self.increment(i, dt, h, p, R::ONE) + k * (R::ONE + self.damping[i] / dt)
    }

    /// The sum of `corner(4 t + c)` over node `i`'s tets `t` (`c` its corner in each).
    #[inline]
    pub fn gather<V: Vector<Real = R>>(&self, i: usize, corner: impl Fn(usize) -> V) -> V {
        let mut sum = V::ZERO;
        for &item in self.node_tets.row(i) {
            sum += corner(item as usize);
        }
        sum
    }

    /// Tet `t`'s stiffness `linear` (kept at the step's linearisation) times its corners'
    /// velocities over the step so far, `(end - start) / dt`: the corners' shares of
    /// `K v`, the Rayleigh damping's ([`ElasticNodes::newton_row`]).
    #[inline]
    pub fn rate_corners<V: Vector<Real = R>>(
        &self,
        t: usize,
        tet: [u32; 4],
        linear: &ElasticLinear<V>,
        dt: R,
        start: impl Fn(usize) -> V,
        end: impl Fn(usize) -> V,
    ) -> [V; 4] {
        let u = tet.map(|k| (end(k as usize) - start(k as usize)) * (R::ONE / dt));
        elastic_product(&self.tets[t], linear, u)
    }

    /// The elastic force a move `alpha p` of node `i` within the step adds: its inertia's
    /// `m/dt^2 alpha p`, and, where a contact holds it (`h` not zero), the force the
    /// stiffening `h (h . alpha p)` stood for, which the contact takes from it once the move
    /// is applied (the contact's solve stops the node and reports what pressed it).
    #[inline]
    pub fn increment<V: Vector<Real = R>>(&self, i: usize, dt: R, h: V, p: V, alpha: R) -> V {
        p * (alpha * self.mass[i] / (dt * dt)) + h * (h.dot(p) * alpha)
    }

    /// The coarse level of the conjugate gradients' preconditioner at the linearisation
    /// `at` ([`CoarseSpace`]), its matrix not yet assembled.
    pub fn coarse_space<V: Vector<Real = R>>(&self, at: &[V]) -> CoarseSpace {
        CoarseSpace::new(&self.aggregates, |k| at[k].to_dvec3())
    }

    /// Aggregate `a`'s six columns of the coarse matrix `P^T A P` into `columns` (zeroed
    /// here; column-major, all rows): its free nodes' own blocks (`m/dt^2 I + h h^T`, `h`
    /// their contacts' stiffening) and its tets' stiffness `linear` times its modes, each
    /// row scaled by `1 + beta/dt` as [`ElasticNodes::product`] scales it. In `f64` from
    /// the `R` products.
    #[allow(clippy::too_many_arguments)]
    pub fn coarse_columns<V: Vector<Real = R>>(
        &self,
        coarse: &CoarseSpace,
        a: usize,
        tets: &[[u32; 4]],
        at: &[V],
        linear: &[ElasticLinear<V>],
        held: &[V],
        dt: R,
        columns: &mut [f64],
    ) {
        columns.fill(0.0);
        let aggregates = &self.aggregates;
        let dt64 = dt.to_f64();
        for &i in &aggregates.members[a] {
            let i = i as usize;
            let (m, h) = (self.mass[i].to_f64() / (dt64 * dt64), held[i].to_dvec3());
            let block = [
                m + h.x * h.x,
                m + h.y * h.y,
                m + h.z * h.z,
                h.x * h.y,
                h.y * h.z,
                h.x * h.z,
            ];
            coarse.add_node(a, at[i].to_dvec3(), block, columns);
        }
        let of = |k: u32| {
            Some(aggregates.of[k as usize] as usize).filter(|&b| b != NO_AGGREGATE as usize)
        };
        for &t in &aggregates.tets[a] {
            let (t, tet) = (t as usize, tets[t as usize]);
            let corners = tet.map(|k| (of(k), at[k as usize].to_dvec3()));
            let scale = tet.map(|k| 1.0 + self.damping[k as usize].to_f64() / dt64);
            let product = |d: [DVec3; 4]| {
                let applied = elastic_product(&self.tets[t], &linear[t], d.map(V::from_dvec3));
                std::array::from_fn(|c| applied[c].to_dvec3() * scale[c])
            };
            coarse.add_tet(a, corners, product, columns);
        }
    }

    /// The sums over node `i`'s tets of the energy's gradient at its corner and the
    /// Hessian block, with node `k` at `end(k)`.
    #[inline]
    pub fn gradient<V: Vector<Real = R>>(
        &self,
        i: usize,
        tets: &[[u32; 4]],
        end: &impl Fn(usize) -> V,
    ) -> (V, [R; 6]) {
        let mut grad = V::ZERO;
        let mut hessian = [R::ZERO; 6];
        for &item in self.node_tets.row(i) {
            let (t, corner) = ((item / 4) as usize, (item % 4) as usize);
            let p = tets[t].map(|k| end(k as usize));
            let (g, h) = elastic_corner(&self.tets[t], p, corner);
            grad += g;
            for (s, h) in hessian.iter_mut().zip(h) {
                *s += h;
            }
        }
        (grad, hessian)
    }
}

impl ElasticNodes<f64> {
    /// The two-level preconditioner (`cpu-ref`'s): each node's inverse diagonal block
    /// (`inverse`) times its residual `r`, plus, for a node of an aggregate not `touching` a
    /// contact, the coarse correction `P A_c^-1 P^T r` of `coarse` with the nodes at `at`.
    pub fn precondition(
        &self,
        coarse: &CoarseSpace,
        at: &[DVec3],
        r: &[DVec3],
        inverse: &[Sym3<f64>],
        touching: &[bool],
    ) -> Vec<DVec3> {
        let aggregates = &self.aggregates;
        let mut u = vec![0.0; coarse.unknowns()];
        for (a, members) in aggregates.members.iter().enumerate() {
            for &i in members {
                if touching[i as usize] {
                    continue;
                }
                let share = coarse.restrict(a, at[i as usize], r[i as usize]);
                (u[6 * a..6 * a + 6].iter_mut().zip(share)).for_each(|(u, s)| *u += s);
            }
        }
        coarse.solve(&mut u);
        (0..r.len())
            .map(|i| {
                let z = sym3_apply(inverse[i], r[i]);
                match aggregates.of[i] {
                    NO_AGGREGATE => z,
                    _ if touching[i] => z,
                    a => z + coarse.prolong(a as usize, at[i], &u),
                }
            })
            .collect()
    }

    /// The step's incremental potential with the nodes moved by `moves` from `at` (`cpu-ref`'s
    /// in [`backtrack`]): `sum_i m_i / (2 dt^2) |x_i - y_i|^2 + (h_i . d_i)^2 / 2` over the
    /// free nodes (`inv_mass > 0`; `y` where inertia and gravity alone take them, `h` their
    /// contacts' stiffening, `d` their moves) plus the tets' energy.
    #[allow(clippy::too_many_arguments)]
    pub fn potential(
        &self,
        tets: &[[u32; 4]],
        inv_mass: &[f64],
        dt: f64,
        at: &[DVec3],
        moves: &[DVec3],
        y: &[DVec3],
        held: &[DVec3],
    ) -> f64 {
        let x: Vec<DVec3> = at.iter().zip(moves).map(|(a, d)| *a + *d).collect();
        let inertia: f64 = (0..x.len())
            .filter(|&i| inv_mass[i] > 0.0)
            .map(|i| {
                let contact = held[i].dot(moves[i]).powi(2) * dt * dt;
                self.mass[i] * (x[i] - y[i]).length_squared() + contact
            })
            .sum::<f64>()
            / (2.0 * dt * dt);
        let energy: f64 = (tets.iter().zip(&self.tets))
            .map(|(tet, t)| elastic_energy(t, tet.map(|k| x[k as usize])))
            .sum();
        inertia + energy
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A direction with `p . A p = 1` and the conjugate gradients' step 1 (the model
    /// `-a + a^2 / 2`, least at 1, predicting a fall of 1/2), its strain change 1 per unit
    /// step: beyond the trust, so checked against `potential`.
    fn stepped(potential: impl Fn(f64) -> f64) -> Backtracked {
        backtrack(1.0, 1.0, 1.0, None, potential)
    }

    #[test]
    fn a_step_the_model_predicts_keeps_the_linearisation() {
        // The potential is the model: the fall is the predicted one.
        let exact = stepped(|a| -a + a * a / 2.0);
        assert_eq!(exact.alpha, Some(1.0));
        assert!(exact.checked && !exact.relinearise, "{exact:?}");
        // A fall of 0.3 of the predicted 0.5 is 0.6 of it: kept.
        assert!(!stepped(|a| -0.6 * (a - a * a / 2.0)).relinearise);
        // A fall of 0.2 (0.4 of it): a new Newton step.
        let short = stepped(|a| -0.4 * (a - a * a / 2.0));
        assert!(short.checked && short.relinearise, "{short:?}");
    }

    #[test]
    fn a_step_that_raises_the_potential_is_halved_and_relinearised() {
        // Rises at 1, falls at 1/2 by 0.3 against the model's 3/8: kept at 0.8 of it.
        let halved = stepped(|a| {
            if a > 0.75 {
                1.0
            } else {
                -0.8 * (a - a * a / 2.0)
            }
        });
        assert_eq!(halved.alpha, Some(0.5));
        assert!(!halved.relinearise, "{halved:?}");
        // Rises until halved within the trust: taken unchecked, then a new Newton step.
        let trusted = backtrack(1.0, 0.015, 1.0, None, |a| a);
        assert_eq!(trusted.alpha, Some(0.5));
        assert!(trusted.checked && trusted.relinearise && trusted.potential.is_none());
        // Within the trust from the start: neither checked nor relinearised.
        let small = backtrack(1.0, 0.005, 1.0, None, |_| panic!("not evaluated"));
        assert!(!small.checked && !small.relinearise);
    }
}
