#!/usr/bin/env bash
# Stages everything a bare GPU machine (no Rust, no package registry, no network) needs to
# measure tetrasim into target/gpu-bundle/ (ignored by git): the release binaries, the GPU
# test binaries, the Vulkan loader with libglvnd (the NVIDIA driver needs both) and the
# validation layer as .deb files, tet meshes made here, the scans, and scripts/gpu-report.sh.
# Run from the project root:
#   scripts/gpu-bundle.sh [--old BINARY] [--cpu BINARY]
# --old: another build of `tetrasim` to bench beside this one (old beside new);
# --cpu: another build to measure the `cpu` backend's thread scaling with.
# Then run `bash target/gpu-bundle/gpu-report.sh` on the GPU machine from the project root
# (the device tool: carry ["target/gpu-bundle"]); figures land in $OUT/gpu-<device>/, to be
# copied to docs/data/. Follows ../shared/gpu/bundle.sh, which measured the first H200 run.
set -euo pipefail
old=""; cpu=""
while [ $# -gt 0 ]; do
  case $1 in
    --old) old=$2; shift 2 ;;
    --cpu) cpu=$2; shift 2 ;;
    *) echo "gpu-bundle.sh: unknown argument \`$1\` (known: --old BINARY, --cpu BINARY)" >&2; exit 2 ;;
  esac
done
for f in "$old" "$cpu"; do
  if [ -n "$f" ] && [ ! -x "$f" ]; then echo "gpu-bundle.sh: \`$f\` is not an executable" >&2; exit 2; fi
done
command -v xz >/dev/null || { echo "gpu-bundle.sh: xz is missing (apt-get install xz-utils): it packs the binaries" >&2; exit 2; }
[ -d ../shared/meshes ] || { echo "gpu-bundle.sh: ../shared/meshes is missing (run from the project root)" >&2; exit 2; }
t=${CARGO_TARGET_DIR:-target}
b=target/gpu-bundle
rm -rf "$b"; mkdir -p "$b/bin" "$b/tests" "$b/debs" "$b/meshes" "$b/project" "$b/shared"
echo "building (release) ..."
cargo build --release --workspace -q
cp "$t/release/tetrasim" "$t/release/tetprep" "$b/bin/"
[ -n "$old" ] && cp "$old" "$b/bin/tetrasim-old"
[ -n "$cpu" ] && cp "$cpu" "$b/bin/tetrasim-cpu"
tests=(gpu_lifecycle gpu_matches_cpu gpu_validation determinism gpu_frames_in_flight gpu_free_fall
       atomics_paths_agree gpu_timing gpu_warm_start backends_match_reference_settings gpu_colliders
       gpu_body_contact anderson inversion block_gauss_seidel gpu_minres gpu_descriptor_sets
       gpu_clamps gpu_grabs gpu_cli render extremes gpu_finite_elements squash_recovery forces_out
       gpu_coarse_twin gpu_elastic_solve_twin)
args=(); for n in "${tests[@]}"; do [ -f "tests/$n.rs" ] && args+=(--test "$n"); done
cargo test --release --no-run "${args[@]}" 2>&1 | sed -n 's/.*Executable tests\/\([a-z_0-9]*\)\.rs (\(.*\))/\1 \2/p' |
  while read -r name path; do cp "$path" "$b/tests/$name"; done
strip "$b"/bin/* "$b"/tests/* 2>/dev/null || true
# The binaries share most of their code (about 140 MiB stripped: 22 test binaries and up to
# three builds of the CLI). xz's window (64 MiB at -9) spans several of them, so one archive
# holds each shared part once: about 6 MiB, where gzip's 32 KiB window gave 29 MiB for 17
# test binaries alone and the bundle outgrew the device tool's 64 MiB carry limit.
echo "packing the binaries (xz -9, about half a minute) ..."
tar cf - -C "$b" bin tests | xz -9 > "$b/binaries.tar.xz" && rm -rf "$b/bin" "$b/tests"
echo "downloading the Vulkan loader, libglvnd and the validation layer (.deb) ..."
lists=$(mktemp -d); mkdir -p "$lists/partial"
o="-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=$lists"
apt-get $o update -qq
(cd "$b/debs" && apt-get $o download -qq libvulkan1 libglvnd0 libgl1 libglx0 libegl1 libopengl0 libgles2 vulkan-validationlayers 2>/dev/null)
echo "meshing ..."
"$t/release/tetprep" ../shared/meshes/bun_zipper.ply -o "$b/meshes/bunny20k" --target-tets 20000 >/dev/null
"$t/release/tetprep" ../shared/meshes/horse.ply -o "$b/meshes/horse86m" --preserve-surface --quality 0 >/dev/null
# the test binaries read meshes/ and tests/data at the path they were built in, and the
# scans at ../shared/meshes beside it
cp -r meshes "$b/project/"; mkdir -p "$b/project/tests"; cp -r tests/data "$b/project/tests/"
cp -r ../shared/meshes "$b/shared/"
echo "$PWD" > "$b/build-path"; (cd "$t" && pwd) > "$b/target-path"
git rev-parse --short HEAD > "$b/commit" 2>/dev/null || echo unknown > "$b/commit"
git diff --quiet 2>/dev/null || echo "+changes" >> "$b/commit"
cp scripts/gpu-report.sh "$b/"
# The device tool carries the working tree (tracked files) and the bundle together, 64 MiB
# at most: say so here rather than there.
limit=$((64 * 1024 * 1024))
bundle=$(du -sb "$b" | cut -f1)
tree=$(git ls-files -z 2>/dev/null | xargs -0 du -cb 2>/dev/null | tail -1 | cut -f1)
total=$((bundle + ${tree:-0}))
echo "bundle $((bundle / 1024 / 1024)) MiB + working tree $((${tree:-0} / 1024 / 1024)) MiB = $((total / 1024 / 1024)) MiB (the device tool carries 64 MiB)"
if [ "$total" -gt "$limit" ]; then
  echo "gpu-bundle.sh: $b and the working tree come to $((total / 1024 / 1024)) MiB, over the device tool's 64 MiB: drop --old or --cpu, or meshes from $b/meshes" >&2
  exit 1
fi
