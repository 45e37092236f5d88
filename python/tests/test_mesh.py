"""Meshes: reading (bundled, files), arrays in and out, meshio both ways, writing, meshing
a surface, and the errors bad input raises."""

import numpy as np
import pytest

import tetrasim


def test_the_bundled_sphere_reads_as_numpy_arrays():
    mesh = tetrasim.read_mesh("meshes/sphere")
    assert mesh.nodes.shape == (823, 3) and mesh.nodes.dtype == np.float64
    assert mesh.tets.shape == (2857, 4) and mesh.tets.dtype == np.int64
    assert mesh.faces.shape[1] == 3 and len(mesh.faces) == 1280
    assert mesh.tets.min() == 0 and mesh.tets.max() == 822
    assert "823 nodes" in repr(mesh)


def test_arrays_and_meshio_round_trip(tmp_path):
    import meshio

    mesh = tetrasim.read_mesh("meshes/box")
    again = tetrasim.Mesh(mesh.nodes, mesh.tets.astype(np.int64))
    assert np.array_equal(again.nodes, mesh.nodes) and np.array_equal(again.tets, mesh.tets)
    m = mesh.to_meshio()
    assert isinstance(m, meshio.Mesh) and m.cells[0].type == "tetra"
    back = tetrasim.Mesh.from_meshio(m)
    assert np.array_equal(back.nodes, mesh.nodes) and np.array_equal(back.tets, mesh.tets)
    # Our writers against a reader we did not write.
    for ext in ("vtk", "vtu"):
        path = tmp_path / f"box.{ext}"
        mesh.write(path)
        read = meshio.read(path)
        assert np.allclose(read.points, mesh.nodes)
        assert np.array_equal(read.cells_dict["tetra"], mesh.tets)
    mesh.write(tmp_path / "box.node")
    assert np.array_equal(tetrasim.read_mesh(tmp_path / "box").tets, mesh.tets)
    mesh.write(tmp_path / "box.stl")
    assert len(meshio.read(tmp_path / "box.stl").cells_dict["triangle"]) == len(mesh.faces)


def test_pickling_keeps_the_arrays():
    import pickle

    mesh = tetrasim.read_mesh("meshes/torus")
    back = pickle.loads(pickle.dumps(mesh))
    assert np.array_equal(back.nodes, mesh.nodes) and back.label == mesh.label


@pytest.mark.skipif(not tetrasim.HAS_TETGEN, reason="built without TetGen")
def test_prep_meshes_a_surface_like_tetprep():
    mesh = tetrasim.prep("meshes/sphere_surface.off", target_tets=1500)
    assert 1000 < len(mesh.tets) < 2200, len(mesh.tets)
    voxel = tetrasim.prep("meshes/sphere_surface.off", target_tets=1500, mesher="voxel")
    assert len(voxel.tets) > 100


def test_bad_meshes_raise_the_right_exceptions(tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere"):
        tetrasim.read_mesh("nowhere/nothing.vtk")
    with pytest.raises(FileNotFoundError):
        tetrasim.prep("nowhere.ply")
    bad = tmp_path / "bad.vtk"
    bad.write_text("# vtk DataFile Version 3.0\nnot a mesh\n")
    with pytest.raises(ValueError, match="bad.vtk"):
        tetrasim.read_mesh(bad)
    nodes = np.zeros((4, 3))
    with pytest.raises(ValueError, match="shape"):
        tetrasim.Mesh(np.zeros((4, 2)), np.array([[0, 1, 2, 3]]))
    with pytest.raises(ValueError, match="outside 0..4"):
        tetrasim.Mesh(nodes, np.array([[0, 1, 2, 7]]))
    with pytest.raises(ValueError, match="unknown mesh format"):
        tetrasim.read_mesh("meshes/box").write(tmp_path / "box.xyz")
    with pytest.raises(ValueError, match="mesher"):
        tetrasim.prep("meshes/sphere_surface.off", mesher="magic")


def test_arrays_in_any_memory_order_make_the_same_mesh():
    box = tetrasim.read_mesh("meshes/box")
    nodes, tets = box.nodes, box.tets
    fortran = tetrasim.Mesh(np.asfortranarray(nodes), np.asfortranarray(tets))
    strided = tetrasim.Mesh(np.repeat(nodes, 2, axis=0)[::2], tets[:, [0, 1, 2, 3]])
    for mesh in (fortran, strided):
        np.testing.assert_array_equal(mesh.nodes, nodes)
        np.testing.assert_array_equal(mesh.tets, tets)
    with pytest.raises(ValueError, match=r"`tets` must have shape \(n, 4\), not \[4, 1980\]"):
        tetrasim.Mesh(nodes, tets.T)
