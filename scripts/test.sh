#!/usr/bin/env bash
# Runs the whole test suite (installs missing system packages first).
# GPU tests run on whatever Vulkan device is present; on machines without a GPU that is
# lavapipe, with the validation layer on.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# The Python with meshio that setup.sh made (tests/mesh_readers.rs).
[ -x target/py/bin/python ] && export TETRASIM_PYTHON="$PWD/target/py/bin/python"
# The house rules (Cargo.toml's [workspace.lints], ARCHITECTURE.md): any warning fails.
# Release mode shares the build of shaderc with the tests below.
cargo clippy --workspace --release -- -D warnings
cargo test --workspace --release "$@"
# The documentation site (mdBook, docs/SUMMARY.md); the tests above ran the guide's commands
# and checked the generated reference pages, and the Python suite below runs its blocks.
scripts/docs.sh --site
# The Python package: built into a fresh venv with the README's command, then its pytest suite.
scripts/test-python.sh
