#!/usr/bin/env bash
# Fuzzes every mesh reader, the scene parser (with its staging), the checkpoint reader and
# the Python layer's array checks:
# builds the cargo-fuzz targets in fuzz/ (nightly, libFuzzer) and runs each in turn for
# SECONDS (default 60) with its seed corpus (fuzz/corpus/TARGET, made here from tests/data,
# meshes/, examples/scenes and a checkpoint of the bundled box) and its dictionary
# (fuzz/dict/mesh.dict, fuzz/dict/scene.dict). The scene and checkpoint targets build the
# engine, and with it shaderc, once per toolchain (about 15 minutes on 2 cores).
# Limits: 10 s per input, 2 GiB of memory. A crash, hang or out-of-memory input is copied
# to fuzz/regressions/TARGET/, which tests/fuzz_regressions.rs replays on stable; the script
# goes on with the other targets and exits non-zero at the end, naming them.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]
#       targets: surface tet_mesh sniffed tetgen scene checkpoint arrays
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(surface tet_mesh sniffed tetgen scene checkpoint arrays)

if ! rustup toolchain list | grep -q '^nightly'; then
    echo "fuzz: cargo-fuzz needs a nightly toolchain: rustup toolchain install nightly" >&2
    exit 1
fi
command -v cargo-fuzz > /dev/null || cargo install cargo-fuzz --locked

# Seed corpora: every fixture, prefixed with the byte that picks its format where the
# target takes one (see tetmesh::mesh::io::fuzzing).
seed() { # seed TARGET NAME PICK FILE...   (PICK "-": no format byte)
    local target=$1 name=$2 pick=$3
    shift 3
    mkdir -p "fuzz/corpus/$target"
    {
        [ "$pick" = "-" ] || printf "\\x$(printf %02x "$pick")"
        local first=1
        for f in "$@"; do
            [ $first = 1 ] || printf '\xff'
            first=0
            cat "$f"
        done
    } > "fuzz/corpus/$target/seed-$name"
}
for f in tests/data/meshio/*.vtk tests/data/meshio/*.vtu tests/data/meshio/*.msh tests/data/meshio/*.mesh; do
    case $f in *.vtk) pick=0 ;; *.vtu) pick=1 ;; *.msh) pick=2 ;; *.mesh) pick=3 ;; esac
    seed tet_mesh "$(basename "$f")" "$pick" "$f"
    seed sniffed "$(basename "$f")" - "$f"
done
for prefix in meshes/box meshes/sphere meshes/torus tests/data/meshio/box; do
    name=$(echo "$prefix" | tr / _)
    if [ -f "$prefix.face" ]; then
        seed tetgen "$name" - "$prefix.node" "$prefix.ele" "$prefix.face"
    else
        seed tetgen "$name" - "$prefix.node" "$prefix.ele"
    fi
done
for f in meshes/*_surface.off; do seed surface "$(basename "$f")" 2 "$f"; done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' > "$tmp/tet.ply"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' > "$tmp/tet.obj"
printf 'solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid t\n' > "$tmp/tet.stl"
seed surface tet.ply 0 "$tmp/tet.ply"
seed surface tet.obj 1 "$tmp/tet.obj"
seed surface tet.stl 3 "$tmp/tet.stl"
for f in examples/scenes/*.toml; do seed scene "$(basename "$f")" - "$f"; done
# A checkpoint of the run the checkpoint target checks against (the bundled box's scene).
printf '[[object]]\nmesh = "%s"\n' "$PWD/meshes/box" > "$tmp/box.toml"
cargo build --release --bin tetrasim
target/release/tetrasim run --scene "$tmp/box.toml" --frames 3 --quiet \
    --checkpoint "$tmp/box.checkpoint" > /dev/null
seed checkpoint box - "$tmp/box.checkpoint"
# Arrays: the bundled box's nodes (3 columns, float64) and tets (4 columns, int64) as
# tetmesh::mesh::io::fuzzing::arrays_input writes them.
python3 - "$tmp/box.arrays" meshes/box << 'PY'
import struct, sys
def rows(path):  # the data lines of a TetGen file, after its count line
    lines = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    return [l[1:] for l in lines[1:]]
nodes = [float(v) for r in rows(sys.argv[2] + ".node") for v in r[:3]]
tets = [int(v) for r in rows(sys.argv[2] + ".ele") for v in r[:4]]  # numbered from 0
head = bytes([3, 4]) + struct.pack("<H", len(nodes) // 3)
body = struct.pack(f"<{len(nodes)}d", *nodes) + struct.pack(f"<{len(tets)}q", *tets)
open(sys.argv[1], "wb").write(head + body)
PY
seed arrays box - "$tmp/box.arrays"

failed=()
for target in "${targets[@]}"; do
    echo "== fuzz: $target for $seconds s"
    case $target in
        scene) dict=(-dict=fuzz/dict/scene.dict) ;;
        checkpoint | arrays) dict=() ;;
        *) dict=(-dict=fuzz/dict/mesh.dict) ;;
    esac
    log="fuzz/artifacts/$target.log"
    mkdir -p "fuzz/artifacts/$target"
    if cargo +nightly fuzz run "$target" "fuzz/corpus/$target" -- \
        -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
        "${dict[@]}" -print_final_stats=1 > "$log" 2>&1; then
        runs=$(grep -a 'stat::number_of_executed_units' "$log" | awk '{print $2}')
        echo "fuzz: $target: no crash, hang or out-of-memory in $runs runs"
    else
        tail -30 "$log"
        mkdir -p "fuzz/regressions/$target"
        cp fuzz/artifacts/"$target"/{crash,timeout,oom,leak,slow-unit}-* "fuzz/regressions/$target/" 2> /dev/null || true
        echo "fuzz: $target FAILED (input kept in fuzz/regressions/$target; log $log)"
        failed+=("$target")
    fi
done
if [ ${#failed[@]} -gt 0 ]; then
    echo "fuzz: failed: ${failed[*]}" >&2
    exit 1
fi
echo "fuzz: ${targets[*]}: $seconds s each, nothing found"
