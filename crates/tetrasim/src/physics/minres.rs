//! MINRES on a step's linearised constraints (docs/PHYSICS.md, "MINRES after the sweeps"):
//! the host-side solver both CPU backends share. Its vectors are in double precision; the
//! gradients and the matrix product are in the backend's ([`StepRows`]).
//!
//! Every constraint of a step is linear in the step's forces: its gradients are taken at
//! `x(t)`, and its multiplier increment solves `A delta = B` (physics.md, "Implicit
//! constraint enforcement"). All of them together are the symmetric system
//!
//! ```text
//! (J W J^T + S) delta = r
//! ```
//!
//! with `J` the gradients (one row per constraint), `W` the inverse masses, `S` the
//! softness of compliant constraints and `r` each constraint's numerator `B` at the forces
//! so far ([`compliant_residual`]). The sweeps converge it one constraint at a time, so a
//! body's slowest modes (a stiff body squashing on the floor) take hundreds of sweeps.
//! MINRES (Paige and Saunders 1975) converges them in tens of iterations, each one product
//! with the matrix: a pass over the constraints to the nodes and one back.
//!
//! The floor is one-sided and the sweeps have found who touches it: a node the floor (or a
//! collider, or a grab) pushes is held, its motion along the push taken out of `W` (the
//! `mobility` per node). A constraint that holding leaves less than [`HELD_SHARE`] of its
//! mobility is left to the sweeps: its row would ask the held nodes to move, and near that
//! singularity the solve's forces grow without bound (the horse's hooves at impact).
//!
//! MINRES, not conjugate gradients: both minimise over the same Krylov space, but MINRES the
//! residual `r` (each constraint's violation), which never grows from one iteration to the
//! next. Conjugate gradients minimise the error in the forces' energy norm, and cut short
//! at a single-node contact their intermediate forces threw the rigid sphere off the floor
//! (measured; docs/PHYSICS.md). The preconditioner is the rows' diagonal `A + s`.

use glam::DVec3;

use super::{Real, Vector};

/// How a node moves under a force in the solve: its inverse mass, less the direction a
/// contact holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mobility {
    /// The node's inverse mass [1/kg] (0: held in every direction, or pinned).
    pub inv_mass: f64,
    /// The unit normal a contact holds it along (zero: free).
    pub held: DVec3,
}

impl Mobility {
    /// A node free in every direction.
    pub fn free(inv_mass: f64) -> Self {
        Mobility {
            inv_mass,
            held: DVec3::ZERO,
        }
    }

    /// A node's mobility in a step's solve: the floor holds it along `+Y` when it pushes
    /// it, a collider along its push `collider` (zero: none), a grab in every direction.
    pub fn held_by(inv_mass: f64, floor: bool, collider: DVec3, grabbed: bool) -> Self {
        let held = match (floor, collider != DVec3::ZERO) {
            (true, _) => DVec3::Y,
            (false, true) => collider.normalize(),
            (false, false) => DVec3::ZERO,
        };
        let inv_mass = if grabbed { 0.0 } else { inv_mass };
        Mobility { inv_mass, held }
    }

    /// The velocity change per step^2 a force `u` gives the node.
    #[inline]
    fn apply(&self, u: DVec3) -> DVec3 {
        (u - self.held * self.held.dot(u)) * self.inv_mass
    }

    /// The same in the rows' precision.
    fn rounded<V: Vector>(&self) -> (V::Real, V) {
        (V::Real::from_f64(self.inv_mass), V::from_dvec3(self.held))
    }
}

/// [`Mobility::apply`] in precision `V`.
#[inline]
fn apply_rounded<V: Vector>((inv_mass, held): (V::Real, V), u: V) -> V {
    (u - held * held.dot(u)) * inv_mass
}

/// `sum_j f(j)` over `0..m` in four independent partial sums, which hide the additions'
/// latency.
#[inline(always)]
fn lanes_sum(m: usize, mut f: impl FnMut(usize) -> f64) -> f64 {
    let (mut a, mut b, mut c, mut d) = (0.0, 0.0, 0.0, 0.0);
    let mut j = 0;
    while j + 4 <= m {
        a += f(j);
        b += f(j + 1);
        c += f(j + 2);
        d += f(j + 3);
        j += 4;
    }
    while j < m {
        a += f(j);
        j += 1;
    }
    (a + b) + (c + d)
}

/// The most MINRES iterations a step may run.
pub const MINRES_MAX_ITERATIONS: u32 = 200;

/// A row keeps at least this share of its mobility when its held nodes are taken out, or it
/// is left to the sweeps.
pub const HELD_SHARE: f64 = 0.5;

/// The numerator `B` of a compliant constraint's multiplier increment ([`compliant_multiplier`](
/// super::compliant_multiplier) is `B / (A + s)`): `c / dt^2 + b - kd s c / dt`, `b` the
/// sum [`implicit_accumulate`](super::implicit_accumulate) gives minus `s` times the
/// multiplier so far. Zero when the constraint holds at the forces so far.
#[inline]
pub fn compliant_residual<R: Real>(c: R, b: R, dt: R, softness: R, damping: R) -> R {
    c / (dt * dt) + b - damping * softness * c / dt
}

/// Rows of `K` entries each: their indices, nodes and gradients.
#[derive(Debug, Clone)]
struct Fixed<const K: usize, V> {
    row: Vec<u32>,
    nodes: Vec<[u32; K]>,
    grads: Vec<[V; K]>,
}

impl<const K: usize, V> Default for Fixed<K, V> {
    fn default() -> Self {
        Fixed {
            row: Vec::new(),
            nodes: Vec::new(),
            grads: Vec::new(),
        }
    }
}

impl<const K: usize, V: Vector> Fixed<K, V> {
    /// Adds row `row` if it has `K` entries; gives it back if not.
    fn take(&mut self, row: u32, nodes: &[u32], grads: &[DVec3]) -> bool {
        match (<[u32; K]>::try_from(nodes), <[DVec3; K]>::try_from(grads)) {
            (Ok(n), Ok(g)) => {
                self.row.push(row);
                self.nodes.push(n);
                self.grads.push(g.map(V::from_dvec3));
                true
            }
            _ => false,
        }
    }

    /// Every `(row, node, gradient)` entry.
    fn entries(&self) -> impl Iterator<Item = (usize, usize, DVec3)> + '_ {
        (self.row.iter().zip(&self.nodes).zip(&self.grads)).flat_map(|((&j, n), g)| {
            (n.iter().zip(g)).map(move |(&i, &g)| (j as usize, i as usize, g.to_dvec3()))
        })
    }

    /// `u += grad p` on each row's nodes.
    fn scatter(&self, p: &[f64], u: &mut [V]) {
        for ((&j, n), g) in self.row.iter().zip(&self.nodes).zip(&self.grads) {
            let pj = p[j as usize];
            if pj != 0.0 {
                let pj = V::Real::from_f64(pj);
                for k in 0..K {
                    u[n[k] as usize] += g[k] * pj;
                }
            }
        }
    }

    /// `q += grad . u` over each row's nodes.
    fn gather(&self, u: &[V], q: &mut [f64]) {
        for ((&j, n), g) in self.row.iter().zip(&self.nodes).zip(&self.grads) {
            let mut sum = V::Real::ZERO;
            for k in 0..K {
                sum += g[k].dot(u[n[k] as usize]);
            }
            q[j as usize] += sum.to_f64();
        }
    }
}

/// A step's constraint rows: each one's nodes, its gradient on each, its softness and its
/// residual at the forces so far. Rows of two and four entries (springs and distance
/// constraints, tets) are kept apart from the wide ones (the global volume constraints),
/// so that the solve's products run fixed-size loops. The gradients and the product's node
/// sums are kept in precision `V` (the backend's); the solve's vectors are `f64`.
#[derive(Debug, Clone)]
pub struct StepRows<V = DVec3> {
    pairs: Fixed<2, V>,
    tets: Fixed<4, V>,
    /// The other rows: their indices, and their entries from `wide_first[k]` on.
    wide_row: Vec<u32>,
    wide_first: Vec<usize>,
    wide_nodes: Vec<u32>,
    wide_grads: Vec<V>,
    softness: Vec<f64>,
    residual: Vec<f64>,
}

impl<V: Vector> Default for StepRows<V> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V: Vector> StepRows<V> {
    /// No rows.
    pub fn new() -> Self {
        StepRows {
            pairs: Fixed::default(),
            tets: Fixed::default(),
            wide_row: Vec::new(),
            wide_first: vec![0],
            wide_nodes: Vec::new(),
            wide_grads: Vec::new(),
            softness: Vec::new(),
            residual: Vec::new(),
        }
    }

    /// Adds a row: its nodes, its gradient on each, its softness and its residual.
    pub fn push(&mut self, nodes: &[u32], grads: &[DVec3], softness: f64, residual: f64) {
        debug_assert_eq!(nodes.len(), grads.len());
        let row = self.softness.len() as u32;
        if !self.pairs.take(row, nodes, grads) && !self.tets.take(row, nodes, grads) {
            self.wide_row.push(row);
            self.wide_nodes.extend_from_slice(nodes);
            self.wide_grads
                .extend(grads.iter().map(|&g| V::from_dvec3(g)));
            self.wide_first.push(self.wide_nodes.len());
        }
        self.softness.push(softness);
        self.residual.push(residual);
    }

    /// No rows, the memory kept for the next step's.
    pub fn clear(&mut self) {
        self.pairs.row.clear();
        self.pairs.nodes.clear();
        self.pairs.grads.clear();
        self.tets.row.clear();
        self.tets.nodes.clear();
        self.tets.grads.clear();
        self.wide_row.clear();
        self.wide_first.clear();
        self.wide_first.push(0);
        self.wide_nodes.clear();
        self.wide_grads.clear();
        self.softness.clear();
        self.residual.clear();
    }

    /// The number of rows.
    pub fn len(&self) -> usize {
        self.softness.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.softness.is_empty()
    }

    /// Every `(row, node, gradient)` entry, the rows in no particular order.
    pub fn entries(&self) -> impl Iterator<Item = (usize, usize, DVec3)> + '_ {
        let wide = self.wide_row.iter().enumerate().flat_map(move |(k, &j)| {
            let range = self.wide_first[k]..self.wide_first[k + 1];
            (self.wide_nodes[range.clone()]
                .iter()
                .zip(&self.wide_grads[range]))
            .map(move |(&i, &g)| (j as usize, i as usize, g.to_dvec3()))
        });
        self.pairs.entries().chain(self.tets.entries()).chain(wide)
    }

    /// Per row, `sum_k grad_k . M_k grad_k` with `M_k` node `k`'s mobility, and the same
    /// with every node free.
    fn diagonals(&self, mobility: &[Mobility]) -> (Vec<f64>, Vec<f64>) {
        let (mut held, mut free) = (vec![0.0; self.len()], vec![0.0; self.len()]);
        for (j, i, g) in self.entries() {
            held[j] += g.dot(mobility[i].apply(g));
            free[j] += g.length_squared() * mobility[i].inv_mass;
        }
        (held, free)
    }

    /// `q = (J M J^T + S) p` over the rows `live` leaves in (`u`: scratch per node, `mobility`
    /// rounded to `V`); `p` is 0 on the others.
    fn product(
        &self,
        mobility: &[(V::Real, V)],
        live: &[bool],
        p: &[f64],
        u: &mut [V],
        q: &mut [f64],
    ) {
        u.fill(V::ZERO);
        self.pairs.scatter(p, u);
        self.tets.scatter(p, u);
        for (k, &j) in self.wide_row.iter().enumerate() {
            let range = self.wide_first[k]..self.wide_first[k + 1];
            let pj = V::Real::from_f64(p[j as usize]);
            for (&i, &g) in self.wide_nodes[range.clone()]
                .iter()
                .zip(&self.wide_grads[range])
            {
                u[i as usize] += g * pj;
            }
        }
        for (ui, &m) in u.iter_mut().zip(mobility) {
            *ui = apply_rounded(m, *ui);
        }
        for ((qj, &s), &pj) in q.iter_mut().zip(&self.softness).zip(p) {
            *qj = s * pj;
        }
        self.pairs.gather(u, q);
        self.tets.gather(u, q);
        for (k, &j) in self.wide_row.iter().enumerate() {
            let range = self.wide_first[k]..self.wide_first[k + 1];
            let entries = self.wide_nodes[range.clone()]
                .iter()
                .zip(&self.wide_grads[range]);
            let sum = entries.fold(V::Real::ZERO, |a, (&i, &g)| a + g.dot(u[i as usize]));
            q[j as usize] += sum.to_f64();
        }
        for (qj, &l) in q.iter_mut().zip(live) {
            if !l {
                *qj = 0.0;
            }
        }
    }
}

/// The multiplier increments after `iterations` of preconditioned MINRES on `rows`, each
/// node moving with its `mobility` (what the floor, colliders and grabs hold taken out).
/// Rows the holding leaves less than [`HELD_SHARE`] of their mobility, or none, get 0.
pub fn minres<V: Vector>(rows: &StepRows<V>, mobility: &[Mobility], iterations: u32) -> Vec<f64> {
    let m = rows.len();
    let (held, full) = rows.diagonals(mobility);
    let live: Vec<bool> = (held.iter().zip(&full))
        .map(|(&h, &f)| h > 0.0 && h >= HELD_SHARE * f)
        .collect();
    let inverse: Vec<f64> = (0..m)
        .map(|j| match live[j] {
            true => 1.0 / (held[j] + rows.softness[j]),
            false => 0.0,
        })
        .collect();
    let mut x = vec![0.0; m];
    // The Lanczos vectors: r1 and r2 the last two, y = M^-1 r2, v = y / beta.
    let mut r2: Vec<f64> = (rows.residual.iter().zip(&live))
        .map(|(&r, &l)| if l { r } else { 0.0 })
        .collect();
    let mut y: Vec<f64> = r2.iter().zip(&inverse).map(|(r, d)| r * d).collect();
    let beta1 = r2.iter().zip(&y).map(|(r, y)| r * y).sum::<f64>();
    if !(beta1 > 0.0 && beta1.is_finite()) {
        return x;
    }
    let mut beta = beta1.sqrt();
    let mut v: Vec<f64> = y.iter().map(|y| y / beta).collect();
    let mut r1 = vec![0.0; m];
    let (mut old_beta, mut dbar, mut epsilon, mut phibar) = (0.0, 0.0, 0.0, beta);
    let (mut cs, mut sn) = (-1.0f64, 0.0f64);
    let (mut w, mut w1) = (vec![0.0; m], vec![0.0; m]);
    let mut av = vec![0.0; m];
    let rounded: Vec<(V::Real, V)> = mobility.iter().map(Mobility::rounded).collect();
    let mut u = vec![V::ZERO; mobility.len()];
    for _ in 0..iterations {
        rows.product(&rounded, &live, &v, &mut u, &mut av);
        // av = A v - (beta / old_beta) r1, alpha = v . av
        let back = if old_beta > 0.0 { beta / old_beta } else { 0.0 };
        let alpha = {
            let (av, r1, v) = (&mut av[..m], &r1[..m], &v[..m]);
            lanes_sum(m, |j| {
                av[j] -= back * r1[j];
                v[j] * av[j]
            })
        };
        // The next Lanczos vector: r1 <- r2, r2 <- av - (alpha / beta) r2, y = M^-1 r2.
        let along = alpha / beta;
        let next = {
            let (av, r1, r2) = (&av[..m], &mut r1[..m], &mut r2[..m]);
            let (y, inverse) = (&mut y[..m], &inverse[..m]);
            lanes_sum(m, |j| {
                let a = av[j] - along * r2[j];
                r1[j] = r2[j];
                r2[j] = a;
                y[j] = a * inverse[j];
                a * y[j]
            })
        };
        old_beta = beta;
        beta = next.max(0.0).sqrt();
        // The QR factorisation of the tridiagonal matrix, one Givens rotation per iteration.
        let old_epsilon = epsilon;
        let delta = cs * dbar + sn * alpha;
        let gbar = sn * dbar - cs * alpha;
        epsilon = sn * beta;
        dbar = -cs * beta;
        let gamma = gbar.hypot(beta);
        if !(gamma > 0.0 && gamma.is_finite()) {
            break;
        }
        (cs, sn) = (gbar / gamma, beta / gamma);
        let phi = cs * phibar;
        phibar *= sn;
        // The search direction w (from the last two), the solution, the next v.
        let scale = if beta > 0.0 { 1.0 / beta } else { 0.0 };
        let over = 1.0 / gamma;
        let (v, w, w1, x, y) = (&mut v[..m], &mut w[..m], &mut w1[..m], &mut x[..m], &y[..m]);
        for j in 0..m {
            let wj = (v[j] - old_epsilon * w1[j] - delta * w[j]) * over;
            w1[j] = w[j];
            w[j] = wj;
            x[j] += phi * wj;
            v[j] = y[j] * scale;
        }
        if beta == 0.0 {
            break;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of `n` nodes in 3D with a distance-like row per neighbour pair and per
    /// second neighbour, hard and compliant, with residuals.
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
        let inv_mass = (0..n).map(|i| 1.0 / (1.0 + (i % 4) as f64)).collect();
        (rows, inv_mass)
    }

    /// The residual's norm in the preconditioner's metric, which MINRES minimises.
    fn residual_after(rows: &StepRows, mobility: &[Mobility], x: &[f64]) -> f64 {
        let rounded: Vec<(f64, DVec3)> = mobility.iter().map(Mobility::rounded).collect();
        let live = vec![true; rows.len()];
        let diagonal = rows.diagonals(mobility).0;
        let mut q = vec![0.0; rows.len()];
        let mut u = vec![DVec3::ZERO; mobility.len()];
        rows.product(&rounded, &live, x, &mut u, &mut q);
        let terms = rows
            .residual
            .iter()
            .zip(&q)
            .zip(&diagonal)
            .zip(&rows.softness);
        terms
            .map(|(((r, q), d), s)| (r - q).powi(2) / (d + s))
            .sum::<f64>()
            .sqrt()
    }

    #[test]
    fn minres_solves_the_step_system_and_never_lets_its_residual_grow() {
        let (rows, inv_mass) = chain(40);
        let mobility: Vec<Mobility> = inv_mass.iter().map(|&w| Mobility::free(w)).collect();
        let start = residual_after(&rows, &mobility, &vec![0.0; rows.len()]);
        let mut last = start;
        for iterations in [1, 2, 4, 8, 16, 32] {
            let x = minres(&rows, &mobility, iterations);
            let r = residual_after(&rows, &mobility, &x);
            assert!(
                r <= last * (1.0 + 1e-9),
                "{iterations} iterations: {r} after {last}"
            );
            last = r;
        }
        let x = minres(&rows, &mobility, 200);
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
        let x = minres(&rows, &mobility, 50);
        assert_eq!(x[0], 0.0);
        assert!(x[1..].iter().any(|&d| d != 0.0));
    }
}
