"""``tetrasim.Scene``: a whole scene built in code, one to one with the scene file format
(``tetrasim run --scene``; every table and key is in docs/reference/scene.md): the ``[solver]`` keys as the constructor's keywords,
``add_body`` for an ``[[object]]``, ``add_collider`` for a ``[[collider]]``, ``add_grab``
for a ``[[grab]]`` (a handle holding nodes), ``output`` for ``[output]``. Keywords are named as the scene keys are. ``to_toml()`` writes the scene file
and ``Scene.from_toml`` reads one (text or a path); ``tetrasim.Simulation(scene)`` runs it
as the command line runs the file. The engine's own parser checks every scene: an error
names the key as the file would (``object[1].material.density``, ``collider[2].motion``).
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Optional, Union

from . import _tetrasim

PathLike = Union[str, "os.PathLike[str]"]

#: The ``material`` keys an object takes (also as ``add_body``'s keywords).
MATERIAL_KEYS = ("ks", "kd", "node_mass", "density", "youngs_modulus", "poisson_ratio", "damping")


def _plain(value: Any) -> Any:
    """``value`` with tuples, numpy arrays and numbers as JSON's lists and numbers, and
    ``None`` entries of dicts dropped (a scene file has no null)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items() if v is not None}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "tolist"):
        return _plain(value.tolist())
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return value


class Scene:
    """A scene: ``Scene(frames=600, dt=1e-3, gravity=[0, 0, -9.81], ...)`` takes the
    ``[solver]`` keys; then bodies, colliders and outputs are added. Relative mesh paths are
    taken from the working folder when added (from the file's folder when read), and kept
    absolute, so the scene runs and writes the same from anywhere."""

    def __init__(self, **solver: Any) -> None:
        self.solver: Dict[str, Any] = _plain(solver)
        self.objects: List[Dict[str, Any]] = []
        self.colliders: List[Dict[str, Any]] = []
        self.grabs: List[Dict[str, Any]] = []
        #: The ``[output]`` table: ``json``, ``out_dir``, ``every``, ``format``, ``units``.
        self.output: Dict[str, Any] = {}

    def add_body(
        self,
        mesh: PathLike,
        *,
        method: Optional[str] = None,
        material: Optional[Dict[str, Any]] = None,
        pin: Any = None,
        **keys: Any,
    ) -> int:
        """Adds an ``[[object]]``: ``mesh`` (a tet mesh or surface file), ``method``,
        ``material`` (a dict of ``MATERIAL_KEYS``, which may also be given as keywords:
        ``youngs_modulus=1e5, density=1050``), ``pin`` (one pin dict ``{"nodes": [...],
        "box": {"min": [...], "max": [...]}, "motion": {...}}`` or a list of them), and the
        object keys ``fit_size``, ``drop_height``, ``rotation`` ([w, x, y, z]), ``offset``,
        ``velocity``, ``self_contact``, ``target_tets``. Returns its index."""
        if not isinstance(mesh, (str, os.PathLike)):
            raise TypeError(
                "`mesh` must be a path (write a Mesh built from arrays first: mesh.write('part.vtu'))"
            )
        material = dict(material or {})
        for key in MATERIAL_KEYS:
            if key in keys:
                material[key] = keys.pop(key)
        body = {"mesh": os.path.abspath(os.fspath(mesh)), "method": method, **keys}
        body.update(material=material or None, pin=pin)
        self.objects.append(_plain(body))
        return len(self.objects) - 1

    def add_collider(self, type: str, **keys: Any) -> int:
        """Adds a ``[[collider]]`` of ``type`` (``"floor"``, ``"plane"``, ``"sphere"``,
        ``"box"``, ``"capsule"`` or ``"mesh"``) with its keys (``normal``, ``distance``,
        ``center``, ``radius``, ``half_extents``, ``rotation``, ``a``, ``b``, ``mesh``,
        ``cells``, ``friction``, ``thickness``, ``motion``). Returns its index (the floor
        counts, as in a file)."""
        collider = {"type": type, **keys}
        if type == "mesh" and "mesh" in collider:
            collider["mesh"] = os.path.abspath(os.fspath(collider["mesh"]))
        self.colliders.append(_plain(collider))
        return len(self.colliders) - 1

    def add_grab(self, point: Any, radius: float, **keys: Any) -> int:
        """Adds a ``[[grab]]``: a handle holding the free nodes within ``radius`` [m] of
        ``point`` [m] at the start, moved by its ``motion`` (as a collider's), hard or
        through a spring of ``stiffness`` [N/m], letting go at ``release`` [s]. Returns its
        index."""
        self.grabs.append(_plain({"point": point, "radius": radius, **keys}))
        return len(self.grabs) - 1

    def to_dict(self) -> Dict[str, Any]:
        """The scene's tables, as a scene file holds them."""
        tables: Dict[str, Any] = {}
        if self.solver:
            tables["solver"] = dict(self.solver)
        tables["object"] = [dict(o) for o in self.objects]
        if self.colliders:
            tables["collider"] = [dict(c) for c in self.colliders]
        if self.grabs:
            tables["grab"] = [dict(g) for g in self.grabs]
        output = _plain(self.output)
        if output:
            tables["output"] = {
                k: os.path.abspath(v) if k in ("json", "out_dir") else v for k, v in output.items()
            }
        return tables

    def to_toml(self) -> str:
        """The scene file's text (checked by the engine's parser first)."""
        return _tetrasim.scene_toml(json.dumps(self.to_dict()))

    def write(self, path: PathLike) -> None:
        """Writes the scene file."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.to_toml())

    @classmethod
    def from_toml(cls, source: Union[str, PathLike]) -> "Scene":
        """A scene from a scene file's text, or from the file at a path (its relative paths
        taken from its folder)."""
        text, base = os.fspath(source), os.getcwd()
        if "\n" not in text and os.path.exists(text):
            base = os.path.dirname(os.path.abspath(text))
            with open(text, encoding="utf-8") as f:
                text = f.read()
        tables = json.loads(_tetrasim.scene_json(text))
        scene = cls(**tables.get("solver", {}))
        for body in tables.get("object", []):
            body = dict(body)
            scene.add_body(os.path.join(base, body.pop("mesh")), **body)
        for collider in tables.get("collider", []):
            collider = dict(collider)
            for key in ("mesh", "path"):  # `path` before 2026-12-06
                if collider.get("type") == "mesh" and key in collider:
                    collider[key] = os.path.join(base, collider[key])
            scene.add_collider(**collider)
        for grab in tables.get("grab", []):
            scene.add_grab(**grab)
        scene.output = {
            k: os.path.join(base, v) if k in ("json", "out_dir", "dir") else v
            for k, v in tables.get("output", {}).items()
        }
        return scene

    def override(self, **values: Any) -> "Scene":
        """Sets values over the scene's, as ``tetrasim run --scene S`` takes flags over the
        file's: ``[solver]`` keys, ``method`` (every object's) and ``MATERIAL_KEYS`` (every
        object's material; a Young's modulus replaces the spring constants, a density the
        node mass, and the other way round). Returns the scene."""
        method = values.pop("method", None)
        material = {k: values.pop(k) for k in MATERIAL_KEYS if k in values}
        self.solver.update(_plain(values))
        replaces = {
            "youngs_modulus": ("ks", "kd", "poisson_ratio", "damping"),
            "ks": ("youngs_modulus", "poisson_ratio", "damping"),
            "kd": ("youngs_modulus", "poisson_ratio", "damping"),
            "density": ("node_mass",),
            "node_mass": ("density",),
        }
        for body in self.objects:
            if method is not None:
                body["method"] = method
            if material:
                own = dict(body.get("material", {}))
                for key in material:
                    for other in replaces.get(key, ()):
                        own.pop(other, None)
                own.update(_plain(material))
                body["material"] = own
        return self

    def __repr__(self) -> str:
        return f"Scene({len(self.objects)} bodies, {len(self.colliders)} colliders, solver={self.solver})"
