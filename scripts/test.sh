#!/usr/bin/env bash
# Runs the whole test suite (installs missing system packages first).
# GPU tests run on whatever Vulkan device is present; on machines without a GPU that is
# lavapipe, with the validation layer on.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo test --workspace --release "$@"
