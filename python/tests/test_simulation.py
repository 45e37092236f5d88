"""Simulations: the seed table equals the command line's to the last digit, state in and
out as numpy arrays, records, output files, and the exceptions bad input raises."""

import json
import subprocess

import numpy as np
import pytest

import tetrasim

SERIES = ("time_s", "volume_pct", "local_error_pct", "inverted_tets")
SUMMARY = ("min_volume_pct", "avg_volume_pct", "max_inverted_tets", "avg_local_error_pct", "max_local_error_pct", "contact_time_s", "diverged")


@pytest.mark.parametrize("backend", ["cpu", "cpu-ref"])
def test_the_seed_table_equals_the_command_lines(cli, tmp_path, backend):
    out = tmp_path / "seed.json"
    subprocess.run(
        [cli, "run", "--mesh", "meshes/sphere", "--preset", "seed", "--method", "all",
         "--backend", backend, "--json", str(out), "--quiet"],
        check=True, capture_output=True,
    )
    records = json.loads(out.read_text())
    assert [r["method"] for r in records] == ["mss", "distance", "volume"]
    mesh = tetrasim.read_mesh("meshes/sphere")
    for cli_record in records:
        sim = tetrasim.Simulation(mesh, backend=backend, method=cli_record["method"])
        sim.step(400)
        mine = sim.record()
        for key in SERIES + SUMMARY + ("params", "groups", "global_volume", "nodes", "tets", "frames"):
            assert mine[key] == cli_record[key], (cli_record["method"], key)
        assert len(mine["volume_pct"]) == 400


@pytest.mark.parametrize("backend", ["cpu-ref", "cpu"])
def test_state_comes_back_as_numpy_and_survives_set_state(backend):
    sim = tetrasim.Simulation("meshes/sphere", method="volume", iterations=5, backend=backend)
    x0 = sim.positions
    assert x0.shape == (823, 3) and x0.dtype == np.float64
    # Placement: fitted to 1 m, lowest node 0.1 m up (exact in f64, to f32 rounding on cpu).
    assert x0[:, 1].min() == pytest.approx(0.1, abs=1e-7)
    assert np.ptp(x0, axis=0).max() == pytest.approx(1.0, abs=1e-6)
    # Any state set comes back as set (cpu holds float32: set values it can hold).
    x0 = x0.astype(np.float32).astype(np.float64)
    sim.step(20)
    x, v = sim.positions, sim.velocities
    assert v[:, 1].mean() < -0.1  # falling
    assert (sim.frames, sim.time) == (20, pytest.approx(0.02))
    lifted = (x + [0.0, 1.0, 0.0]).astype(np.float32).astype(np.float64)
    sim.set_state(lifted, np.zeros_like(v))
    assert np.array_equal(sim.positions, lifted)
    assert np.array_equal(sim.velocities, np.zeros_like(v))
    sim.set_state(x0)  # velocities kept
    assert np.array_equal(sim.positions, x0) and np.array_equal(sim.velocities, np.zeros_like(v))
    assert sim.volume_ratio == pytest.approx(1.0, abs=1e-6)


def test_an_offset_moves_the_placed_mesh():
    still = tetrasim.Simulation("meshes/torus", backend="cpu-ref")
    moved = tetrasim.Simulation("meshes/torus", backend="cpu-ref", offset=(1.5, 0.25, -2.0))
    assert np.allclose(moved.positions - still.positions, [1.5, 0.25, -2.0], atol=1e-12)
    with pytest.raises(ValueError, match="offset"):
        tetrasim.Simulation("meshes/torus", offset=(0.0, float("nan"), 0.0))


def test_pins_hold_nodes_and_materials_take_physical_units():
    sim = tetrasim.Simulation(
        "meshes/box", method="volume", springs="implicit", youngs_modulus=1e5,
        poisson_ratio=0.45, density=1000.0, drop_height=0.5,
        pin_boxes=[((-1.0, 0.0, -1.0), (-0.45, 2.0, 1.0))],
    )
    x0 = sim.positions
    pinned = x0[:, 0] <= -0.45
    assert pinned.sum() > 10
    sim.step(100)
    x = sim.positions
    assert np.array_equal(x[pinned], x0[pinned])
    assert x[~pinned, 1].min() < x0[~pinned, 1].min() - 0.01  # the free end sags
    record = sim.record()
    assert record["params"]["youngs_modulus"] == 1e5 and record["damping"] > 0
    assert record["params"]["mass"] == {"mode": "density", "density": 1000.0}


def test_the_deformed_mesh_is_written_with_its_fields(tmp_path):
    import meshio

    sim = tetrasim.Simulation("meshes/sphere", method="distance", iterations=5)
    sim.step(10)
    sim.write(tmp_path / "f.vtu")
    m = meshio.read(tmp_path / "f.vtu")
    assert np.allclose(m.points, sim.positions)
    assert {"displacement", "velocity", "volume_ratio", "pinned"} <= set(m.point_data)
    sim.write(tmp_path / "f.ply")
    assert (tmp_path / "f.ply").stat().st_size > 0


def test_bad_parameters_raise_with_the_engines_message():
    with pytest.raises(TypeError, match="itterations"):
        tetrasim.Simulation("meshes/sphere", itterations=3)
    with pytest.raises(ValueError, match="dt"):
        tetrasim.Simulation("meshes/sphere", dt=-1.0)
    with pytest.raises(ValueError, match="method"):
        tetrasim.Simulation("meshes/sphere", method="magic")
    with pytest.raises(ValueError, match="backend"):
        tetrasim.Simulation("meshes/sphere", backend="abacus")
    with pytest.raises(ValueError, match="pins"):
        tetrasim.Simulation("meshes/sphere", pins=[100000])
    with pytest.raises(ValueError, match="density"):
        tetrasim.Simulation("meshes/sphere", density=1.0, node_mass=1.0)
    sim = tetrasim.Simulation("meshes/sphere", iterations=2)
    with pytest.raises(ValueError, match="positions"):
        sim.set_state(np.zeros((5, 3)))
    with pytest.raises(ValueError, match="not finite"):
        sim.set_state(np.full((823, 3), np.nan))


def test_a_diverging_run_raises_and_keeps_its_record():
    sim = tetrasim.Simulation("meshes/sphere", method="mss", ks=5e7, dt=1e-2)
    # The advice names the settings as Python does (keyword arguments), not as flags.
    with pytest.raises(tetrasim.DivergedError, match=r'`springs = "implicit"`.*`dt = '):
        sim.step(200)
    record = sim.record()
    assert record["diverged"] and record["divergence"]
    assert "--" not in record["divergence"]
    assert len(record["volume_pct"]) < 200


def test_a_turned_body_falls_along_a_gravity_vector():
    # 90 degrees about Y: the box's long side (X) stands along Z, as a Z-up part would.
    turn = (np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0)
    sim = tetrasim.Simulation(
        "meshes/box", backend="cpu-ref", fit_size=None, drop_height=None, rotation=turn,
        floor=False, gravity=[0.0, 0.0, -9.81],
    )
    x0 = sim.positions
    assert x0.max(axis=0) - x0.min(axis=0) == pytest.approx([0.5, 0.5, 1.0], abs=1e-9)
    sim.step(100)
    # Symplectic Euler's free fall: dz = -g dt^2 n (n + 1) / 2 after n steps; nothing across.
    moved = sim.positions.mean(axis=0) - x0.mean(axis=0)
    assert moved == pytest.approx([0.0, 0.0, -9.81e-6 * 100 * 101 / 2], abs=1e-7)
    assert sim.record()["params"]["gravity"] == [0.0, 0.0, -9.81]
    with pytest.raises(ValueError, match="rotation"):
        tetrasim.Simulation("meshes/box", rotation=(1.0, 1.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="gravity"):
        tetrasim.Simulation("meshes/box", gravity=[0.0, -9.81])


def test_a_record_rebuilds_its_simulation():
    sim = tetrasim.Simulation("meshes/torus", method="volume", iterations=4, backend="cpu-ref")
    sim.step(30)
    again = tetrasim.Simulation.from_record(sim.record(), fit_size=1.0, drop_height=0.1)
    again.step(30)
    assert again.record()["volume_pct"] == sim.record()["volume_pct"]


def test_the_gpu_backend_runs_from_python():
    sim = tetrasim.Simulation("meshes/sphere", method="volume", backend="vulkan")
    sim.step(150)
    record = sim.record()
    assert record["backend"] == "vulkan" and record["device"]
    assert [p["name"] for p in record["passes"]][-1] == "reactions"
    assert sim.positions.shape == (823, 3)
    reference = tetrasim.Simulation("meshes/sphere", method="volume", backend="cpu-ref")
    reference.step(150)
    assert np.abs(sim.positions - reference.positions).max() < 1e-3
    assert abs(sim.volume_ratio - reference.volume_ratio) < 1e-4
    # The forces out too: the floor's push on the landed sphere, as the reference's.
    assert np.abs(sim.floor_force - reference.floor_force).max() < 1e-3 * np.abs(
        reference.floor_force
    ).max()
    assert reference.floor_force[1] > 0.0


def test_a_material_without_a_method_runs_the_finite_elements():
    material = dict(youngs_modulus=1e5, poisson_ratio=0.45, density=1000.0)
    sim = tetrasim.Simulation("meshes/sphere", backend="cpu", **material)
    assert sim.record()["params"]["method"] == "neo-hookean"
    springs = tetrasim.Simulation("meshes/sphere", backend="cpu", springs="implicit", **material)
    assert springs.record()["params"]["method"] == "volume"
    named = tetrasim.Simulation("meshes/sphere", backend="cpu", method="mss", **material)
    assert named.record()["params"]["method"] == "mss"


def test_a_scene_runs_as_the_command_line_runs_it(cli, root, tmp_path):
    scene = tmp_path / "two.toml"
    scene.write_text(
        "[solver]\nframes = 120\niterations = 5\n"
        "[[object]]\nmesh = \"{root}/meshes/sphere\"\nmethod = \"volume\"\nfit_size = 0.4\n"
        "drop_height = 0.05\nvelocity = [0.5, 0.0, 0.0]\n"
        "[[object]]\nmesh = \"{root}/meshes/torus\"\nmethod = \"volume\"\nfit_size = 0.5\n"
        "drop_height = 0.6\nmaterial = {{ ks = 3000.0 }}\npin = {{ nodes = [0, 1, 2] }}\n"
        "[[collider]]\ntype = \"floor\"\nfriction = 0.3\n"
        "[output]\njson = \"out.json\"\n".format(root=root)
    )
    run = subprocess.run([cli, "run", "--scene", str(scene), "--backend", "cpu", "--quiet"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    cli_record = json.loads((tmp_path / "out.json").read_text())[0]
    sim = tetrasim.Simulation.from_scene(scene, backend="cpu")
    assert sim.scene_frames == 120 and sim.mesh is None
    sim.step(sim.scene_frames)
    mine = sim.record()
    for key in SERIES + SUMMARY + ("params", "nodes", "tets", "mesh"):
        assert mine[key] == cli_record[key], key
    assert mine["params"]["friction"] == 0.3
    with pytest.raises(FileNotFoundError):
        tetrasim.Simulation.from_scene(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[[object]]\nmesh = \"x\"\nfit_size = -1.0\n")
    with pytest.raises(ValueError, match=r"object\[0\].fit_size"):
        tetrasim.Simulation.from_scene(bad)



def test_self_contact_and_moving_pins():
    # self_contact: the keyword reaches the model (a lone box does not touch itself).
    sim = tetrasim.Simulation("meshes/box", backend="cpu", self_contact=True, drop_height=0.5)
    sim.step(5)
    assert np.isfinite(sim.positions).all()
    # A scene's moving pin: clamped_block pulls its right end 0.3 m along X over 0.5 s
    # (0.06 m after 0.1 s) and holds its left end.
    sim = tetrasim.Simulation.from_scene("examples/scenes/clamped_block.toml", backend="cpu")
    x0 = sim.positions
    sim.step(100)
    x = sim.positions
    right, left = x0[:, 0] >= 0.49, x0[:, 0] <= -0.49
    assert right.sum() > 10 and left.sum() > 10
    assert np.allclose(x[right, 0] - x0[right, 0], 0.06, atol=1e-4)
    assert np.array_equal(x[left], x0[left])
    # The moving pin is the scene's one clamp: it pulls the block outwards (+X), and it is a
    # share of the pins' force (the fixed end pulls the other way).
    clamps = sim.clamp_forces
    assert clamps.shape == (1, 3)
    assert clamps[0, 0] > 1.0, clamps
    assert (sim.pin_force - clamps[0])[0] < -1.0, (sim.pin_force, clamps)
    assert len(sim.record()["clamp_force"][-1]) == 1


def test_split_contact_keeps_a_rigid_sphere_down():
    # The distance sphere dropped from 0.1 m: combined contact rebounds by centimetres,
    # split contact (contact="split") not at all (tests/no_false_restitution.rs).
    def rebound(**params):
        sim = tetrasim.Simulation("meshes/sphere", backend="cpu", method="distance", **params)
        landed, highest = False, 0.0
        for _ in range(300):
            sim.step()
            lowest = sim.positions[:, 1].min()
            landed = landed or lowest < 1e-4
            if landed:
                highest = max(highest, lowest)
        assert landed
        return highest

    assert rebound() > 0.02
    assert rebound(contact="split") < 2e-3
    with pytest.raises(ValueError, match="contact"):
        tetrasim.Simulation("meshes/sphere", contact="split", solver="chebyshev")


def test_the_pins_hold_a_hanging_body_by_its_weight():
    """Forces out (issue 51): a finite-element box hanging at rest from pins along its top
    is held by its weight, m g summed from the density and the tets' volume."""
    mesh = tetrasim.read_mesh("meshes/box")
    top = np.flatnonzero(mesh.nodes[:, 1] >= mesh.nodes[:, 1].max() - 1e-9)
    assert len(top) > 10
    sim = tetrasim.Simulation(
        "meshes/box", method="neo-hookean", youngs_modulus=1e6, poisson_ratio=0.3,
        density=1000.0, floor=False, pins=top.tolist(), backend="cpu",
    )
    x = sim.positions
    tets = mesh.tets
    a, b, c, d = (x[tets[:, k]] for k in range(4))
    volume = np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))).sum() / 6.0
    weight = 1000.0 * volume * 9.81
    sim.step(1500)
    assert np.abs(sim.velocities).max() < 1e-3
    force = sim.pin_force
    assert force.shape == (3,)
    assert abs(force[1] / weight - 1.0) < 0.01, (force, weight)
    assert abs(force[0]) < 0.01 * weight and abs(force[2]) < 0.01 * weight
    assert sim.collider_forces.shape == (0, 3)
    record = sim.record()
    assert len(record["pin_force"]) == 1500
    assert record["pin_force"][-1] == pytest.approx(list(force))


def test_a_youngs_modulus_without_a_density_is_refused():
    # At 1 kg per node the body would weigh the wrong amount for its stiffness.
    with pytest.raises(ValueError, match="density"):
        tetrasim.Simulation("meshes/box", method="volume", springs="implicit",
                            youngs_modulus=1e5, poisson_ratio=0.3)


def test_pythonic_edges_meshio_names_pyvista_a_device_and_closing():
    mesh = tetrasim.read_mesh("meshes/box")
    assert np.array_equal(mesh.points, mesh.nodes) and np.array_equal(mesh.cells["tetra"], mesh.tets)
    meshio = pytest.importorskip("meshio")
    assert meshio.Mesh(mesh.points, mesh.cells).cells_dict["tetra"].shape == (1980, 4)
    pytest.importorskip("pyvista")
    grid = mesh.to_pyvista()
    assert grid.n_cells == 1980 and grid.volume == pytest.approx(0.25, rel=1e-9)  # 1 x 0.5 x 0.5
    # The device by a part of its name, as `tetrasim run --device` takes it.
    name = tetrasim.Simulation("meshes/sphere", backend="vulkan").record()["device"]
    with tetrasim.Simulation("meshes/sphere", backend="vulkan", device=name.split()[0]) as sim:
        sim.step(2)
        assert sim.record()["device"] == name
    with pytest.raises(RuntimeError, match="closed"):
        sim.step(1)
    sim.close()  # twice is harmless
    with pytest.raises(ValueError, match="device"):
        tetrasim.Simulation("meshes/sphere", backend="cpu", device=0)
    with pytest.raises(RuntimeError):
        tetrasim.Simulation("meshes/sphere", backend="vulkan", device="no such gpu")


def test_the_accuracy_dial_orders_cost_and_error_and_yields_to_settings_given():
    """``accuracy=`` picks the front's settings (the same as ``--accuracy`` and a scene's
    ``[solver] accuracy``); on the bundled sphere the local volume error falls from ``fast``
    to ``accurate``, and a setting given beside the dial wins."""
    errors = {}
    for level in ("fast", "balanced", "accurate"):
        sim = tetrasim.Simulation("meshes/sphere", accuracy=level)
        sim.step(200)
        record = sim.record()
        errors[level] = record["avg_local_error_pct"]
        params = record["params"]
        # The frame's length is the same at every level.
        assert params["dt"] * params["substeps"] == pytest.approx(1e-3)
    assert errors["fast"] > errors["balanced"] > errors["accurate"], errors
    params = tetrasim.Simulation("meshes/sphere", accuracy="fast").record()["params"]
    assert (params["iterations"], params["groups"]) == (5, 4)
    params = tetrasim.Simulation("meshes/sphere", accuracy="fast", iterations=7).record()["params"]
    assert (params["iterations"], params["groups"]) == (7, 4)
    scene = tetrasim.Scene(accuracy="accurate")
    scene.add_body("meshes/sphere")
    params = tetrasim.Simulation(scene).record()["params"]
    assert (params["substeps"], params["dt"]) == (2, 5e-4)
    with pytest.raises(ValueError, match="accuracy"):
        tetrasim.Simulation("meshes/sphere", accuracy="perfect")
