#!/usr/bin/env bash
# The device side of scripts/gpu-bundle.sh: run from the project root on a bare GPU machine
# (no Rust, no registry, no network) with target/gpu-bundle/ present:
#   bash target/gpu-bundle/gpu-report.sh [STEPS]
# STEPS (default: all, in this order) picks and orders what is measured:
#   bench     the default solver, jacobi, chebyshev and 1 and 2 groups on bunny20k and horse86m (new, and old beside it
#             when the bundle holds bin/tetrasim-old), the pass breakdown included
#   blocks    block Gauss-Seidel (--block-size) beside the default on bunny20k and horse86m: blocks of
#             1024, 512 and 256, swept 2 and 3 times, with Anderson at 10 and 7 iterations, the
#             pass breakdown included;
#             the real-size horse with implicit springs in blocks; the cpu backend's threads in blocks
#   implicit  the real-size horse with implicit springs (issue 13's scene), 400 frames
#   elastic   the same horse with the finite elements (neo-hookean, issue 51), 400 frames, and
#             the cantilever's trade against scikit-fem (tradeoff --cantilever) on the GPU
#   stiff     issue 26: the real-size horse (1000 kg/m^3, ks 5000) with Anderson acceleration,
#             more colour groups, substeps, inversion sweeps, blocks swept twice and MINRES,
#             400 frames each; the `distance` sphere with the settings that stop its rebound; what those
#             options cost on bunny20k and horse86m at the seed preset (bench), and one sweep
#             then MINRES (issue 22's candidate default)
#   tests     the GPU test binaries, one at a time, default test threads, CI=true
#   threads   the cpu backend on 1..all cores (new: bin/tetrasim-cpu when bundled; old
#             beside it)
#   tradeoff  the speed/accuracy trade on bunny20k on the GPU
#   scaling   voxel spheres of 16k to 4M tets
# Figures go to gpu-<device>/ under $WORK (default /tmp/gpu-report), one file per bench,
# test binary and sweep plus report.log, packed into $OUT/gpu-<device>.tgz after every step
# (OUT defaults to ./gpu-report); unpack it into docs/data/. Every step has a time limit, so
# a run cut short still returns what it measured.
set -u
b=target/gpu-bundle
[ -f "$b/binaries.tar.xz" ] || { echo "gpu-report.sh: $b/binaries.tar.xz is missing; run scripts/gpu-bundle.sh first" >&2; exit 2; }
steps=${*:-bench blocks implicit elastic stiff tests threads tradeoff scaling}
for s in $steps; do
  case $s in bench|blocks|implicit|elastic|stiff|tests|threads|tradeoff|scaling) ;;
    *) echo "gpu-report.sh: unknown step \`$s\` (known: bench blocks implicit elastic stiff tests threads tradeoff scaling)" >&2; exit 2 ;;
  esac
done
OUT=${OUT:-$PWD/gpu-report}; WORK=${WORK:-/tmp/gpu-report}; mkdir -p "$OUT"
t0=$(date +%s)
say() { echo "== [$(( $(date +%s) - t0 )) s] $*"; }
# The loader and libglvnd go to / (this machine is lent bare); the validation layer to its
# own folder.
for f in "$b"/debs/*.deb; do case $f in *validationlayers*) ;; *) dpkg -x "$f" /;; esac; done
ldconfig 2>/dev/null
mkdir -p /tmp/vl && dpkg -x "$b"/debs/vulkan-validationlayers_*.deb /tmp/vl
export VK_LAYER_PATH=/tmp/vl/usr/share/vulkan/explicit_layer.d
export LD_LIBRARY_PATH=/tmp/vl/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
# The CLI builds and the test binaries, packed by gpu-bundle.sh into one xz archive: unpacked
# by xz where the machine has it, else by Python's lzma (the GPU machines' image has python3).
U=/tmp/gpu-binaries; rm -rf "$U"; mkdir -p "$U"
if command -v xz >/dev/null; then xz -dc "$b/binaries.tar.xz" | tar xf - -C "$U"
else python3 -c 'import lzma, shutil, sys; shutil.copyfileobj(lzma.open(sys.argv[1]), sys.stdout.buffer)' \
  "$b/binaries.tar.xz" | tar xf - -C "$U"; fi
[ -x "$U/bin/tetrasim" ] || { echo "gpu-report.sh: could not unpack $b/binaries.tar.xz (no xz, no python3?)" >&2; exit 2; }
B=$U/bin; M=$b/meshes
"$B/tetrasim" info > /tmp/info.txt 2>&1
grep -q '^device 0' /tmp/info.txt || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
"$B/tetrasim" info > /tmp/info.txt 2>&1
name=$(sed -n 's/^device 0: \(.*\) \[.*/\1/p' /tmp/info.txt | head -1)
slug=$(echo "${name:-unknown}" | tr 'A-Z' 'a-z' | sed 's/[^a-z0-9]\+/-/g; s/^-//; s/-$//')
R=$WORK/gpu-$slug; mkdir -p "$R"
pack() { tar czf "$OUT/gpu-$slug.tgz" -C "$WORK" "gpu-$slug"; cp "$R/report.log" "$OUT/" 2>/dev/null; }
exec > >(tee -a "$R/report.log") 2>&1
{ cat /tmp/info.txt; echo "commit: $(cat "$b/commit" | tr '\n' ' ')"; nvidia-smi -L 2>/dev/null; nproc; } > "$R/info.txt"
cat "$R/info.txt"
# The test binaries find the project at the path they were built in, ../shared beside it,
# and the CLI where cargo built it.
built=$(cat "$b/build-path"); mkdir -p "$(dirname "$built")"
[ -e "$built" ] || ln -s "$PWD/$b/project" "$built"
[ -e "$(dirname "$built")/shared" ] || ln -s "$PWD/$b/shared" "$(dirname "$built")/shared"
tp=$(cat "$b/target-path"); mkdir -p "$tp/release" 2>/dev/null && cp "$B/tetrasim" "$B/tetprep" "$tp/release/" 2>/dev/null
builds="new"; [ -x "$B/tetrasim-old" ] && builds="old new"
bin_of() { case $1 in old) echo "$B/tetrasim-old";; *) echo "$B/tetrasim";; esac; }
for step in $steps; do
  pack
  say "$step"
  case $step in
  bench)
    for v in $builds; do
      for s in gauss-seidel:8+global jacobi chebyshev+global gauss-seidel:1+global gauss-seidel:2+global; do
        f="$R/bench_${v}_${s//[:+]/-}"
        timeout 120 "$(bin_of $v)" bench --mesh "$M/bunny20k" --mesh "$M/horse86m" --no-bundled --method volume \
          --backend vulkan --solver "$s" --json "$f.json" > "$f.txt" 2>&1
        echo "$v $s:"; grep -E 'ms/frame|GPU' "$f.txt" | head -8
      done
    done
    # per-pass workgroup sizes apart from the other changes: every pass at 1024
    timeout 60 "$B/tetrasim" bench --mesh "$M/horse86m" --no-bundled --method volume --backend vulkan \
      --workgroup-size 1024 > "$R/bench_new_wg1024.txt" 2>&1
    grep -E 'ms/frame' "$R/bench_new_wg1024.txt" | sed 's/^/new, --workgroup-size 1024: /'
    "$B/tetrasim" plan --mesh "$M/horse86m" --method volume > "$R/plan_horse.txt" 2>&1 ;;
  blocks)
    for s in gauss-seidel:8+global gauss-seidel:block1024+global gauss-seidel:block512+global \
             gauss-seidel:block256+global gauss-seidel:block1024+global+anderson5 \
             gauss-seidel:block1024x2+global gauss-seidel:block1024x3+global \
             gauss-seidel:block1024x2+global+anderson5; do
      f="$R/blocks_bench_${s//[:+]/-}"
      timeout 90 "$B/tetrasim" bench --mesh "$M/bunny20k" --mesh "$M/horse86m" --no-bundled --method volume \
        --backend vulkan --solver "$s" --json "$f.json" > "$f.txt" 2>&1
      echo "$s:"; grep -E 'ms/frame|GPU' "$f.txt" | head -8
    done
    f="$R/blocks_bench_block1024-anderson5-7it"
    timeout 90 "$B/tetrasim" bench --mesh "$M/bunny20k" --mesh "$M/horse86m" --no-bundled --method volume \
      --backend vulkan --solver gauss-seidel:block1024+global+anderson5 --iterations 7 --json "$f.json" > "$f.txt" 2>&1
    echo "block1024+anderson5, 7 it:"; grep -E 'ms/frame' "$f.txt" | head -4
    for m in bunny20k horse86m; do
      "$B/tetrasim" plan --mesh "$M/$m" --method volume --block-size 1024 > "$R/blocks_plan_$m.txt" 2>&1
    done
    timeout 90 "$B/tetrasim" run --mesh "$M/horse86m" --no-fit --drop-height 0.1 --method volume \
      --youngs-modulus 1e5 --poisson-ratio 0.45 --density 1050 --springs implicit --block-size 1024 --backend vulkan \
      --frames 400 > "$R/blocks_implicit_horse.txt" 2>&1
    echo "implicit horse, blocks of 1024:"; sed -n '2,4p' "$R/blocks_implicit_horse.txt"
    n=$(nproc)
    for k in $(printf '%s\n' 1 2 4 8 16 "$n" | sort -nu); do
      [ "$k" -le "$n" ] || continue
      f="$R/blocks_threads_$k.txt"
      RAYON_NUM_THREADS=$k timeout 60 "$B/tetrasim" bench --mesh "$M/bunny20k" --mesh "$M/horse86m" --no-bundled \
        --method volume --backend cpu --solver gauss-seidel:block1024+global --frames 40 --warmup 5 > "$f" 2>&1
      echo "cpu blocks of 1024, threads $k: $(grep -E 'cpu: [0-9.]+ ms/frame' "$f" | sed 's/.*meshes\///' | tr '\n' ';')"
    done ;;
  implicit)
    for v in $builds; do
      timeout 90 "$(bin_of $v)" run --mesh "$M/horse86m" --no-fit --drop-height 0.1 --method volume \
        --youngs-modulus 1e5 --poisson-ratio 0.45 --density 1050 --springs implicit --backend vulkan --frames 400 \
        > "$R/implicit_horse_$v.txt" 2>&1
      echo "$v:"; sed -n '2,4p' "$R/implicit_horse_$v.txt"
    done ;;
  elastic)
    timeout 150 "$B/tetrasim" run --mesh "$M/horse86m" --no-fit --drop-height 0.1 --method neo-hookean \
      --youngs-modulus 1e5 --poisson-ratio 0.45 --density 1050 --backend vulkan --frames 400 \
      > "$R/elastic_horse.txt" 2>&1
    sed -n '2,4p' "$R/elastic_horse.txt"
    timeout 150 "$B/tetrasim" tradeoff --cantilever --backend vulkan --out-dir "$R/cantilever" \
      > "$R/cantilever.txt" 2>&1
    tail -24 "$R/cantilever.txt" ;;
  stiff)
    while read -r label opts; do
      f="$R/stiff_horse_$label.txt"
      timeout 60 "$B/tetrasim" run --mesh "$M/horse86m" --no-fit --drop-height 0.1 --density 1000 \
        --method volume --springs implicit --backend vulkan --frames 400 $opts > "$f" 2>&1
      echo "horse $label: $(sed -n 3p "$f")"
    done <<'SETTINGS'
default
anderson5 --anderson 5
anderson5_groups16 --anderson 5 --groups 16
anderson5_groups64 --anderson 5 --groups 64
anderson5_groups16_inversion4 --anderson 5 --groups 16 --inversion-sweeps 4
anderson5_groups16_inversion8 --anderson 5 --groups 16 --inversion-sweeps 8
groups16_inversion8 --groups 16 --inversion-sweeps 8
anderson5_substeps2 --anderson 5 --substeps 2 --dt 0.0005
anderson5_substeps2_inversion4 --anderson 5 --substeps 2 --dt 0.0005 --inversion-sweeps 4
anderson5_7x2_inversion4 --anderson 5 --iterations 7 --substeps 2 --dt 0.0005 --inversion-sweeps 4
anderson5_groups16_5x2_inversion4 --anderson 5 --groups 16 --iterations 5 --substeps 2 --dt 0.0005 --inversion-sweeps 4
blocks1024_anderson5_substeps2_inversion4 --block-size 1024 --anderson 5 --substeps 2 --dt 0.0005 --inversion-sweeps 4
blocks1024x2_anderson5_substeps2_inversion4 --block-size 1024 --block-sweeps 2 --anderson 5 --substeps 2 --dt 0.0005 --inversion-sweeps 4
blocks1024x2_anderson5_15it_inversion4 --block-size 1024 --block-sweeps 2 --anderson 5 --iterations 15 --inversion-sweeps 4
blocks1024x3_anderson5_15it_inversion4 --block-size 1024 --block-sweeps 3 --anderson 5 --iterations 15 --inversion-sweeps 4
blocks1024x2s1_anderson5_substeps2_inversion4 --block-size 1024 --block-sweeps 2 --spring-block-sweeps 1 --anderson 5 --substeps 2 --dt 0.0005 --inversion-sweeps 4
blocks1024x3s1_anderson5_15it_inversion4 --block-size 1024 --block-sweeps 3 --spring-block-sweeps 1 --anderson 5 --iterations 15 --inversion-sweeps 4
minres25_inversion8 --iterations 1 --minres 25 --inversion-sweeps 8
minres26_inversion8 --iterations 1 --minres 26 --inversion-sweeps 8
SETTINGS
    # The `distance` sphere's rebound bar: what the settings that bring it to rest cost here
    # (the rebound itself is the cpu backend's to the third digit: docs/PHYSICS.md).
    while read -r label opts; do
      f="$R/stiff_sphere_$label.txt"
      timeout 60 "$B/tetrasim" run --mesh meshes/sphere --method distance --backend vulkan --frames 400 \
        $opts > "$f" 2>&1
      echo "sphere $label: $(sed -n 3p "$f")"
    done <<'SETTINGS'
default
anderson5_30it --anderson 5 --iterations 30
blocks1024x2_anderson5_30it --block-size 1024 --block-sweeps 2 --anderson 5 --iterations 30
blocks1024_anderson5_40it --block-size 1024 --anderson 5 --iterations 40
minres28 --iterations 1 --minres 28
minres36 --iterations 1 --minres 36
SETTINGS
    for s in gauss-seidel:8+global gauss-seidel:8+global+anderson5 gauss-seidel:8+global+inversion4 \
             gauss-seidel:16+global+anderson5; do
      f="$R/stiff_bench_${s//[:+]/-}"
      timeout 60 "$B/tetrasim" bench --mesh "$M/bunny20k" --mesh "$M/horse86m" --no-bundled --method volume \
        --backend vulkan --solver "$s" --json "$f.json" > "$f.txt" 2>&1
      echo "$s:"; grep -E 'ms/frame' "$f.txt" | head -4
    done
    # Issue 22's candidate default (docs/BENCHMARKS.md, "One sweep, then MINRES" and "With
    # MINRES's close"): one sweep of 1, 2 or 8 colour groups, then MINRES (ending with the
    # global volume constraints, or with an inversion sweep), at the seed preset.
    # With an old build bundled (gpu-bundle.sh --old), it runs these too: e.g. a build of
    # docs/experiments/minres_object_chunks.patch, whose MINRES passes only a GPU can judge.
    for v in $builds; do
      for s in gauss-seidel:1+global+minres7 gauss-seidel:2+global+minres7 \
               gauss-seidel:2+global+minres8 gauss-seidel:8+global+minres10+inversion1; do
        f="$R/stiff_bench_1it_${s//[:+]/-}"; [ "$v" = old ] && f="${f}_old"
        timeout 60 "$(bin_of "$v")" bench --mesh "$M/bunny20k" --mesh "$M/horse86m" --no-bundled \
          --method volume --backend vulkan --solver "$s" --iterations 1 --json "$f.json" > "$f.txt" 2>&1
        echo "$v $s, 1 iteration:"; grep -E 'ms/frame' "$f.txt" | head -4
      done
      [ "$v" = old ] || continue
      f="$R/stiff_horse_minres25_inversion8_old.txt"
      timeout 60 "$B/tetrasim-old" run --mesh "$M/horse86m" --no-fit --drop-height 0.1 --density 1000 \
        --method volume --springs implicit --backend vulkan --frames 400 --iterations 1 --minres 25 \
        --inversion-sweeps 8 > "$f" 2>&1
      echo "old horse minres25_inversion8: $(sed -n 3p "$f")"
    done ;;
  tests)
    export CI=true
    for t in "$U"/tests/*; do
      n=$(basename "$t")
      (cd "$built" && timeout 150 "$t" > "$R/test_$n.txt" 2>&1); c=$?
      echo "test $n: exit $c: $(grep -E '^test result' "$R/test_$n.txt" | tail -1)"
    done
    unset CI ;;
  threads)
    n=$(nproc)
    for v in $builds; do
      # the old build as a baseline at a few counts, the new one at every count
      list="1 2 4 8 16"; [ "$v" = old ] && list="1 2 16"; [ "$n" -gt 16 ] && list="$list $n"
      cb=$(bin_of $v); [ "$v" = new ] && [ -x "$B/tetrasim-cpu" ] && cb=$B/tetrasim-cpu
      for s in gauss-seidel:8+global jacobi; do
        for k in $list; do
          [ "$k" -le "$n" ] || continue
          f="$R/threads_${v}_${s//[:+]/-}_$k.txt"
          RAYON_NUM_THREADS=$k timeout 60 "$cb" bench --mesh "$M/bunny20k" --mesh "$M/horse86m" --no-bundled \
            --method volume --backend cpu --solver "$s" --frames 40 --warmup 5 > "$f" 2>&1
          echo "$v $s threads $k: $(grep -E 'cpu: [0-9.]+ ms/frame' "$f" | sed 's/.*meshes\///' | tr '\n' ';')"
        done
      done
    done ;;
  tradeoff)
    # the reference on the threaded cpu backend, as docs/BENCHMARKS.md's front on 2 cores
    timeout 240 "$B/tetrasim" tradeoff --mesh "$M/bunny20k" --backend vulkan --methods volume \
      --solvers gauss-seidel:1+global,gauss-seidel:2+global,gauss-seidel:4+global,gauss-seidel:8+global,chebyshev+global,jacobi+global,gauss-seidel:8+global+anderson5,gauss-seidel:4+global+anderson5,jacobi+global+anderson5,gauss-seidel:block1024+global,gauss-seidel:block1024+global+anderson5 \
      --iterations 5,10,20 --substeps 1,2 --frames 200 --ref-backend cpu --ref-iterations 50 --ref-substeps 4 \
      --out-dir "$R/tradeoff" > "$R/tradeoff.txt" 2>&1
    tail -25 "$R/tradeoff.txt" ;;
  scaling)
    timeout 120 "$B/tetrasim" scaling --sizes 16000,64000,256000,1000000,4000000 --out-dir "$R/scaling" > "$R/scaling.txt" 2>&1
    tail -12 "$R/scaling.txt" ;;
  esac
done
say done
pack
