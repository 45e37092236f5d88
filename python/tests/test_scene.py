"""Scenes built in Python: the same scene from code, from the TOML that `to_toml()` writes,
and from the command line gives the same record; it runs on `vulkan` too; the TOML round
trips; bad keys are refused naming them as a scene file would."""

import json
import os
import subprocess

import numpy as np
import pytest

import tetrasim

TURN_X = [0.7071068, 0.7071068, 0.0, 0.0]  # 90 degrees about X, [w, x, y, z]
FRAMES = 300


def pressed_part() -> tetrasim.Scene:
    """A part turned 90 degrees about X under Z-up gravity above the ground plane z = 0,
    held at one end by a clamp that rises, pressed by a box tool that moves down and back."""
    scene = tetrasim.Scene(frames=FRAMES, gravity=[0.0, 0.0, -9.81], iterations=5)
    scene.add_body(
        "meshes/box", fit_size=0.3, rotation=TURN_X, offset=[0.0, 0.0, 0.3],
        pin={
            "box": {"min": [-0.2, -1.0, -1.0], "max": [-0.13, 1.0, 1.0]},
            "motion": {"keyframes": [{"t": 0.0}, {"t": 0.3, "translation": [0.0, 0.0, 0.05]}]},
        },
    )
    scene.add_collider("plane", normal=[0.0, 0.0, 1.0], distance=0.0)
    scene.add_collider(
        "box", center=[0.08, 0.0, 0.45], half_extents=[0.05, 0.2, 0.05],
        motion={"keyframes": [
            {"t": 0.0}, {"t": 0.15, "translation": [0.0, 0.0, -0.12]}, {"t": 0.3, "translation": [0.0, 0.0, 0.0]},
        ]},
    )
    return scene


def test_a_scene_from_code_equals_its_toml_and_the_command_line(cli, tmp_path):
    scene = pressed_part()
    from_code = tetrasim.Simulation(scene, backend="cpu")
    assert from_code.scene_frames == FRAMES
    from_code.step(FRAMES)
    path = tmp_path / "part.toml"
    scene.write(path)
    from_file = tetrasim.Simulation.from_scene(path, backend="cpu")
    from_file.step(FRAMES)
    assert np.array_equal(from_code.positions, from_file.positions)
    record = from_code.record()
    assert record["volume_pct"] == from_file.record()["volume_pct"]
    # The clamp pressed the part and the tool came down onto it: forces were exerted.
    assert np.abs(np.asarray(record["clamp_force"])).max() > 1.0
    assert max(record["collider_nodes"]) > 0
    out = tmp_path / "run.json"
    subprocess.run([cli, "run", "--quiet", "--scene", str(path), "--json", str(out)], check=True)
    assert json.loads(out.read_text())[0]["volume_pct"] == record["volume_pct"]
    # The round trip keeps every table.
    assert tetrasim.Scene.from_toml(path).to_dict() == scene.to_dict()
    assert tetrasim.Scene.from_toml(scene.to_toml()).to_dict() == scene.to_dict()


def test_the_scene_runs_on_vulkan_as_on_the_cpu():
    scene = pressed_part()
    cpu = tetrasim.Simulation(scene, backend="cpu-ref")
    cpu.step(100)
    with tetrasim.Simulation(scene, backend="vulkan") as gpu:
        gpu.step(100)
        assert np.abs(gpu.positions - cpu.positions).max() < 1e-3


def test_overrides_and_bad_keys():
    sim = tetrasim.Simulation.from_scene(
        "examples/scenes/tilted_plane.toml", frames=5, dt=5e-4, method="distance", density=900.0
    )
    params = sim.record()["params"]
    assert (sim.scene_frames, params["dt"], params["method"]) == (5, 5e-4, "distance")
    assert params["mass"] == {"mode": "density", "density": 900.0}
    scene = tetrasim.Scene()
    scene.add_body("meshes/box", method="neo-hookean", youngs_modulus=1e5, poisson_ratio=0.45)
    with pytest.raises(ValueError, match=r"object\[0\]\.material\.density"):
        scene.to_toml()
    scene = tetrasim.Scene(dtt=1e-3)
    scene.add_body("meshes/box")
    with pytest.raises(ValueError, match="dtt"):
        tetrasim.Simulation(scene)
    scene = tetrasim.Scene()
    scene.add_body("meshes/box")
    scene.add_collider("sphere", center=[0, 1, 0])
    with pytest.raises(ValueError, match=r"collider\[0\].*radius"):
        scene.to_toml()


def test_old_scene_keys_warn_naming_the_new_ones(tmp_path):
    path = tmp_path / "old.toml"
    path.write_text(
        "[solver]\nframes = 2\nepsilon = 1e-20\n[[object]]\nmesh = \"meshes/sphere\"\n"
        "[[collider]]\ntype = \"plane\"\nnormal = [0, 1, 0]\noffset = 0.0\n"
    )
    (tmp_path / "meshes").symlink_to(os.path.abspath("meshes"))  # the tests run from the root
    with pytest.warns(DeprecationWarning) as caught:
        sim = tetrasim.Simulation.from_scene(path)
    said = [str(w.message) for w in caught]
    assert any("`collider[0].offset` is now `collider[0].distance`" in s for s in said), said
    assert any("`solver.constraint_epsilon`" in s for s in said), said
    sim.step(2)


@pytest.mark.parametrize("backend", ["cpu", "vulkan"])
def test_a_grab_from_python_lifts_what_it_holds(backend):
    scene = tetrasim.Scene(frames=300)
    scene.add_body("meshes/sphere", fit_size=0.4, drop_height=0.0)
    scene.add_collider("floor")
    # The top of the ball (0.4 m high), lifted at 0.5 m/s for 0.3 s: 0.15 m.
    scene.add_grab([0.0, 0.4, 0.0], 0.05, motion={"velocity": [0.0, 0.5, 0.0]})
    again = tetrasim.Scene.from_toml(scene.to_toml())
    assert again.to_dict() == scene.to_dict()
    sim = tetrasim.Simulation(scene, backend=backend)
    start = sim.positions
    held = np.linalg.norm(start - [0.0, 0.4, 0.0], axis=1) <= 0.05
    assert held.any()
    sim.step(300)
    lift = (sim.positions - start)[held]
    assert lift[:, 1] == pytest.approx(0.15, abs=2e-3)
    bad = tetrasim.Scene()
    bad.add_body("meshes/sphere")
    bad.add_grab([5.0, 5.0, 5.0], 0.01)
    with pytest.raises(ValueError, match=r"grab\[0\].*catches no node"):
        tetrasim.Simulation(bad)
