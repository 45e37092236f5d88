"""Sweeps: 16 settings on a local Ray cluster give the records of the sequential run."""

import pytest

import tetrasim
from tetrasim.sweep import TIMING_FIELDS


def settings():
    out = []
    for method in ("distance", "volume"):
        for solver in ("jacobi", "gauss-seidel"):
            for iterations in (2, 5):
                for mesh in ("meshes/sphere", "meshes/box"):
                    out.append({"mesh": mesh, "method": method, "solver": solver,
                                "iterations": iterations, "frames": 40, "backend": "cpu"})
    return out


def strip(record):
    return {k: v for k, v in record.items() if k not in TIMING_FIELDS}


def test_a_sweep_on_ray_matches_the_sequential_records():
    ray = pytest.importorskip("ray")
    sequential = tetrasim.sweep(settings(), use_ray=False, processes=1, dataframe=False)
    assert len(sequential) == 16
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        table = tetrasim.sweep(settings(), use_ray=True)
    finally:
        ray.shutdown()
    assert len(table) == 16
    assert list(table["method"]) == [s["method"] for s in settings()]
    for mine, theirs in zip(table["record"], sequential):
        assert strip(mine) == strip(theirs)
    # The table carries the settings and the summaries.
    assert {"solver", "iterations", "avg_local_error_pct", "ms_per_frame"} <= set(table.columns)


def test_local_processes_give_the_same_records():
    few = settings()[:4]
    one = tetrasim.sweep(few, use_ray=False, processes=1, dataframe=False)
    two = tetrasim.sweep(few, use_ray=False, processes=2, dataframe=False)
    assert [strip(r) for r in one] == [strip(r) for r in two]
