"""Parameter sweeps: many independent runs, on a Ray cluster when Ray is installed, on local
processes otherwise. The same settings give the same records either way (the ``cpu`` and
``cpu-ref`` backends are deterministic; only the timing fields differ)."""

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from typing import Any, Dict, List, Optional, Sequence

#: Keys of a setting that are not run parameters.
RUN_KEYS = ("mesh", "backend", "frames", "fit_size", "drop_height", "pins", "pin_boxes")

#: Record fields that measure time, not physics: they differ between two runs of a setting.
TIMING_FIELDS = ("ms_per_frame", "wall_s", "passes")


def run_setting(setting: Dict[str, Any], mesh: Any = None) -> Dict[str, Any]:
    """Runs one setting and returns its record (a diverged run returns its record too, with
    ``diverged`` set). ``setting``: ``mesh`` (a ``Mesh`` or path; default the bundled
    sphere), ``backend`` (default ``cpu``), ``frames`` (default 400), ``fit_size``,
    ``drop_height``, ``pins``, ``pin_boxes`` and any run parameter by its name."""
    from . import DivergedError, Simulation

    setting = dict(setting)
    mesh = mesh if mesh is not None else setting.pop("mesh", "meshes/sphere")
    setting.pop("mesh", None)
    frames = int(setting.pop("frames", 400))
    sim = Simulation(mesh, **setting)
    try:
        sim.step(frames)
    except DivergedError:
        pass
    return sim.record()


def _mesh_key(mesh: Any) -> Any:
    return os.fspath(mesh) if isinstance(mesh, (str, os.PathLike)) else id(mesh)


def sweep(
    settings: Sequence[Dict[str, Any]],
    *,
    use_ray: Optional[bool] = None,
    processes: Optional[int] = None,
    dataframe: bool = True,
) -> Any:
    """Runs every setting (a dict, see ``run_setting``) and gathers the records, in the
    order of ``settings``.

    ``use_ray``: ``None`` uses Ray when it is importable (connecting to the cluster
    ``ray.init()`` finds, or starting a local one; call ``ray.init(address=...)`` first to
    use a running cluster), ``True`` requires it, ``False`` runs on ``processes`` local
    processes (default: the CPU count; 1 runs in this process). On Ray each mesh is read
    once and shipped through the object store; each setting is one task.

    Returns a pandas ``DataFrame`` (one row per setting: its keys, then the record's
    scalar fields, and the whole record in the ``record`` column) when pandas is installed
    and ``dataframe``; otherwise the list of records.
    """
    settings = [dict(s) for s in settings]
    ray = None
    if use_ray is None or use_ray:
        try:
            import ray  # type: ignore[no-redef]
        except ImportError:
            if use_ray:
                raise
            ray = None
    if ray is not None:
        records = _on_ray(ray, settings)
    else:
        records = _on_processes(settings, processes)
    if not dataframe:
        return records
    try:
        import pandas as pd
    except ImportError:
        return records
    rows = []
    for setting, record in zip(settings, records):
        row = {k: (v if isinstance(v, (int, float, str, bool)) or v is None else str(v)) for k, v in setting.items()}
        row.update({k: v for k, v in record.items() if isinstance(v, (int, float, str, bool)) or v is None})
        row["record"] = record
        rows.append(row)
    return pd.DataFrame(rows)


def _on_ray(ray: Any, settings: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
    from . import read_mesh

    if not ray.is_initialized():
        ray.init()
    task = ray.remote(run_setting)
    # Each mesh once: read here (a path) and put into the object store; tasks get a ref.
    refs: Dict[Any, Any] = {}
    futures = []
    for setting in settings:
        mesh = setting.pop("mesh", "meshes/sphere")
        key = _mesh_key(mesh)
        if key not in refs:
            loaded = read_mesh(mesh) if isinstance(mesh, (str, os.PathLike)) else mesh
            refs[key] = ray.put(loaded)
        futures.append(task.remote(setting, refs[key]))
    return list(ray.get(futures))


def _on_processes(settings: List[Dict[str, Any]], processes: Optional[int]) -> List[Dict[str, Any]]:
    workers = processes or os.cpu_count() or 1
    if workers <= 1 or len(settings) <= 1:
        return [run_setting(s) for s in settings]
    # Spawned, not forked: a fork copies no threads, so a child would wait forever on
    # rayon's global pool if this process had started it (a run whose team is one thread,
    # as with RAYON_NUM_THREADS=1, does).
    spawn = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=spawn) as pool:
        return list(pool.map(run_setting, settings))
