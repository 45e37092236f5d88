#!/usr/bin/env bash
# Long runs that watch themselves (issue 54): the bundled sphere with the volume method on
# `cpu` for CPU_FRAMES (default 100000) and on `vulkan` (lavapipe where there is no GPU)
# for VULKAN_FRAMES (default 20000), each sampling resident memory, the allocator's device
# memory, total energy and volume 100 times (`tetrasim soak`). Fails (exit 1) when memory
# grows by more than 1 % after the first tenth of the run, the energy rises above its
# start, the volume leaves 100 +- 5 % or a run diverges. Each run's figures are on its
# last line; docs/SOAK.md has the figures of the last soak and the machine.
#
#   scripts/soak.sh [CPU_FRAMES] [VULKAN_FRAMES]    (0 skips that backend)
set -euo pipefail
cd "$(dirname "$0")/.."

cpu_frames=${1:-100000}
vulkan_frames=${2:-20000}
cargo build --release --bin tetrasim
tetrasim=target/release/tetrasim
failed=0
if [ "$cpu_frames" -gt 0 ]; then
    "$tetrasim" soak --method volume --backend cpu --frames "$cpu_frames" || failed=1
fi
if [ "$vulkan_frames" -gt 0 ]; then
    "$tetrasim" soak --method volume --backend vulkan --frames "$vulkan_frames" || failed=1
fi
exit $failed
