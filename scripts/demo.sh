#!/usr/bin/env bash
# The main job: the paper's `seed` experiment (free fall onto a floor, 400 frames) on the
# bundled mesh with every method, on the CPU reference and on Vulkan (lavapipe when no GPU),
# printing the paper-style table. Installs missing system packages first.
# Extra arguments go to `tetrasim run`, e.g. scripts/demo.sh --backend cpu --frames 100
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo run --release --bin tetrasim -- run --preset seed --method all "$@"
