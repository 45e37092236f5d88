#!/usr/bin/env bash
# Runs the GPU tests and the benchmarks on whatever Vulkan device the machine has and writes
# the figures under docs/data/gpu-<device>/ (device name lower-cased, non-alphanumerics as
# '-'), so a machine with a real GPU adds its own folder beside lavapipe's:
#   info.txt        `tetrasim info`
#   tests.txt       the GPU tests (validation layer on; any message fails them)
#   bench-*.json    `tetrasim bench` on the bunny, per solver (jacobi, gauss-seidel:8+global)
#   scaling/        `tetrasim scaling` up to 1M tets (volume and mss, vulkan and cpu)
#   tradeoff/       `tetrasim tradeoff` on the bunny (solvers x iterations x substeps)
#   plan.txt        `tetrasim plan` of the bunny (bytes per frame, bandwidth-bound times)
# Usage: scripts/gpu-report.sh [--quick]   (needs ../shared/meshes/bun_zipper.ply)
set -euo pipefail
cd "$(dirname "$0")/.."
quick=()
sizes=1000,4000,16000,64000,256000,1000000
if [[ "${1:-}" == "--quick" ]]; then
    quick=(--quick)
    sizes=1000,4000
fi
scripts/setup.sh
cargo build --release --workspace
bin=target/release
device=$("$bin/tetrasim" info | sed -n 's/^device 0: \(.*\) \[.*/\1/p' | head -n 1)
if [[ -z "$device" ]]; then
    echo "gpu-report: no Vulkan device (tetrasim info lists none)" >&2
    exit 1
fi
slug=$(echo "$device" | tr '[:upper:]' '[:lower:]' | sed 's/[^a-z0-9]\+/-/g; s/^-//; s/-$//')
out="docs/data/gpu-$slug"
mkdir -p "$out"
echo "gpu-report: $device -> $out" >&2
"$bin/tetrasim" info > "$out/info.txt"

echo "gpu-report: GPU tests" >&2
CI=true cargo test --release --test gpu_matches_cpu --test gpu_validation --test gpu_timing \
    --test gpu_free_fall --test determinism --test backends_match_reference_settings \
    -- --nocapture > "$out/tests.txt" 2>&1

mesh=../shared/meshes/bun_zipper.ply
bunny=$(mktemp -d)/bunny
"$bin/tetprep" "$mesh" -o "$bunny" --target-tets 20000 >&2
"$bin/tetrasim" plan --mesh "$bunny" --method volume > "$out/plan.txt"
for solver in jacobi gauss-seidel:8+global; do
    echo "gpu-report: bench, solver $solver" >&2
    "$bin/tetrasim" bench "${quick[@]}" --mesh "$bunny" --backend vulkan,cpu --solver "$solver" \
        --json "$out/bench-${solver//[:+]/-}.json" > "$out/bench-${solver//[:+]/-}.txt"
done
echo "gpu-report: scaling to $sizes tets" >&2
"$bin/tetrasim" scaling --sizes "$sizes" --out-dir "$out/scaling" > "$out/scaling.txt"
echo "gpu-report: bunny trade-off" >&2
"$bin/tetrasim" tradeoff "${quick[@]}" --mesh "$bunny" --methods volume \
    --solvers jacobi,gauss-seidel:8,gauss-seidel:8+global --out-dir "$out/tradeoff" \
    > "$out/tradeoff.txt"
echo "gpu-report: done; figures in $out" >&2
