"""Writes the fixtures of tests/mesh_readers.rs with meshio, an independent writer.

Run from this folder with a Python that has meshio 5.3.5 and numpy (scripts/setup.sh makes
one at target/py):

    ../../../target/py/bin/python make_fixtures.py

Made with meshio 5.3.5 and numpy 2.4.6. The figures it prints (node count, tet count and the
sum of |tet volume| computed with numpy) are hard-coded in tests/mesh_readers.rs as the
reference values.

The mesh: two unit cubes side by side (x in [0, 2]), each split into six tets around its
main diagonal, so 12 nodes and 12 tets, total volume 2. Tet 1 is written with negative
orientation (two nodes swapped), as readers must keep a file's orientation as it is.
"""

import meshio
import numpy as np

assert meshio.__version__ == "5.3.5", meshio.__version__

points = np.array(
    [[x, y, z] for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0, 2.0)]
)


def node(x, y, z):
    return z * 6 + y * 3 + x


tets = []
for cx in (0, 1):
    c = [node(cx + (k & 1), (k >> 1) & 1, (k >> 2) & 1) for k in range(8)]
    # Six tets around the diagonal c[0]-c[7] (Kuhn triangulation), positively oriented.
    for a, b in [(1, 3), (3, 2), (2, 6), (6, 4), (4, 5), (5, 1)]:
        t = [c[0], c[a], c[b], c[7]]
        v = np.dot(np.cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]),
                   points[t[3]] - points[t[0]])
        tets.append(t if v > 0 else [t[0], t[2], t[1], t[3]])
tets = np.array(tets)
tets[1] = tets[1][[0, 1, 3, 2]]  # negative orientation on purpose


def volumes(p, t):
    a, b, c, d = (p[t[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6.0


mesh = meshio.Mesh(points, [("tetra", tets)])
files = {
    "box_ascii.vtk": dict(file_format="vtk", binary=False),
    "box_binary.vtk": dict(file_format="vtk", binary=True),
    "box_42_ascii.vtk": dict(file_format="vtk42", binary=False),
    "box_42_binary.vtk": dict(file_format="vtk42", binary=True),
    "box.vtu": dict(file_format="vtu"),  # meshio's default: binary, zlib
    "box_ascii.vtu": dict(file_format="vtu", binary=False),
    "box_binary_raw.vtu": dict(file_format="vtu", compression=None),
    "box_22_ascii.msh": dict(file_format="gmsh22", binary=False),
    "box_22_binary.msh": dict(file_format="gmsh22", binary=True),
    "box.msh": dict(file_format="gmsh", binary=False),  # 4.1 ascii
    "box_41_binary.msh": dict(file_format="gmsh", binary=True),
    "box.mesh": dict(file_format="medit"),
}
for name, kw in files.items():
    meshio.write(name, mesh, **kw)
meshio.write("box.node", mesh, file_format="tetgen")  # box.node + box.ele, the original

# Mixed: the tets plus boundary triangles, a vertex cell and a node that no tet uses (only
# the vertex cell), as gmsh and meshio files often have.
extra = np.vstack([points, [[5.0, 5.0, 5.0]]])
tri = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])


def mixed_mesh(name):
    # A fresh mesh per file: meshio's VTK writers pad 2-component point data in place, and
    # its medit writer takes any point data for node references (so none there).
    if name.endswith(".mesh"):
        return meshio.Mesh(extra, [("vertex", np.array([[12]])), ("triangle", tri), ("tetra", tets)])
    return meshio.Mesh(
        extra,
        [("vertex", np.array([[12]])), ("triangle", tri), ("tetra", tets)],
        # gmsh 4.1 groups nodes by entity: the tets' volume, and a point for node 12.
        point_data={"gmsh:dim_tags": np.array([[3, 1]] * 12 + [[0, 1]])},
        cell_data={
            "gmsh:geometrical": [np.array([1]), np.array([1] * 4), np.array([1] * 12)],
            "gmsh:physical": [np.array([1]), np.array([2] * 4), np.array([3] * 12)],
        },
    )


for name, kw in {
    "mixed_ascii.vtk": dict(file_format="vtk", binary=False),
    "mixed.vtu": dict(file_format="vtu"),
    "mixed_22_ascii.msh": dict(file_format="gmsh22", binary=False),
    "mixed_41_binary.msh": dict(file_format="gmsh", binary=True),
    "mixed.mesh": dict(file_format="medit"),
}.items():
    meshio.write(name, mixed_mesh(name), **kw)

# Only triangles: no tets (an error for our readers).
meshio.write("triangles.vtk", meshio.Mesh(points, [("triangle", tri)]), binary=False)

for name in list(files) + ["box.node"]:
    m = meshio.read(name) if name != "box.node" else meshio.read("box.node", file_format="tetgen")
    t = m.get_cells_type("tetra")
    assert (t == tets).all(), name
    print(name, len(m.points), len(t), abs(volumes(m.points, t)).sum())
print("signed volume of tet 1:", volumes(points, tets)[1])
print("total |volume|:", repr(abs(volumes(points, tets)).sum()))
