"""tetrasim: volume-preserving soft bodies on tetrahedral meshes, from Python.

The engine (Rust: a CPU reference, a multi-threaded CPU backend and a Vulkan GPU backend)
with numpy arrays in and out::

    import tetrasim
    sim = tetrasim.Simulation("meshes/sphere", method="volume", backend="cpu")
    sim.step(400)                  # 400 frames of 1 ms
    print(sim.volume_ratio, sim.positions.shape)
    record = sim.record()          # what `tetrasim run --json` writes

Units are SI throughout: metres, seconds, kilograms, newtons, pascals. See docs/PYTHON.md
for every call.
"""

from __future__ import annotations

import copyreg
import json
import os
from typing import Any, Iterable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _tetrasim
from ._tetrasim import BACKENDS, HAS_TETGEN, DivergedError, Mesh, __version__

__all__ = [
    "BACKENDS",
    "HAS_TETGEN",
    "DivergedError",
    "Mesh",
    "Scene",
    "Series",
    "Simulation",
    "default_params",
    "mesh_from_meshio",
    "mesh_to_meshio",
    "prep",
    "read_mesh",
    "sweep",
    "__version__",
]

PathLike = Union[str, "os.PathLike[str]"]


def default_params() -> dict:
    """Every run parameter by its name, with its default (the keys `Simulation` takes)."""
    return json.loads(_tetrasim.default_params())


def read_mesh(path: PathLike, target_tets: Optional[int] = None) -> Mesh:
    """Reads a tet mesh (TetGen prefix or ``.node``, ``.vtk``, ``.vtu``, ``.msh``, ``.mesh``;
    the bundled ``meshes/sphere``, ``meshes/box``, ``meshes/torus`` from any folder), or
    meshes a surface file (``.ply``, ``.obj``, ``.off``, ``.stl``) aiming at ``target_tets``.

    Raises ``FileNotFoundError``, ``OSError`` or ``ValueError`` (bad content)."""
    return _tetrasim.read_mesh(os.fspath(path), target_tets)


def prep(
    surface: PathLike,
    target_tets: Optional[int] = None,
    mesher: str = "tetgen",
    quality: Optional[float] = 2.0,
) -> Mesh:
    """Meshes a closed surface file into tets as ``tetprep`` does (repair, then TetGen with
    the radius-edge bound ``quality``, aiming at ``target_tets``; ``mesher="voxel"`` for the
    grid mesher). Raises ``FileNotFoundError``, ``ValueError`` or ``RuntimeError``."""
    return _tetrasim.prep(os.fspath(surface), target_tets, mesher, quality)


def mesh_from_meshio(m: Any, label: str = "meshio") -> Mesh:
    """A ``Mesh`` from a ``meshio.Mesh`` holding a ``tetra`` cell block (other blocks are
    ignored; unused nodes are kept). Raises ``ValueError`` without tetrahedra."""
    blocks = [c.data for c in m.cells if c.type == "tetra"]
    if not blocks:
        raise ValueError("the meshio mesh has no `tetra` cells")
    tets = np.concatenate(blocks).astype(np.int64)
    return Mesh(np.asarray(m.points, dtype=np.float64)[:, :3], tets, label)


def mesh_to_meshio(mesh: Mesh) -> Any:
    """The mesh as a ``meshio.Mesh`` (points and one ``tetra`` block)."""
    import meshio

    return meshio.Mesh(mesh.nodes, [("tetra", mesh.tets)])


def mesh_to_pyvista(mesh: Mesh) -> Any:
    """The mesh as a ``pyvista.UnstructuredGrid`` of tetrahedra (needs PyVista:
    ``pip install pyvista``)."""
    try:
        import pyvista
    except ImportError as e:
        raise ImportError("to_pyvista needs PyVista: pip install pyvista") from e
    return pyvista.UnstructuredGrid({pyvista.CellType.TETRA: mesh.tets}, mesh.nodes)


# Mesh methods in the Python layer, and pickling (for Ray and process pools). ``points``
# and ``cells`` are meshio's names (``meshio.Mesh(m.points, m.cells)`` works);
# ``nodes`` and ``tets`` are kept.
Mesh.from_meshio = staticmethod(mesh_from_meshio)  # type: ignore[attr-defined]
Mesh.to_meshio = mesh_to_meshio  # type: ignore[attr-defined]
Mesh.to_pyvista = mesh_to_pyvista  # type: ignore[attr-defined]
Mesh.points = property(lambda m: m.nodes, doc="Node positions, (n, 3) float64 (meshio's name).")  # type: ignore[attr-defined]
Mesh.cells = property(  # type: ignore[attr-defined]
    lambda m: {"tetra": m.tets}, doc="The cells by type, ``{\"tetra\": (t, 4) int64}`` (meshio's ``cells_dict``)."
)
copyreg.pickle(Mesh, lambda m: (Mesh, (m.nodes, m.tets, m.label)))


def _mesh(mesh: Union[Mesh, PathLike]) -> Mesh:
    if isinstance(mesh, Mesh):
        return mesh
    return read_mesh(mesh)


def _params(overrides: dict) -> str:
    params = default_params()
    unknown = sorted(set(overrides) - set(params) - {"density", "node_mass", "accuracy"})
    if unknown:
        raise TypeError(
            f"unknown parameter(s) {', '.join(unknown)}; known: {', '.join(sorted(params))}, "
            "density, node_mass, accuracy"
        )
    overrides = dict(overrides)
    # The speed/accuracy dial first; every parameter given beside it overrides it.
    accuracy = overrides.pop("accuracy", None)
    if accuracy is not None:
        params = json.loads(_tetrasim.accuracy_params(str(accuracy)))
    density = overrides.pop("density", None)
    node_mass = overrides.pop("node_mass", None)
    if density is not None and node_mass is not None:
        raise ValueError("give `density` or `node_mass`, not both")
    if density is not None:
        params["mass"] = {"mode": "density", "density": float(density)}
    if node_mass is not None:
        params["mass"] = {"mode": "per-node", "mass": float(node_mass)}
    gravity = overrides.get("gravity")
    if gravity is not None and not isinstance(gravity, (int, float)):
        overrides["gravity"] = [float(g) for g in gravity]
    params.update(overrides)
    # A material given by its Young's modulus runs as the scene's object would: the finite
    # elements unless a parameter asks for springs (``tetrascene::scene::material_method``).
    if "method" not in overrides and params.get("youngs_modulus") is not None:
        params["method"] = _tetrasim.material_method(json.dumps(params))
    return json.dumps(params)


def _quaternion(rotation: Sequence[float]) -> Tuple[float, float, float, float]:
    q = tuple(float(c) for c in rotation)
    if len(q) != 4:
        raise ValueError(f"`rotation` must be a quaternion (w, x, y, z), got {len(q)} numbers")
    length = sum(c * c for c in q) ** 0.5
    if abs(length - 1.0) > 1e-3:
        raise ValueError(f"`rotation` must be a unit quaternion (w, x, y, z), got length {length}")
    return q


class Simulation:
    """One mesh under one parameter set on one backend.

    ``mesh``: a ``Mesh`` or a path for ``read_mesh``. ``backend``: ``"cpu"`` (all cores),
    ``"cpu-ref"`` (the double-precision reference) or ``"vulkan"`` (the GPU).
    ``fit_size`` [m]: scale the mesh so its largest side is this (``None``: keep its size);
    ``drop_height`` [m]: its lowest node this far above the floor, centred over the origin
    when fitted (``None``: keep its position); ``rotation``: a unit quaternion
    ``(w, x, y, z)`` turning the mesh about its bounding box's centre before it is placed
    (``(0.7071, -0.7071, 0, 0)`` stands a Z-up part on the floor); ``offset`` [m]: then
    moved by this (objects start apart). ``pins``: node indices that never move (unless
    ``set_state`` moves them); ``pin_boxes``: ``((x0, y0, z0), (x1, y1, z1))`` boxes [m,
    after placement] whose nodes are pinned. ``self_contact``: the surface collides with
    itself (the scene key ``self_contact``). ``params``: any run parameter by its name
    (``default_params()`` lists them, e.g. ``method="distance"`` (default ``"volume"``;
    ``"neo-hookean"`` for a material given by ``youngs_modulus`` unless springs are asked for),
    ``dt=1e-3``, ``iterations=10``, ``solver="gauss-seidel"``, ``youngs_modulus=1e5``,
    ``poisson_ratio=0.45``, ``contact="split"`` (no rebound, at twice the solve)), plus
    ``density`` [kg/m^3] or ``node_mass`` [kg] (a ``youngs_modulus`` needs a ``density``)
    and ``accuracy``: ``"fast"``, ``"balanced"`` or ``"accurate"``, the speed/accuracy dial
    (solver, groups, iterations, substeps and dt; any of them given beside it wins).
    ``device`` (``backend="vulkan"`` only): the GPU, by a part of its name or its index in
    ``tetrasim info``'s list, as ``tetrasim run --device`` takes it (default: the best).

    A simulation is a context manager: ``with tetrasim.Simulation(...) as sim:`` closes it
    at the end (``close()`` frees its backend and, on ``vulkan``, its GPU memory at once).

    Raises ``TypeError`` for an unknown parameter name, ``ValueError`` for a bad value (the
    engine's message names it), ``OSError`` for mesh files, ``RuntimeError`` for the GPU.
    """

    def __init__(
        self,
        mesh: Union[Mesh, PathLike],
        *,
        backend: str = "cpu",
        fit_size: Optional[float] = 1.0,
        drop_height: Optional[float] = 0.1,
        offset: Sequence[float] = (0.0, 0.0, 0.0),
        rotation: Optional[Sequence[float]] = None,
        pins: Iterable[int] = (),
        pin_boxes: Sequence[Tuple[Sequence[float], Sequence[float]]] = (),
        self_contact: bool = False,
        device: Optional[Union[str, int]] = None,
        **params: Any,
    ) -> None:
        if isinstance(mesh, Scene):
            if params:
                raise TypeError(
                    "a Scene carries its own parameters; set them on it (scene.override(...))"
                )
            self.mesh = None
            self._sim, self.scene_frames = _tetrasim._Simulation.from_scene_text(
                mesh.to_toml(), os.getcwd(), backend, None if device is None else str(device)
            )
            return
        self.mesh = _mesh(mesh)
        boxes = [(tuple(map(float, lo)), tuple(map(float, hi))) for lo, hi in pin_boxes]
        self._sim = _tetrasim._Simulation(
            self.mesh,
            _params(params),
            backend,
            fit_size,
            drop_height,
            [int(i) for i in pins],
            boxes,
            tuple(map(float, offset)),
            bool(self_contact),
            None if rotation is None else _quaternion(rotation),
            None if device is None else str(device),
        )

    #: Frames the scene asks for (``solver.frames``), for a simulation made by ``from_scene``.
    scene_frames: Optional[int] = None

    @classmethod
    def from_scene(
        cls,
        path: PathLike,
        backend: str = "cpu",
        device: Optional[Union[str, int]] = None,
        **overrides: Any,
    ) -> "Simulation":
        """The scene file ``path`` (TOML: objects with their meshes, placement, materials,
        pins and velocities, colliders, ``[solver]``) staged as ``tetrasim run --scene``
        stages it, on ``backend``. ``scene_frames`` is the frames it asks for; its
        ``[output]`` is the command line's and not written here (``record()`` and ``write``
        are). ``mesh`` is ``None`` (the objects are one model). Raises ``FileNotFoundError``,
        ``ValueError`` naming the scene key that is wrong, ``OSError``. ``overrides`` take
        their values over the file's, as flags do on the command line (``Scene.override``:
        ``[solver]`` keys, ``method``, material keys)."""
        if overrides:
            return cls(Scene.from_toml(path).override(**overrides), backend=backend, device=device)
        self = cls.__new__(cls)
        self.mesh = None
        self._sim, self.scene_frames = _tetrasim._Simulation.from_scene(
            os.fspath(path), backend, None if device is None else str(device)
        )
        return self

    @classmethod
    def from_record(cls, record: dict, mesh: Union[Mesh, PathLike, None] = None, **kw: Any) -> "Simulation":
        """A simulation with the parameters and backend of a run record (``record()`` or a
        record of ``tetrasim run --json``), on ``mesh`` (default: the record's)."""
        return cls(mesh if mesh is not None else record["mesh"], backend=record["backend"], **record["params"], **kw)

    def save(self, path: PathLike) -> None:
        """Saves the run to a checkpoint file (through a temporary file): its state, what
        its steps carry (warm-started multipliers, the finite elements' forces, the colliders'
        clock) and its record so far. Backends ``cpu-ref``, ``cpu``, and ``vulkan`` without
        warm-started springs."""
        self._sim.save(os.fspath(path))

    def load(self, path: PathLike) -> None:
        """Resumes a checkpoint saved by a simulation built the same way (mesh, placement,
        parameters, backend): the next ``step`` continues the saved run bit for bit.
        Raises ``ValueError`` for a checkpoint that is truncated, corrupt or of another
        run (saying what differs), ``FileNotFoundError`` for a missing one."""
        self._sim.load(os.fspath(path))

    def close(self) -> None:
        """Frees the backend (on ``vulkan`` its GPU memory and objects) now rather than when
        the simulation is garbage-collected; later calls that need it raise
        ``RuntimeError``. Closing twice is harmless."""
        self._sim.close()

    def __enter__(self) -> "Simulation":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def step(self, frames: int = 1) -> None:
        """Advances ``frames`` frames (``substeps`` time steps of ``dt`` each), releasing the
        GIL. Raises ``DivergedError`` when the run diverges."""
        self._sim.step(frames)

    @property
    def positions(self) -> np.ndarray:
        """Node positions [m], ``(n, 3)`` float64 (a copy)."""
        return self._sim.positions

    @property
    def velocities(self) -> np.ndarray:
        """Node velocities [m/s], ``(n, 3)`` float64 (a copy)."""
        return self._sim.velocities

    def set_state(self, positions: Any, velocities: Any = None) -> None:
        """Replaces positions [m] and velocities [m/s] (``(n, 3)``; ``velocities=None`` keeps
        the current ones)."""
        positions = np.ascontiguousarray(positions, dtype=np.float64)
        if velocities is not None:
            velocities = np.ascontiguousarray(velocities, dtype=np.float64)
        self._sim.set_state(positions, velocities)

    @property
    def volume_ratio(self) -> float:
        """Total volume over rest volume now (1.0: kept)."""
        return self._sim.volume_ratio

    @property
    def pin_force(self) -> np.ndarray:
        """The force [N] the pinned nodes (pins and clamps) exerted on the bodies in the last
        step, ``(3,)`` float64: a body hanging at rest from its pins is held by its weight.
        ``cpu`` and ``cpu-ref`` (``vulkan`` raises ``RuntimeError`` for now)."""
        return self._sim.pin_force

    @property
    def floor_force(self) -> np.ndarray:
        """The floor's force [N] on the bodies in the last step, ``(3,)`` float64."""
        return self._sim.floor_force

    @property
    def collider_forces(self) -> np.ndarray:
        """Each kinematic collider's force [N] on the bodies in the last step,
        ``(colliders, 3)`` float64, in the scene's order (the floor is ``floor_force``)."""
        return self._sim.collider_forces

    @property
    def clamp_forces(self) -> np.ndarray:
        """Each clamp's force [N] on the bodies in the last step, ``(clamps, 3)`` float64,
        in the scene's order: a share of ``pin_force`` (a tensile test's force is its
        moving clamp's)."""
        return self._sim.clamp_forces

    @property
    def frames(self) -> int:
        """Frames completed."""
        return self._sim.frames

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self._sim.time

    @property
    def backend(self) -> str:
        """The backend's name."""
        return self._sim.backend

    def record(self) -> dict:
        """The run record so far (per-frame ``volume_pct``, ``local_error_pct``,
        ``inverted_tets``, ``time_s``, their summaries, ``params``): what ``tetrasim run
        --json`` writes for one method."""
        return json.loads(self._sim.record_json())

    def write(self, path: PathLike) -> None:
        """Writes the deformed mesh, the format from the extension: ``.vtk``, ``.vtu`` (tet
        mesh with displacement, velocity, volume ratio, pinned and inverted fields), ``.ply``
        (surface with per-vertex volume ratio), ``.obj`` (surface) or ``.usda`` (a USD
        stage of one time sample; ``Series`` writes a whole run)."""
        self._sim.write(os.fspath(path))

    def __repr__(self) -> str:
        what = repr(self.mesh) if self.mesh is not None else "scene"
        return f"Simulation({what}, backend={self.backend!r}, frames={self.frames})"


class Series:
    """A simulation's frames as one series of files, added as the script steps::

        with tetrasim.Series(sim, "out/run.usda") as series:
            series.add()                   # frame 0
            for _ in range(100):
                sim.step(10)
                series.add()               # frames 10, 20, ...

    ``path`` ending in ``.usda``: one animated USD stage (every body's surface, its points
    and ``volume_ratio`` time-sampled at the frames added, metres, up axis Y), written when
    the series closes; Blender, Houdini, Omniverse and usdview play it. Another ``path``: a
    folder (made with its parents) of one file per frame, ``frame_FFFFF.EXT`` in ``format``
    ``"vtu"`` (default; with ``series.pvd``, a ParaView time series rewritten at each add),
    ``"vtk"``, ``"ply"`` or ``"obj"``, as ``tetrasim run --format`` writes them.
    """

    def __init__(self, sim: Simulation, path: PathLike, format: Optional[str] = None) -> None:
        self._series = _tetrasim._Series(sim._sim, os.fspath(path), format)
        self._sim = sim

    def add(self) -> None:
        """Adds the simulation's current state as its current frame (``sim.frames``)."""
        self._series.add(self._sim._sim)

    @property
    def frames(self) -> list:
        """The frames added so far."""
        return self._series.frames

    def close(self) -> None:
        """Writes what waits for the end (the USD stage, through a temporary file)."""
        self._series.close()

    def __enter__(self) -> "Series":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


from .scene import Scene  # noqa: E402
from .sweep import sweep  # noqa: E402  (uses Simulation)
