//! A step's linearised constraints as rows of one symmetric system, for the MINRES solve
//! both CPU backends run after the sweeps (docs/PHYSICS.md, "MINRES after the sweeps"; the
//! solver is `backend::cpu::minres`).
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
//! so far ([`compliant_residual`]). [`StepRows`] holds `J`, `S` and `r`, [`NodeRows`] the
//! transpose of `J` (each node's rows, for the product's pass to the nodes), [`Mobility`]
//! each node's `W`.
//!
//! The floor is one-sided and the sweeps have found who touches it: a node the floor (or a
//! collider, or a grab) pushes is held, its motion along the push taken out of `W`. A
//! constraint that holding leaves less than [`HELD_SHARE`] of its mobility is left to the
//! sweeps: its row would ask the held nodes to move, and near that singularity the solve's
//! forces grow without bound (the horse's hooves at impact).

use std::ops::Range;

use glam::DVec3;

use super::{held_direction, Real, Vector};

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
        let held = held_direction(floor, collider);
        let inv_mass = if grabbed { 0.0 } else { inv_mass };
        Mobility { inv_mass, held }
    }

    /// The velocity change per step^2 a force `u` gives the node.
    #[inline]
    fn apply(&self, u: DVec3) -> DVec3 {
        (u - self.held * self.held.dot(u)) * self.inv_mass
    }

    /// The same in precision `V`.
    pub fn rounded<V: Vector>(&self) -> Held<V> {
        Held {
            inv_mass: V::Real::from_f64(self.inv_mass),
            held: V::from_dvec3(self.held),
        }
    }
}

/// A [`Mobility`] in precision `V` (the product's).
#[derive(Debug, Clone, Copy)]
pub struct Held<V: Vector> {
    inv_mass: V::Real,
    held: V,
}

impl<V: Vector> Held<V> {
    /// The velocity change per step^2 a force `u` gives the node ([`Mobility`]'s).
    #[inline]
    pub fn apply(&self, u: V) -> V {
        self.unheld(u) * self.inv_mass
    }

    /// Force `u` less its part along the held direction.
    #[inline]
    pub fn unheld(&self, u: V) -> V {
        u - self.held * self.held.dot(u)
    }
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
    fn clear(&mut self) {
        self.row.clear();
        self.nodes.clear();
        self.grads.clear();
    }

    /// Adds row `row` if it has `K` entries; gives it back if not.
    fn take(&mut self, row: u32, nodes: &[u32], grads: &[V]) -> bool {
        match (<[u32; K]>::try_from(nodes), <[V; K]>::try_from(grads)) {
            (Ok(n), Ok(g)) => {
                self.row.push(row);
                self.nodes.push(n);
                self.grads.push(g);
                true
            }
            _ => false,
        }
    }

    /// Each entry's row, node and gradient, in row order.
    fn each(&self, mut f: impl FnMut(u32, u32, V)) {
        for ((&j, n), g) in self.row.iter().zip(&self.nodes).zip(&self.grads) {
            for k in 0..K {
                f(j, n[k], g[k]);
            }
        }
    }

    /// `q[j - rows.start] += grad . u` over the nodes of each of its rows `j` in `rows`.
    fn gather(&self, rows: Range<usize>, u: &[V], q: &mut [f64]) {
        let (from, to) = indices_within(&self.row, &rows);
        let items = (self.row[from..to].iter())
            .zip(&self.nodes[from..to])
            .zip(&self.grads[from..to]);
        for ((&j, n), g) in items {
            let mut sum = V::Real::ZERO;
            for k in 0..K {
                sum += g[k].dot(u[n[k] as usize]);
            }
            q[j as usize - rows.start] += sum.to_f64();
        }
    }
}

/// Rows of two entries whose gradients are opposite (`grad_b = -grad_a`: springs and
/// distance constraints, whose value depends on `x_a - x_b` only), the gradient kept once.
#[derive(Debug, Clone)]
struct Opposed<V> {
    row: Vec<u32>,
    nodes: Vec<[u32; 2]>,
    grads: Vec<V>,
}

impl<V> Default for Opposed<V> {
    fn default() -> Self {
        Opposed {
            row: Vec::new(),
            nodes: Vec::new(),
            grads: Vec::new(),
        }
    }
}

impl<V: Vector> Opposed<V> {
    /// Adds row `row` if it has two entries of exactly opposite gradients; gives it back
    /// if not.
    fn take(&mut self, row: u32, nodes: &[u32], grads: &[V]) -> bool {
        match (nodes, grads) {
            (&[a, b], &[ga, gb]) if gb == -ga => {
                self.row.push(row);
                self.nodes.push([a, b]);
                self.grads.push(ga);
                true
            }
            _ => false,
        }
    }

    fn clear(&mut self) {
        self.row.clear();
        self.nodes.clear();
        self.grads.clear();
    }

    /// Each entry's row, node and gradient, in row order.
    fn each(&self, mut f: impl FnMut(u32, u32, V)) {
        for ((&j, &[a, b]), &g) in self.row.iter().zip(&self.nodes).zip(&self.grads) {
            f(j, a, g);
            f(j, b, V::ZERO - g);
        }
    }

    /// `q[j - rows.start] += grad_a . (u_a - u_b)` for each of its rows `j` in `rows`.
    fn gather(&self, rows: Range<usize>, u: &[V], q: &mut [f64]) {
        let (from, to) = indices_within(&self.row, &rows);
        let items = (self.row[from..to].iter())
            .zip(&self.nodes[from..to])
            .zip(&self.grads[from..to]);
        for ((&j, &[a, b]), g) in items {
            q[j as usize - rows.start] += g.dot(u[a as usize] - u[b as usize]).to_f64();
        }
    }
}

/// The positions in `ascending` of the values in `range`.
fn indices_within(ascending: &[u32], range: &Range<usize>) -> (usize, usize) {
    let at = |v: usize| ascending.partition_point(|&r| (r as usize) < v);
    (at(range.start), at(range.end))
}

/// A step's constraint rows: each one's nodes, its gradient on each, its softness and its
/// residual at the forces so far. Rows of two entries with opposite gradients
/// (springs and distance constraints), other rows of two and of four (tets) are kept apart from the wide ones (the global volume constraints),
/// so that the solve's products run fixed-size loops. The gradients and the product's node
/// sums are kept in precision `V` (the backend's); the solve's vectors are `f64`.
#[derive(Debug, Clone)]
pub struct StepRows<V = DVec3> {
    opposed: Opposed<V>,
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
            opposed: Opposed::default(),
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
    pub fn push(&mut self, nodes: &[u32], grads: &[V], softness: f64, residual: f64) {
        debug_assert_eq!(nodes.len(), grads.len());
        let row = self.softness.len() as u32;
        let taken = self.opposed.take(row, nodes, grads)
            || self.pairs.take(row, nodes, grads)
            || self.tets.take(row, nodes, grads);
        if !taken {
            self.wide_row.push(row);
            self.wide_nodes.extend_from_slice(nodes);
            self.wide_grads.extend_from_slice(grads);
            self.wide_first.push(self.wide_nodes.len());
        }
        self.softness.push(softness);
        self.residual.push(residual);
    }

    /// No rows, the memory kept for the next step's.
    pub fn clear(&mut self) {
        self.opposed.clear();
        self.pairs.clear();
        self.tets.clear();
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

    /// Each row's softness `s`.
    pub fn softness(&self) -> &[f64] {
        &self.softness
    }

    /// Each row's residual `r` at the forces so far.
    pub fn residual(&self) -> &[f64] {
        &self.residual
    }

    /// Every entry's row, node and gradient: the rows of two entries, then of four, then
    /// the wide ones, each kind in row order.
    pub fn each(&self, mut f: impl FnMut(u32, u32, V)) {
        self.opposed.each(&mut f);
        self.pairs.each(&mut f);
        self.tets.each(&mut f);
        for (k, &j) in self.wide_row.iter().enumerate() {
            let range = self.wide_first[k]..self.wide_first[k + 1];
            for (&i, &g) in self.wide_nodes[range.clone()]
                .iter()
                .zip(&self.wide_grads[range])
            {
                f(j, i, g);
            }
        }
    }

    /// `q[j - rows.start] += sum_k grad_k . u_k` over the nodes `k` of each row `j` in
    /// `rows` (the product `J u`, in the rows' precision).
    pub fn gather(&self, rows: Range<usize>, u: &[V], q: &mut [f64]) {
        self.opposed.gather(rows.clone(), u, q);
        self.pairs.gather(rows.clone(), u, q);
        self.tets.gather(rows.clone(), u, q);
        let (from, to) = indices_within(&self.wide_row, &rows);
        for k in from..to {
            let range = self.wide_first[k]..self.wide_first[k + 1];
            let entries = self.wide_nodes[range.clone()]
                .iter()
                .zip(&self.wide_grads[range]);
            let sum = entries.fold(V::Real::ZERO, |a, (&i, &g)| a + g.dot(u[i as usize]));
            q[self.wide_row[k] as usize - rows.start] += sum.to_f64();
        }
    }

    /// Whether `other` has the same rows on the same nodes (their gradients, softness and
    /// residuals aside): then the transpose of one is the other's.
    pub fn same_shape(&self, other: &Self) -> bool {
        self.len() == other.len()
            && (&self.opposed.row, &self.opposed.nodes)
                == (&other.opposed.row, &other.opposed.nodes)
            && (&self.pairs.row, &self.pairs.nodes) == (&other.pairs.row, &other.pairs.nodes)
            && (&self.tets.row, &self.tets.nodes) == (&other.tets.row, &other.tets.nodes)
            && (&self.wide_row, &self.wide_first, &self.wide_nodes)
                == (&other.wide_row, &other.wide_first, &other.wide_nodes)
    }

    /// The gradient of entry `e`, entries numbered in the order of [`StepRows::each`].
    #[inline]
    pub fn entry_grad(&self, e: u32) -> V {
        let mut e = e as usize;
        if e < 2 * self.opposed.grads.len() {
            let g = self.opposed.grads[e / 2];
            return if e % 2 == 0 { g } else { V::ZERO - g };
        }
        e -= 2 * self.opposed.grads.len();
        if e < 2 * self.pairs.grads.len() {
            return self.pairs.grads[e / 2][e % 2];
        }
        e -= 2 * self.pairs.grads.len();
        if e < 4 * self.tets.grads.len() {
            return self.tets.grads[e / 4][e % 4];
        }
        self.wide_grads[e - 4 * self.tets.grads.len()]
    }

    /// The preconditioner of the rows `rows`, each node moving with its `mobility`:
    /// `out[j - rows.start] = 1 / (sum_k grad_k . M_k grad_k + s)`, or 0 for a row the
    /// holding leaves less than [`HELD_SHARE`] of its mobility (or none), which is left
    /// to the sweeps.
    pub fn preconditioner(&self, rows: Range<usize>, mobility: &[Mobility], out: &mut [f64]) {
        let start = rows.start;
        let (mut held, mut free) = (vec![0.0; rows.len()], vec![0.0; rows.len()]);
        let mut add = |j: u32, i: u32, g: V| {
            let (g, mobility) = (g.to_dvec3(), &mobility[i as usize]);
            held[j as usize - start] += g.dot(mobility.apply(g));
            free[j as usize - start] += g.length_squared() * mobility.inv_mass;
        };
        let (from, to) = indices_within(&self.opposed.row, &rows);
        for k in from..to {
            let (j, [a, b], g) = (
                self.opposed.row[k],
                self.opposed.nodes[k],
                self.opposed.grads[k],
            );
            add(j, a, g);
            add(j, b, V::ZERO - g);
        }
        let (from, to) = indices_within(&self.pairs.row, &rows);
        for k in from..to {
            for (&i, &g) in self.pairs.nodes[k].iter().zip(&self.pairs.grads[k]) {
                add(self.pairs.row[k], i, g);
            }
        }
        let (from, to) = indices_within(&self.tets.row, &rows);
        for k in from..to {
            for (&i, &g) in self.tets.nodes[k].iter().zip(&self.tets.grads[k]) {
                add(self.tets.row[k], i, g);
            }
        }
        let (from, to) = indices_within(&self.wide_row, &rows);
        for k in from..to {
            let range = self.wide_first[k]..self.wide_first[k + 1];
            for (&i, &g) in self.wide_nodes[range.clone()]
                .iter()
                .zip(&self.wide_grads[range])
            {
                add(self.wide_row[k], i, g);
            }
        }
        for (((out, held), free), &s) in
            (out.iter_mut().zip(held).zip(free)).zip(&self.softness[rows])
        {
            *out = match held > 0.0 && held >= HELD_SHARE * free {
                true => 1.0 / (held + s),
                false => 0.0,
            };
        }
    }

    /// The transpose of the rows over `nodes` nodes into `out`: each node's rows, in the
    /// order of [`StepRows::each`] (so that a node's sum over them adds in the same order
    /// whoever computes it), and the entries they are.
    pub fn transpose(&self, nodes: usize, out: &mut NodeRows) {
        let first = &mut out.first;
        first.clear();
        first.resize(nodes + 1, 0);
        self.each(|_, i, _| first[i as usize + 1] += 1);
        for i in 0..nodes {
            first[i + 1] += first[i];
        }
        let entries = first[nodes] as usize;
        out.row.resize(entries, 0);
        out.entry.resize(entries, 0);
        out.next.clear();
        out.next.extend_from_slice(&first[..nodes]);
        let NodeRows {
            row, entry, next, ..
        } = out;
        let mut e = 0;
        self.each(|j, i, _| {
            let t = next[i as usize] as usize;
            next[i as usize] += 1;
            row[t] = j;
            entry[t] = e;
            e += 1;
        });
    }
}

/// The rows of [`StepRows`] by node (the shape of its transpose `J^T`): node `i`'s
/// entries are `first[i]..first[i + 1]`, each a row and the entry of the rows it is.
/// Their gradients are kept apart ([`NodeRows::sum`]), since the shape stays from step to
/// step and they do not.
#[derive(Debug, Clone)]
pub struct NodeRows {
    first: Vec<u32>,
    row: Vec<u32>,
    entry: Vec<u32>,
    /// Scratch of [`StepRows::transpose`]: each node's next free entry.
    next: Vec<u32>,
}

impl Default for NodeRows {
    fn default() -> Self {
        NodeRows {
            first: vec![0],
            row: Vec::new(),
            entry: Vec::new(),
            next: Vec::new(),
        }
    }
}

impl NodeRows {
    /// The number of nodes.
    pub fn nodes(&self) -> usize {
        self.first.len() - 1
    }

    /// The positions of the entries of nodes `nodes`.
    pub fn entries_of(&self, nodes: Range<usize>) -> Range<usize> {
        self.first[nodes.start] as usize..self.first[nodes.end] as usize
    }

    /// The entry of [`StepRows`] (numbered as [`StepRows::entry_grad`]) at each position
    /// `range`.
    pub fn entries(&self, range: Range<usize>) -> &[u32] {
        &self.entry[range]
    }

    /// `sum grad p[row]` over node `i`'s rows (its share of `J^T p`, in precision `V`),
    /// `grads` each position's gradient.
    #[inline(always)]
    pub fn sum<V: Vector>(&self, grads: &[V], i: usize, p: &[f64]) -> V {
        let range = self.first[i] as usize..self.first[i + 1] as usize;
        let entries = self.row[range.clone()].iter().zip(&grads[range]);
        let mut sum = V::ZERO;
        for (&j, &g) in entries {
            sum += g * V::Real::from_f64(p[j as usize]);
        }
        sum
    }
}
