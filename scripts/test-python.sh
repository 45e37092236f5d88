#!/usr/bin/env bash
# Builds the Python package (python/) into a fresh venv with the README's command and runs
# its tests (python/tests/, pytest; usd-core is Pixar's USD reader, which opens our stages;
# PyVista is for Mesh.to_pyvista).
# scripts/test.sh runs it after the Rust suite, so the release `tetrasim` binary the tests
# compare against is built, and the package's Rust build reuses the release build of shaderc
# in target/.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/pytest-venv
rm -rf "$venv"
python3 -m venv "$venv"
"$venv/bin/pip" install -q --disable-pip-version-check pytest numpy "meshio==5.3.5" pandas "ray>=2.9" usd-core pyvista
# The README's install command, in the fresh venv.
"$venv/bin/pip" install -q --disable-pip-version-check ./python
cargo build --release --bin tetrasim
TETRASIM_CLI="$PWD/target/release/tetrasim" "$venv/bin/python" -m pytest -q python/tests "$@"
