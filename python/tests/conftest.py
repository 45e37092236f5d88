"""Shared fixtures: the repository root, the `tetrasim` command line built beside the
package (for comparing records with the CLI's), and a temporary folder."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture(scope="session")
def cli() -> str:
    """The release `tetrasim` binary (TETRASIM_CLI, else target/release/tetrasim)."""
    path = os.environ.get("TETRASIM_CLI", str(ROOT / "target" / "release" / "tetrasim"))
    if not os.path.exists(path):
        subprocess.run(["cargo", "build", "--release", "--bin", "tetrasim"], cwd=ROOT, check=True)
    return path


@pytest.fixture(autouse=True)
def in_root(monkeypatch):
    """Run from the repository root, as the README does (relative mesh paths)."""
    monkeypatch.chdir(ROOT)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """A skipped test is not a pass: under CI=true it fails (as the Rust suite does)."""
    outcome = yield
    report = outcome.get_result()
    if report.skipped and os.environ.get("CI") == "true":
        report.outcome = "failed"
        report.longrepr = f"skipped under CI=true: {report.longrepr}"
