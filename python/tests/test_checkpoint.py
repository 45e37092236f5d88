"""Checkpoints from Python: `sim.save(path)` and, on a simulation built the same way,
`sim.load(path)` continue the run bit for bit; a truncated checkpoint or one of another run
is refused, saying which."""

import numpy as np
import pytest

import tetrasim

SOFT_BOX = dict(
    backend="cpu", fit_size=0.3, drop_height=0.05, method="neo-hookean",
    youngs_modulus=1e5, poisson_ratio=0.45, density=1000.0,
)


def test_a_saved_run_resumes_bit_for_bit(tmp_path):
    straight = tetrasim.Simulation("meshes/box", **SOFT_BOX)
    straight.step(60)
    path = tmp_path / "run.ckpt"
    with tetrasim.Simulation("meshes/box", **SOFT_BOX) as first:
        first.step(30)
        first.save(path)
    second = tetrasim.Simulation("meshes/box", **SOFT_BOX)
    second.load(path)
    assert second.frames == 30
    second.step(30)
    assert np.array_equal(second.positions, straight.positions)
    assert np.array_equal(second.velocities, straight.velocities)
    assert second.record()["volume_pct"] == straight.record()["volume_pct"]

    data = path.read_bytes()
    (tmp_path / "short.ckpt").write_bytes(data[: len(data) // 2])
    with pytest.raises(ValueError, match="truncated"):
        second.load(tmp_path / "short.ckpt")
    finer = tetrasim.Simulation("meshes/box", **{**SOFT_BOX, "dt": 5e-4})
    with pytest.raises(ValueError, match="another `dt`"):
        finer.load(path)
    with pytest.raises(ValueError, match="saved by the cpu backend"):
        tetrasim.Simulation("meshes/box", **{**SOFT_BOX, "backend": "cpu-ref"}).load(path)
    with pytest.raises(FileNotFoundError):
        second.load(tmp_path / "missing.ckpt")
