#!/usr/bin/env python3
"""Linear-elastic finite-element reference for static cantilever beams (scikit-fem, P1 tets).

What it computes
----------------
A beam 0.6 m long along X with a 0.1 x 0.1 m section, meshed with exactly the same
tetrahedra, in exactly the same node order, as the engine's `box_tets(origin = 0, h, cells)`
(`grid_tets` in crates/tetmesh/src/mesh/grid.rs, ported below in `box_tets`). It solves
small-strain static linear elasticity on that mesh with scikit-fem:

  * element: `ElementVectorH1(ElementTetP1())` (linear displacement per tet);
  * stiffness: `skfem.models.elasticity.linear_elasticity(lambda, mu)` with
    mu = E / (2 (1 + nu)) and lambda = E nu / ((1 + nu) (1 - 2 nu));
  * load: body force rho * g along -Y (Y is up in the engine), rho = 1000 kg/m^3, g = 9.81 m/s^2;
  * support: all three displacement components fixed at every node with x == 0.

Cases written (E = 1e7 Pa): cells [12,2,2] h = 0.05 and cells [24,4,4] h = 0.025, each for
nu = 0.30 and nu = 0.45, to tests/data/fem/beam_{nx}x{ny}x{nz}_nu{0.30|0.45}.txt. The
[48,8,8] h = 0.0125 refinement for nu = 0.30 is also solved as a convergence cross-check of the
P1 solve and written to tests/data/fem/beam_48x8x8_nu0.30.txt (it is under 1.5 MB).

File format: '#' header lines (case, counts, versions, tip sag, beam-theory sags), then one
line per node in engine order: `x y z ux uy uz`, each written with Python's repr (the shortest
text that round-trips the f64 exactly). The tip sag is the mean uy over the nodes with
x == 0.6 (negative: downwards).

Beam theory (printed and put in the headers, for comparison only; positive = downward sag):
  * Euler-Bernoulli, cantilever under uniform load q = rho g A:  w_EB = q L^4 / (8 E I),
    with A = b^2, I = b^4 / 12 (b = 0.1 m), L = 0.6 m.
  * Timoshenko: w_T = w_EB + q L^2 / (2 kappa G A), the shear deflection of a cantilever under
    uniform load, with kappa = 5/6 (rectangular section) and G = mu.
The 3D model differs from both: P1 tets are too stiff in bending on coarse meshes (shear
locking), and more so as nu -> 0.5 (volumetric locking); the fully fixed end also stops the
Poisson contraction at the wall. Refined P1, and quadratic tets (`--convergence`), converge to a
3D answer about 1.5 % (nu = 0.30) and 3.5 % (nu = 0.45) below Timoshenko (1.4 % above and
0.4 % below EB).

Regenerate (from the repository root):
    python3 -m venv target/fem-py
    target/fem-py/bin/pip install scikit-fem==12.0.2 numpy==2.4.6 scipy==1.17.1
    target/fem-py/bin/python scripts/fem_reference.py
(`--out DIR` picks another output folder; `--no-fine` skips the 48x8x8 case. Runs in a few
seconds. `--convergence` also prints, without writing files, the P1 tip sags on [48,8,8] for
nu = 0.45 and on [96,16,16] for nu = 0.30, and quadratic-tet (P2, ElementTetP2) tip sags on
[12,2,2], [24,4,4] and [48,8,8] for both nu: the converged 3D answer the P1 data should approach. That takes about 4 minutes.)

Versions used for the committed data: Python 3.11.7, scikit-fem 12.0.2, numpy 2.4.6,
scipy 1.17.1.
"""

import argparse
import os
import sys
import time

import numpy as np
import scipy
import skfem
from skfem import Basis, ElementTetP1, ElementTetP2, ElementVectorH1, LinearForm, MeshTet, asm, condense, solve
from skfem.models.elasticity import linear_elasticity

# The six tets of a unit cube, as corner numbers x + 2y + 4z (grid.rs KUHN_TETS).
KUHN_TETS = [
    [0, 1, 3, 7],
    [0, 1, 5, 7],
    [0, 2, 3, 7],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 6, 7],
]

E = 1.0e7
RHO = 1000.0
G_ACC = 9.81
LENGTH = 0.6
SIDE = 0.1
KAPPA = 5.0 / 6.0


def tet_volume(p):
    """Signed volume, computed like geometry::tet_volume: (e1 x e2) . e3 / 6."""
    e1, e2, e3 = p[1] - p[0], p[2] - p[0], p[3] - p[0]
    return float(np.dot(np.cross(e1, e2), e3)) * (1.0 / 6.0)


def box_tets(h, cells, origin=(0.0, 0.0, 0.0)):
    """Port of grid_tets(origin, h, cells, |_| true): node ids in first-use order."""
    nx, ny, nz = cells
    origin = np.asarray(origin, dtype=np.float64)
    used = {}
    nodes = []
    tets = []
    for z in range(nz):
        for y in range(ny):
            for x in range(nx):
                for tet in KUHN_TETS:
                    ids = []
                    for c in tet:
                        cx, cy, cz = x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1)
                        key = (cx, cy, cz)
                        if key not in used:
                            used[key] = len(nodes)
                            # origin + DVec3::new(cx, cy, cz) * h, componentwise in f64.
                            nodes.append(origin + np.array([float(cx), float(cy), float(cz)]) * h)
                        ids.append(used[key])
                    p = [nodes[i] for i in ids]
                    if tet_volume(p) < 0.0:
                        ids = [ids[0], ids[1], ids[3], ids[2]]
                    tets.append(ids)
    return np.array(nodes, dtype=np.float64), np.array(tets, dtype=np.int64)


def lame(nu):
    mu = E / (2.0 * (1.0 + nu))
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    return lam, mu


def beam_theory(nu):
    """(Euler-Bernoulli, Timoshenko) tip sags, positive downward."""
    area = SIDE * SIDE
    inertia = SIDE**4 / 12.0
    q = RHO * G_ACC * area
    w_eb = q * LENGTH**4 / (8.0 * E * inertia)
    _, mu = lame(nu)
    w_t = w_eb + q * LENGTH**2 / (2.0 * KAPPA * mu * area)
    return w_eb, w_t


def solve_case(cells, h, nu, element=ElementTetP1):
    """Returns nodes, tets, per-node displacement (vertex dofs), tip mean uy."""
    nodes, tets = box_tets(h, cells)
    mesh = MeshTet(nodes.T.copy(), tets.T.copy())
    # MeshTet must keep our node order (no reordering on construction).
    assert np.array_equal(mesh.p.T, nodes)
    basis = Basis(mesh, ElementVectorH1(element()))
    lam, mu = lame(nu)
    K = asm(linear_elasticity(lam, mu), basis)

    @LinearForm
    def gravity(v, w):
        return -RHO * G_ACC * v.value[1]

    f = asm(gravity, basis)
    fixed = basis.get_dofs(lambda x: x[0] == 0.0).all()
    if element is ElementTetP1:
        assert fixed.size == 3 * (cells[1] + 1) * (cells[2] + 1)
    u = solve(*condense(K, f, D=fixed))
    if element is ElementTetP1:
        # The wall's reaction must carry the whole weight (P1 loads all sit on vertex dofs).
        reaction_y = float((K @ u - f)[basis.nodal_dofs[1]].sum())
        weight = RHO * G_ACC * LENGTH * SIDE * SIDE
        assert abs(reaction_y - weight) < 1e-6 * weight, (reaction_y, weight)
    # nodal_dofs[k, i] is the dof of component k at node i.
    disp = u[basis.nodal_dofs].T
    # The tip nodes' x is nx * h = 0.6000000000000001 in f64, hence the tolerance.
    tip = np.isclose(nodes[:, 0], LENGTH, rtol=0.0, atol=1e-12)
    assert tip.sum() == (cells[1] + 1) * (cells[2] + 1)
    tip_uy = float(disp[tip, 1].mean())
    return nodes, tets, disp, tip_uy


def write_case(path, cells, h, nu, nodes, tets, disp, tip_uy):
    w_eb, w_t = beam_theory(nu)
    lam, mu = lame(nu)
    nx, ny, nz = cells
    lines = [
        "# Static linear-elastic cantilever, scikit-fem P1 tets (scripts/fem_reference.py)",
        f"# cells = [{nx}, {ny}, {nz}], h = {h!r}, origin = [0, 0, 0] (engine box_tets node order)",
        f"# E = {E!r} Pa, nu = {nu!r}, lambda = {lam!r}, mu = {mu!r}",
        f"# rho = {RHO!r} kg/m^3, g = {G_ACC!r} m/s^2 along -Y; all dofs fixed at x == 0",
        f"# nodes = {len(nodes)}, tets = {len(tets)}",
        f"# scikit-fem {skfem.__version__}, numpy {np.__version__}, scipy {scipy.__version__}",
        f"# tip_mean_uy = {tip_uy!r} (mean uy over nodes with x == {LENGTH!r})",
        f"# euler_bernoulli_sag = {w_eb!r} (q L^4 / (8 E I), downward)",
        f"# timoshenko_sag = {w_t!r} (EB + q L^2 / (2 kappa G A), kappa = 5/6, G = mu)",
        "# columns: x y z ux uy uz",
    ]
    for p, d in zip(nodes, disp):
        lines.append(" ".join(repr(float(v)) for v in (*p, *d)))
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(root, "tests", "data", "fem"))
    parser.add_argument("--no-fine", action="store_true", help="skip the 48x8x8 refinement")
    parser.add_argument(
        "--convergence",
        action="store_true",
        help="also print P1 96x16x16 and P2 tip sags (no files; about 4 minutes)",
    )
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    cases = [([12, 2, 2], 0.05, nu) for nu in (0.30, 0.45)]
    cases += [([24, 4, 4], 0.025, nu) for nu in (0.30, 0.45)]
    if not args.no_fine:
        cases.append(([48, 8, 8], 0.0125, 0.30))

    print(f"scikit-fem {skfem.__version__}, numpy {np.__version__}, scipy {scipy.__version__}")
    for cells, h, nu in cases:
        start = time.perf_counter()
        nodes, tets, disp, tip_uy = solve_case(cells, h, nu)
        elapsed = time.perf_counter() - start
        w_eb, w_t = beam_theory(nu)
        name = f"beam_{cells[0]}x{cells[1]}x{cells[2]}_nu{nu:.2f}.txt"
        path = os.path.join(args.out, name)
        write_case(path, cells, h, nu, nodes, tets, disp, tip_uy)
        print(
            f"{name}: nodes {len(nodes)}, tets {len(tets)}, tip mean uy {tip_uy:.6e} m, "
            f"EB {-w_eb:.6e}, Timoshenko {-w_t:.6e}, FE/Timoshenko {-tip_uy / w_t:.4f}, "
            f"{elapsed:.1f} s, {os.path.getsize(path)} bytes"
        )
    if args.convergence:
        runs = [([48, 8, 8], 0.0125, 0.45, ElementTetP1), ([96, 16, 16], 0.00625, 0.30, ElementTetP1)]
        for nu in (0.30, 0.45):
            runs += [(cells, h, nu, ElementTetP2) for cells, h in
                     (([12, 2, 2], 0.05), ([24, 4, 4], 0.025), ([48, 8, 8], 0.0125))]
        for cells, h, nu, element in runs:
            start = time.perf_counter()
            *_, tip_uy = solve_case(cells, h, nu, element)
            _, w_t = beam_theory(nu)
            print(
                f"convergence {element.__name__} {cells[0]}x{cells[1]}x{cells[2]} nu {nu:.2f}: "
                f"tip mean uy {tip_uy:.6e} m, FE/Timoshenko {-tip_uy / w_t:.4f}, "
                f"{time.perf_counter() - start:.1f} s"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
