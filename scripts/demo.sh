#!/usr/bin/env bash
# The main job: the paper's `seed` experiment (free fall onto a floor, 400 frames) on the
# bundled sphere with every method, in Vulkan compute shaders (lavapipe when there is no GPU),
# printing the paper-style table and the per-pass GPU times. Installs missing system
# packages first. Extra arguments go to `tetrasim run`, e.g.
#   scripts/demo.sh --backend cpu-ref        # the f64 reference instead
#   scripts/demo.sh --mesh meshes/torus --json torus.json
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo build --release --workspace
exec target/release/tetrasim run --preset seed --method all --backend vulkan "$@"
