#!/usr/bin/env bash
# Third session's device run: the 1.0M anomaly (voxel spheres, raster and Morton order,
# workgroup sizes), the horse with 4 groups x 5 iterations x 2 substeps, and the cpu
# backend's threads after the group-ordered constraint nodes.
set -u
b=target/gpu-bundle; B=$b/bin; M=$b/meshes; R=$OUT
t0=$(date +%s); say() { echo "== [$(( $(date +%s) - t0 )) s] $*"; }
for f in $b/debs/*.deb; do case $f in *validationlayers*) ;; *) dpkg -x "$f" /;; esac; done; ldconfig 2>/dev/null
$B/tetrasim info > $R/info.txt 2>&1
grep -q '^device 0' $R/info.txt || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
$B/tetrasim info > $R/info.txt 2>&1; head -3 $R/info.txt; nproc
say meshes
for n in 1000000 4000000; do
  $B/tetprep $b/sphere.obj -o /tmp/raster$n --mesher voxel --target-tets $n --keep-order > /dev/null 2>&1
  $B/tetprep $b/sphere.obj -o /tmp/morton$n --mesher voxel --target-tets $n > /dev/null 2>&1
done
$B/tetprep $b/shared/meshes/horse.ply -o /tmp/horse86 --preserve-surface --quality 0 --keep-order > /dev/null 2>&1
say spheres
for wg in default 256; do
  flag=""; [ $wg = default ] || flag="--workgroup-size $wg"
  timeout 100 $B/tetrasim bench --mesh /tmp/raster1000000 --mesh /tmp/morton1000000 --mesh /tmp/raster4000000 --mesh /tmp/morton4000000 \
    --no-bundled --method volume --backend vulkan --frames 30 --warmup 3 $flag --json $R/spheres_wg$wg.json > $R/spheres_wg$wg.txt 2>&1
  echo "wg $wg:"; grep -E 'ms/frame' $R/spheres_wg$wg.txt
done
say horse
for s in "gauss-seidel:8+global 10 1" "gauss-seidel:4+global 5 2" "chebyshev+global 10 2"; do set -- $s
  timeout 60 $B/tetrasim bench --mesh $M/horse86m --mesh $M/bunny20k --no-bundled --method volume --backend vulkan --solver $1 --iterations $2 --substeps $3 \
    --json $R/horse_${1//[:+]/-}_${2}x$3.json > $R/horse_${1//[:+]/-}_${2}x$3.txt 2>&1
  echo "$s:"; grep -E 'ms/frame' $R/horse_${1//[:+]/-}_${2}x$3.txt
done
say threads
for k in 1 2 4 8 16; do
  RAYON_NUM_THREADS=$k timeout 60 $B/tetrasim bench --mesh $M/bunny20k --mesh $M/horse86m --no-bundled --method volume --backend cpu --frames 40 --warmup 5 > $R/threads_$k.txt 2>&1
  echo "threads $k: $(grep -E 'ms/frame' $R/threads_$k.txt | tr '\n' ' ')"
done
for k in 1 16; do
  RAYON_NUM_THREADS=$k timeout 60 $B/tetrasim run --mesh /tmp/horse86 --no-fit --drop-height 0.1 --density 1000 --method volume --springs implicit --backend cpu --frames 20 > $R/implicit_$k.txt 2>&1
  echo "implicit $k: $(grep -A1 '^method' $R/implicit_$k.txt | tail -1)"
done
RAYON_NUM_THREADS=2 taskset -c 0,1 timeout 60 $B/tetrasim run --mesh /tmp/horse86 --no-fit --drop-height 0.1 --density 1000 --method volume --springs implicit --backend cpu --frames 20 > $R/implicit_2.txt 2>&1
echo "implicit 2 (taskset): $(grep -A1 '^method' $R/implicit_2.txt | tail -1)"
say done
