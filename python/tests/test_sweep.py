"""Sweeps: 16 settings on a local Ray cluster give the records of the sequential run."""

import os
import signal
import subprocess
import sys
import textwrap

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


def test_local_processes_run_after_the_engine_started_its_threads():
    """With one thread (`RAYON_NUM_THREADS=1`) the `cpu` backend's team is the caller and
    its loops run on rayon's global pool, which the first run starts; forked workers would
    then wait forever for pool threads a fork does not copy (they did, before the workers
    were spawned). In a child process, so that a hang fails the test."""
    script = textwrap.dedent(
        """
        import tetrasim

        few = [{"mesh": "meshes/box", "frames": 5, "iterations": k} for k in (2, 3)]
        tetrasim.sweep(few, use_ray=False, processes=1)
        records = tetrasim.sweep(few, use_ray=False, processes=2, dataframe=False)
        assert [r["frames_run"] for r in records] == [5, 5], records
        """
    )
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    child = subprocess.Popen([sys.executable, "-c", script], env=env, start_new_session=True)
    try:
        assert child.wait(timeout=120) == 0, "the sweep failed"
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)  # the child and its workers
        child.wait()
        pytest.fail("a sweep on 2 local processes hung")
