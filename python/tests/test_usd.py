"""USD out: `tetrasim run --format usd` writes one animated stage per method that a reader
we did not write (Pixar's `pxr`, from usd-core) opens: a Mesh prim per body with a time
sample of its points and volume ratio at every frame written, metres, up axis Y."""

import json
import subprocess

import numpy as np
import tetrasim
import pytest

pxr = pytest.importorskip("pxr")
from pxr import Usd, UsdGeom  # noqa: E402


def enclosed_volume(points, indices):
    """The volume a closed triangle surface encloses (positive when its triangles wind
    counter-clockwise seen from outside, USD's right-handed orientation)."""
    p = np.asarray(points, dtype=float)
    t = np.asarray(indices).reshape(-1, 3)
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    return np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0


def test_a_run_becomes_one_stage_with_a_sample_per_frame(cli, root, tmp_path):
    scene = tmp_path / "two.toml"
    scene.write_text(
        "[solver]\nframes = 100\n"
        "[[object]]\nmesh = \"{root}/meshes/sphere\"\nfit_size = 0.4\ndrop_height = 0.02\n"
        "[[object]]\nmesh = \"{root}/meshes/torus\"\nfit_size = 0.5\ndrop_height = 0.5\n"
        "[[collider]]\ntype = \"floor\"\n".format(root=root)
    )
    out = tmp_path / "frames"
    record = tmp_path / "run.json"
    subprocess.run(
        [cli, "run", "--quiet", "--scene", str(scene), "--out-dir", str(out),
         "--format", "usd", "--every", "1", "--json", str(record)],
        check=True,
    )
    assert sorted(p.name for p in out.iterdir()) == ["volume.usda"]
    stage = Usd.Stage.Open(str(out / "volume.usda"))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (0.0, 100.0)
    assert stage.GetTimeCodesPerSecond() == pytest.approx(1000.0)  # 1 ms frames
    meshes = [UsdGeom.Mesh(p) for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
    assert [str(m.GetPath()) for m in meshes] == ["/World/body_0", "/World/body_1"]
    # The bodies' surfaces enclose the bodies' volume: at frame 0 the rest volume, and at
    # every frame the record's volume percentage (both bodies together), to f32 rounding.
    volume_pct = json.loads(record.read_text())[0]["volume_pct"]
    rest = None
    for m in meshes:
        samples = m.GetPointsAttr().GetTimeSamples()
        assert samples == [float(f) for f in range(101)]  # frame 0 and the 100 run
        ratio = UsdGeom.PrimvarsAPI(m.GetPrim()).GetPrimvar("volume_ratio")
        assert ratio.GetInterpolation() == UsdGeom.Tokens.vertex
        assert len(ratio.Get(100.0)) == len(m.GetPointsAttr().Get(100.0))
    for frame in (0.0, 50.0, 100.0):
        enclosed = sum(
            enclosed_volume(m.GetPointsAttr().Get(frame), m.GetFaceVertexIndicesAttr().Get())
            for m in meshes
        )
        assert enclosed > 0.0
        rest = rest or enclosed
        if frame > 0:
            assert 100.0 * enclosed / rest == pytest.approx(volume_pct[int(frame) - 1], abs=1e-3)


def test_usd_is_refused_in_the_input_units(cli, tmp_path):
    run = subprocess.run(
        [cli, "run", "--quiet", "--frames", "2", "--out-dir", str(tmp_path / "f"),
         "--format", "usd", "--units", "input"],
        capture_output=True, text=True,
    )
    assert run.returncode != 0 and "units" in run.stderr and "usd" in run.stderr
    assert not (tmp_path / "f").exists() or not any((tmp_path / "f").iterdir())


def test_a_script_records_a_series_as_usd_and_as_a_paraview_series(tmp_path):
    sim = tetrasim.Simulation("meshes/sphere", backend="cpu", fit_size=0.3, drop_height=0.02)
    with tetrasim.Series(sim, tmp_path / "run.usda") as usd, \
            tetrasim.Series(sim, tmp_path / "frames") as vtu:
        for _ in range(5):
            sim.step(20)
            usd.add()
            vtu.add()
        with pytest.raises(ValueError, match="does not follow"):
            usd.add()  # frame 100 again, not stepped past: frames must increase
        end = sim.positions
    assert usd.frames == [20, 40, 60, 80, 100]
    stage = Usd.Stage.Open(str(tmp_path / "run.usda"))
    (mesh,) = [UsdGeom.Mesh(p) for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
    assert mesh.GetPointsAttr().GetTimeSamples() == [20.0, 40.0, 60.0, 80.0, 100.0]
    # The last sample is the state the script saw when it added it (f32 in the stage): the
    # surface's points are among the nodes', each within f32 rounding of one.
    last = np.asarray(mesh.GetPointsAttr().Get(100.0), dtype=float)
    nearest = np.abs(last[:, None, :] - end[None, :, :]).max(axis=2).min(axis=1)
    assert nearest.max() < 1e-6
    names = sorted(p.name for p in (tmp_path / "frames").iterdir())
    assert names == ["frame_00020.vtu", "frame_00040.vtu", "frame_00060.vtu",
                     "frame_00080.vtu", "frame_00100.vtu", "series.pvd"]
    pvd = (tmp_path / "frames" / "series.pvd").read_text()
    assert 'timestep="0.1"' in pvd and 'file="frame_00100.vtu"' in pvd
    with pytest.raises(RuntimeError, match="closed"):
        usd.add()
    with pytest.raises(ValueError, match="format"):
        tetrasim.Series(sim, tmp_path / "x", format="stl")
