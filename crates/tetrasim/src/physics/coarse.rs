//! The coarse level of the finite elements' two-level preconditioner (docs/PHYSICS.md,
//! "A coarse level for the conjugate gradients"). Block-Jacobi conjugate gradients carry a
//! load one ring of nodes per iteration; a body many rings tall does not feel its support
//! within a step's ten. The coarse level moves each aggregate of nodes (a run of a body's
//! free nodes along a Morton curve) as a rigid body, six modes per aggregate, and solves the
//! step's system restricted to those modes exactly: `P A_c^-1 P^T r` is added to the
//! block-Jacobi term (an additive two-level preconditioner, symmetric positive definite as
//! the conjugate gradients need). `A_c = P^T A P` is assembled at a linearisation from
//! the nodes' blocks and each tet's stiffness times the modes at its corners, and factored
//! by a dense Cholesky factorisation (at most [`MOST_AGGREGATES`] x 6 unknowns), once every
//! [`COARSE_REBUILD_STEPS`] steps (the steps between and a later linearisation within a
//! step keep it: a preconditioner need not be exact, only symmetric positive definite).
//! Nodes in contact are left out of the correction ([`touching`]).

use glam::DVec3;
use tetmesh::mesh::order::morton_code;

use super::{Sym3, Vector};

/// The most aggregates: the coarse system has six unknowns per aggregate and is factored
/// densely when built.
pub const MOST_AGGREGATES: usize = 64;

/// The fewest free nodes per aggregate (a smaller one is nearly one tet, which block-Jacobi
/// already handles).
pub const FEWEST_AGGREGATE_NODES: usize = 64;

/// Time steps between builds of the coarse level: a step whose index (counted from the
/// backend's start) is a multiple of it assembles and factors `A_c` anew at its first
/// linearisation, the others keep the last one ([`rebuilds`]; docs/PHYSICS.md, "The coarse
/// level kept for ten steps"). A preconditioner need only be symmetric positive definite;
/// on the horse drop one kept for 10 steps measured better than one built every step, at
/// three quarters of the cost.
pub const COARSE_REBUILD_STEPS: u64 = 10;

/// Whether step `step` (its index from the backend's start) builds the coarse level anew:
/// every [`COARSE_REBUILD_STEPS`], and whenever there is none yet (`built` false).
#[inline]
pub fn rebuilds(step: u64, built: bool) -> bool {
    !built || step % COARSE_REBUILD_STEPS == 0
}

/// No aggregate: a pinned node's entry in [`Aggregates::of`].
pub const NO_AGGREGATE: u32 = u32::MAX;

/// The free nodes grouped into aggregates, each within one object and spatially compact.
#[derive(Debug, Clone, Default)]
pub struct Aggregates {
    /// Per node: its aggregate, or [`NO_AGGREGATE`] for a pinned node.
    pub of: Vec<u32>,
    /// Per aggregate: its nodes, along the Morton curve of the rest positions.
    pub members: Vec<Vec<u32>>,
    /// Per aggregate: the tets with a corner among its nodes, in order.
    pub tets: Vec<Vec<u32>>,
}

impl Aggregates {
    /// Groups the free nodes (`inv_mass > 0`) of each object (`objects`: node ranges'
    /// boundaries) into runs of equal length along the Morton curve of `positions`, at
    /// most [`MOST_AGGREGATES`] in all and none under [`FEWEST_AGGREGATE_NODES`] nodes
    /// unless its object is that small.
    pub fn group(
        positions: &[DVec3],
        inv_mass: &[f64],
        objects: &[u32],
        tets: &[[u32; 4]],
    ) -> Self {
        let free = inv_mass.iter().filter(|&&w| w > 0.0).count();
        let per = free
            .div_ceil(MOST_AGGREGATES)
            .max(FEWEST_AGGREGATE_NODES)
            .max(1);
        let mut of = vec![NO_AGGREGATE; positions.len()];
        let mut members = Vec::new();
        for range in objects.windows(2) {
            let mut nodes: Vec<u32> = (range[0]..range[1])
                .filter(|&i| inv_mass[i as usize] > 0.0)
                .collect();
            if nodes.is_empty() {
                continue;
            }
            let (lo, hi) = nodes.iter().fold(
                (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
                |(lo, hi), &i| {
                    let p = positions[i as usize];
                    (lo.min(p), hi.max(p))
                },
            );
            nodes.sort_by_key(|&i| morton_code(positions[i as usize], lo, hi));
            let count = nodes.len().div_ceil(per);
            let size = nodes.len().div_ceil(count);
            for chunk in nodes.chunks(size) {
                for &i in chunk {
                    of[i as usize] = members.len() as u32;
                }
                members.push(chunk.to_vec());
            }
        }
        let mut touching = vec![Vec::new(); members.len()];
        for (t, tet) in tets.iter().enumerate() {
            for (c, &k) in tet.iter().enumerate() {
                let a = of[k as usize];
                if a != NO_AGGREGATE && !tet[..c].iter().any(|&j| of[j as usize] == a) {
                    touching[a as usize].push(t as u32);
                }
            }
        }
        Aggregates {
            of,
            members,
            tets: touching,
        }
    }

    /// The number of aggregates.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// No free node: no coarse level.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }
}

/// The coarse system of one linearisation: each aggregate's centre and size (its modes are
/// the translations and the rotations about the centre scaled by one over the size) and
/// `A_c`, lower-triangular Cholesky factor once [`CoarseSpace::factor`] ran.
#[derive(Debug, Clone, Default)]
pub struct CoarseSpace {
    centre: Vec<DVec3>,
    size: Vec<f64>,
    matrix: Vec<f64>,
    /// Per unknown: whether its pivot was kept (a mode the fine system does not see, such
    /// as a rotation of an aggregate of nodes on one line, is left out).
    kept: Vec<bool>,
}

impl CoarseSpace {
    /// The modes of `aggregates` with node `k` at `x(k)`, and a zero `A_c`.
    pub fn new(aggregates: &Aggregates, x: impl Fn(usize) -> DVec3) -> Self {
        let (centre, size): (Vec<DVec3>, Vec<f64>) = (aggregates.members.iter())
            .map(|nodes| {
                let n = nodes.len().max(1) as f64;
                let centre = nodes.iter().map(|&i| x(i as usize)).sum::<DVec3>() / n;
                let spread = (nodes.iter())
                    .map(|&i| (x(i as usize) - centre).length_squared())
                    .sum::<f64>()
                    / n;
                let size = if spread > 0.0 { spread.sqrt() } else { 1.0 };
                (centre, size)
            })
            .unzip();
        let unknowns = 6 * centre.len();
        CoarseSpace {
            centre,
            size,
            matrix: vec![0.0; unknowns * unknowns],
            kept: vec![false; unknowns],
        }
    }

    /// The number of unknowns (six per aggregate).
    pub fn unknowns(&self) -> usize {
        self.kept.len()
    }

    /// Whether it has been built (a space of no aggregate never is).
    pub fn is_built(&self) -> bool {
        !self.kept.is_empty()
    }

    /// Its state as numbers, for a checkpoint: the number of aggregates, their centres and
    /// sizes, the kept pivots (1 or 0) and the factored matrix.
    pub fn to_values(&self) -> Vec<f64> {
        let mut values = vec![self.centre.len() as f64];
        values.extend(self.centre.iter().flat_map(|c| c.to_array()));
        values.extend(&self.size);
        values.extend(self.kept.iter().map(|&k| if k { 1.0 } else { 0.0 }));
        values.extend(&self.matrix);
        values
    }

    /// The space [`CoarseSpace::to_values`] wrote, of `aggregates` aggregates; `None` when
    /// the numbers do not describe one of that many.
    pub fn from_values(values: &[f64], aggregates: usize) -> Option<Self> {
        let n = 6 * aggregates;
        let expected = 1 + 4 * aggregates + n + n * n;
        if values.len() != expected || values[0] != aggregates as f64 {
            return None;
        }
        let (centre, rest) = values[1..].split_at(3 * aggregates);
        let (size, rest) = rest.split_at(aggregates);
        let (kept, matrix) = rest.split_at(n);
        if kept.iter().any(|&k| k != 0.0 && k != 1.0) {
            return None;
        }
        Some(CoarseSpace {
            centre: centre.chunks_exact(3).map(DVec3::from_slice).collect(),
            size: size.to_vec(),
            matrix: matrix.to_vec(),
            kept: kept.iter().map(|&k| k == 1.0).collect(),
        })
    }

    /// Aggregate `a`'s six modes at `x`: the three translations, then the rotations about
    /// its centre per unit of its size.
    #[inline]
    pub fn modes(&self, a: usize, x: DVec3) -> [DVec3; 6] {
        let r = (x - self.centre[a]) / self.size[a];
        [
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
            DVec3::X.cross(r),
            DVec3::Y.cross(r),
            DVec3::Z.cross(r),
        ]
    }

    /// Adds to `columns` (aggregate `a`'s six columns of `A_c`, column-major, all rows) a
    /// free node's own block of the fine matrix (`m/dt^2 I` and its contact's stiffening):
    /// a node of aggregate `a` at `x`.
    pub fn add_node(&self, a: usize, x: DVec3, block: Sym3<f64>, columns: &mut [f64]) {
        let n = self.unknowns();
        let modes = self.modes(a, x);
        for (k, mk) in modes.iter().enumerate() {
            let applied = sym3_times(block, *mk);
            for (l, ml) in modes.iter().enumerate() {
                columns[k * n + 6 * a + l] += ml.dot(applied);
            }
        }
    }

    /// Adds to `columns` (aggregate `a`'s six columns) a tet's share: `corners` are its
    /// nodes' aggregates (`None`: pinned) and positions, `product(d)` the fine matrix's tet
    /// part times corner moves `d` (each corner's row scaled as the fine product scales
    /// it). A tet whose four corners are free and in `a` gets nothing from the translations
    /// (its strain does not change under them), and its rows are read off directly: the
    /// rotation `e_l x r` against `y` is `(r x y)_l`.
    pub fn add_tet(
        &self,
        a: usize,
        corners: [(Option<usize>, DVec3); 4],
        mut product: impl FnMut([DVec3; 4]) -> [DVec3; 4],
        columns: &mut [f64],
    ) {
        let n = self.unknowns();
        if corners.iter().all(|c| c.0 == Some(a)) {
            // The common case, the rotations alone, without the modes' tables.
            let r = corners.map(|(_, x)| (x - self.centre[a]) / self.size[a]);
            for (k, axis) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
                let applied = product(r.map(|r| axis.cross(r)));
                let column = &mut columns[(k + 3) * n + 6 * a..(k + 3) * n + 6 * a + 6];
                for (y, r) in applied.iter().zip(&r) {
                    let turn = r.cross(*y);
                    for (entry, value) in column
                        .iter_mut()
                        .zip([y.x, y.y, y.z, turn.x, turn.y, turn.z])
                    {
                        *entry += value;
                    }
                }
            }
            return;
        }
        let modes = corners.map(|(b, x)| b.map(|b| self.modes(b, x)));
        for k in 0..6 {
            let moves: [DVec3; 4] = std::array::from_fn(|j| match (corners[j].0, &modes[j]) {
                (Some(b), Some(m)) if b == a => m[k],
                _ => DVec3::ZERO,
            });
            let applied = product(moves);
            let column = &mut columns[k * n..(k + 1) * n];
            for (j, (b, m)) in corners.iter().zip(&modes).enumerate() {
                if let (Some(b), Some(m)) = (b.0, m) {
                    for (l, ml) in m.iter().enumerate() {
                        column[6 * b + l] += ml.dot(applied[j]);
                    }
                }
            }
        }
    }

    /// Takes `A_c` from its columns (`columns`: column-major, each aggregate's six in
    /// turn, as [`CoarseSpace::add_node`] and [`CoarseSpace::add_tet`] filled them) and
    /// factors it ([`CoarseSpace::factor`]).
    pub fn assemble(&mut self, columns: &[f64]) {
        let n = self.unknowns();
        for row in 0..n {
            for column in 0..=row {
                self.matrix[row * n + column] = columns[column * n + row];
            }
        }
        self.factor();
    }

    /// Factors `A_c` (its lower triangle) as `L L^T`, leaving out unknowns whose pivot
    /// falls below `1e-10` of their diagonal (modes the fine matrix does not see).
    fn factor(&mut self) {
        let n = self.unknowns();
        let a = &mut self.matrix;
        for j in 0..n {
            let diagonal = a[j * n + j];
            let mut d = diagonal;
            for k in 0..j {
                d -= a[j * n + k] * a[j * n + k];
            }
            let kept = d.is_finite() && d > 1e-10 * diagonal.abs();
            if !kept {
                self.kept[j] = false;
                for i in j..n {
                    a[i * n + j] = 0.0;
                }
                continue;
            }
            self.kept[j] = true;
            let pivot = d.sqrt();
            a[j * n + j] = pivot;
            for i in j + 1..n {
                let mut s = a[i * n + j];
                for k in 0..j {
                    s -= a[i * n + k] * a[j * n + k];
                }
                a[i * n + j] = s / pivot;
            }
        }
    }

    /// Solves `A_c u = b` in place with the factor ([`CoarseSpace::factor`]).
    pub fn solve(&self, b: &mut [f64]) {
        let (n, l) = (self.unknowns(), &self.matrix);
        for i in 0..n {
            if !self.kept[i] {
                b[i] = 0.0;
                continue;
            }
            let mut s = b[i];
            for k in 0..i {
                s -= l[i * n + k] * b[k];
            }
            b[i] = s / l[i * n + i];
        }
        for i in (0..n).rev() {
            if !self.kept[i] {
                b[i] = 0.0;
                continue;
            }
            let mut s = b[i];
            for k in i + 1..n {
                s -= l[k * n + i] * b[k];
            }
            b[i] = s / l[i * n + i];
        }
    }

    /// Node `k`'s share of `P^T r` (`r` its residual, `x` its position, `a` its aggregate):
    /// aggregate `a`'s six entries.
    #[inline]
    pub fn restrict(&self, a: usize, x: DVec3, r: DVec3) -> [f64; 6] {
        self.modes(a, x).map(|m| m.dot(r))
    }

    /// The coarse correction `P u` at a node of aggregate `a` at `x`.
    #[inline]
    pub fn prolong(&self, a: usize, x: DVec3, u: &[f64]) -> DVec3 {
        let u = &u[6 * a..6 * a + 6];
        let turn = DVec3::new(u[3], u[4], u[5]);
        DVec3::new(u[0], u[1], u[2]) + turn.cross(x - self.centre[a]) / self.size[a]
    }
}

/// Whether a node is left out of the coarse correction (its restriction and
/// prolongation; the coarse matrix keeps it, with its contact's stiffening): one the floor
/// pushes (`floor`: `Some(true)`), a collider pushes (`pushed` not zero) or a contact holds
/// (`held` not zero), at the latest linearisation. A contact's solve overrides the forces
/// the conjugate gradients give such a node, so a coarse move that carries it along is not
/// the move the step makes: with them in, a ball pressed into a block diverged within 74
/// frames; left out of the matrix too, within 70.
pub fn touching<V: Vector>(floor: Option<bool>, pushed: V, held: V) -> bool {
    floor == Some(true) || pushed != V::ZERO || held != V::ZERO
}

/// A symmetric 3x3 matrix (`[xx, yy, zz, xy, yz, xz]`) times `v`.
fn sym3_times(m: Sym3<f64>, v: DVec3) -> DVec3 {
    DVec3::new(
        m[0] * v.x + m[3] * v.y + m[5] * v.z,
        m[3] * v.x + m[1] * v.y + m[4] * v.z,
        m[5] * v.x + m[4] * v.y + m[2] * v.z,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense symmetric positive definite system is solved exactly, and the unknown of a
    /// zero row is left out rather than failing.
    #[test]
    fn the_factor_solves_and_leaves_out_a_mode_nothing_sees() {
        let aggregates = Aggregates {
            of: vec![0],
            members: vec![vec![0]],
            tets: vec![Vec::new()],
        };
        let mut coarse = CoarseSpace::new(&aggregates, |_| DVec3::ZERO);
        let n = coarse.unknowns();
        // A = diag(1..6) + 0.1 everywhere, but unknown 4 decoupled and zero.
        let a = |i: usize, j: usize| {
            if i == 4 || j == 4 {
                0.0
            } else {
                0.1 + if i == j { (i + 1) as f64 } else { 0.0 }
            }
        };
        let columns: Vec<f64> = (0..n * n).map(|k| a(k % n, k / n)).collect();
        coarse.assemble(&columns);
        let x = [1.0, -2.0, 0.5, 3.0, 0.0, -1.0];
        let mut b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| a(i, j) * x[j]).sum())
            .collect();
        coarse.solve(&mut b);
        for (got, want) in b.iter().zip(x) {
            assert!((got - want).abs() < 1e-12, "{b:?}");
        }
        assert!(!coarse.kept[4]);
    }

    /// Nodes of two objects never share an aggregate, pinned nodes have none, and every
    /// free node has one.
    #[test]
    fn aggregates_stay_within_objects_and_skip_pinned_nodes() {
        let positions: Vec<DVec3> = (0..200).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
        let mut inv_mass = vec![1.0; 200];
        inv_mass[3] = 0.0;
        let aggregates = Aggregates::group(&positions, &inv_mass, &[0, 150, 200], &[]);
        assert_eq!(aggregates.of[3], NO_AGGREGATE);
        for (a, nodes) in aggregates.members.iter().enumerate() {
            let first = nodes[0] < 150;
            assert!(nodes.iter().all(|&i| (i < 150) == first));
            assert!(nodes.iter().all(|&i| aggregates.of[i as usize] == a as u32));
        }
        assert_eq!(aggregates.members.iter().map(Vec::len).sum::<usize>(), 199);
    }

    /// A rigid translation or rotation of an aggregate is carried exactly: restricted,
    /// solved and prolonged through a mass-only fine matrix, the residual `M v` of a rigid
    /// velocity field `v` comes back as `v`.
    #[test]
    fn a_rigid_motion_comes_back_through_the_coarse_level() {
        let positions: Vec<DVec3> = (0..160)
            .map(|i| DVec3::new((i % 4) as f64, ((i / 4) % 5) as f64, (i / 20) as f64) * 0.1)
            .collect();
        let aggregates = Aggregates::group(&positions, &[1.0; 160], &[0, 160], &[]);
        assert!(aggregates.len() > 1, "{}", aggregates.len());
        let mut coarse = CoarseSpace::new(&aggregates, |k| positions[k]);
        let mass = 2.0;
        let n = coarse.unknowns();
        let mut columns = vec![0.0; n * n];
        for (i, &x) in positions.iter().enumerate() {
            let a = aggregates.of[i] as usize;
            let block = [mass, mass, mass, 0.0, 0.0, 0.0];
            coarse.add_node(a, x, block, &mut columns[6 * a * n..6 * (a + 1) * n]);
        }
        coarse.assemble(&columns);
        let velocity = |x: DVec3| DVec3::new(0.3, -1.0, 0.2) + DVec3::new(0.5, 2.0, -1.0).cross(x);
        let mut u = vec![0.0; coarse.unknowns()];
        for (i, &x) in positions.iter().enumerate() {
            let a = aggregates.of[i] as usize;
            let share = coarse.restrict(a, x, velocity(x) * mass);
            u[6 * a..6 * a + 6]
                .iter_mut()
                .zip(share)
                .for_each(|(u, s)| *u += s);
        }
        coarse.solve(&mut u);
        for (i, &x) in positions.iter().enumerate() {
            let back = coarse.prolong(aggregates.of[i] as usize, x, &u);
            assert!(
                (back - velocity(x)).length() < 1e-12,
                "{back} {}",
                velocity(x)
            );
        }
    }

    /// A tet inside one aggregate takes the shortcut (the rotations' columns, read off
    /// directly); its entries equal `m_l . K m_k` summed over the corners, as the general
    /// path computes them, with a real stiffness (a stretched, sheared tet).
    #[test]
    fn the_inside_shortcut_equals_the_modes_products() {
        use crate::physics::{elastic_linearise, elastic_product, shape_gradients, ElasticTet};
        let rest = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z].map(|p| p * 0.1);
        let tet = ElasticTet {
            shape: shape_gradients(rest).unwrap(),
            volume: 0.1f64.powi(3) / 6.0,
            mu: 1e5,
            lambda: 4e5,
            alpha: 1.25,
        };
        let now = [
            DVec3::new(0.01, 0.0, 0.0),
            DVec3::new(0.13, 0.01, 0.0),
            DVec3::new(0.02, 0.09, 0.01),
            DVec3::new(0.0, 0.02, 0.11),
        ];
        let linear = elastic_linearise(&tet, now);
        let aggregates = Aggregates {
            of: vec![0; 4],
            members: vec![vec![0, 1, 2, 3]],
            tets: vec![vec![0]],
        };
        let coarse = CoarseSpace::new(&aggregates, |k| now[k] + DVec3::splat(0.3));
        let n = coarse.unknowns();
        let mut columns = vec![0.0; 6 * n];
        let corners = now.map(|x| (Some(0), x));
        coarse.add_tet(
            0,
            corners,
            |d| elastic_product(&tet, &linear, d),
            &mut columns,
        );
        let modes = now.map(|x| coarse.modes(0, x));
        for k in 3..6 {
            let applied = elastic_product(&tet, &linear, modes.map(|m| m[k]));
            for l in 0..6 {
                let want: f64 = (0..4).map(|c| modes[c][l].dot(applied[c])).sum();
                let got = columns[k * n + l];
                assert!(
                    (got - want).abs() <= 1e-9 * want.abs().max(1.0),
                    "{k} {l}: {got} {want}"
                );
            }
        }
        assert!(columns[5 * n + 5].abs() > 1.0, "a turn strains the tet");
    }
}
