#!/usr/bin/env bash
# Frames produced per second end to end (simulate, draw, read back, encode H.264) for the
# demo scene and coarser or cheaper variants of it: what the 30 frames-per-second goal
# costs in cloth resolution and anti-aliasing on this machine, with the explicit
# integrator the demo had until 2026-11-28. Each time step keeps the
# demo's margin below the explicit stability limit, which grows with the edge length
# (dt proportional to 1 / sqrt(triangles)).
#   bench/demo_variants.sh [BUILD_DIR] [THREADS]      (default: build, all processors)
# Prints one markdown table row per variant.
set -euo pipefail
build=${1:-build}
threads=${2:-$(nproc)}
bench="$build/bench/tissu_render_bench"
[ -x "$bench" ] || { echo "demo_variants.sh: $bench not found (build first)" >&2; exit 2; }

echo "| triangles | dt (s) | steps per frame | MSAA | simulate ms/frame (wall) | draw ms/frame (wall) | frames/s end to end |"
echo "| ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for variant in "5000 4e-5" "2000 6.3e-5" "1250 8e-5" "500 1.26e-4"; do
  read -r triangles dt <<<"$variant"
  for msaa in 4 1; do
    out=$("$bench" --msaa "$msaa" --threads "$threads" --set integrator=symplectic_euler \
          --set cloth.mesh.triangles="$triangles" --set dt="$dt")
    steps=$(sed -n 's/.*dt [^,]*, \([0-9]*\) steps per frame.*/\1/p' <<<"$out")
    sim=$(awk '/simulate \(simulation threads\)/ {print $(NF-1)}' <<<"$out")
    draw=$(awk '/^  draw \(/ {print $(NF-1)}' <<<"$out")
    fps=$(sed -n 's/.*end to end: \([0-9.]*\) frames\/s.*/\1/p' <<<"$out")
    echo "| $triangles | $dt | $steps | $msaa | $sim | $draw | $fps |"
  done
done
