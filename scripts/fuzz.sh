#!/usr/bin/env bash
# Builds the libFuzzer targets in build-fuzz (clang, -fsanitize=fuzzer,address,undefined)
# and runs each for a fixed time, one after the other (docs/reliability.md).
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]     default: 600 s each, targets scene and mesh
#
# Each target starts from its seed corpus tests/fuzz/corpus/<target>/ and keeps what it
# learns in build-fuzz/corpus/<target>/ (not in git). Crash, leak, timeout and OOM inputs
# are copied to tests/fuzz/regressions/<target>/, where fuzz_regression_test replays them
# in the normal test suite. The libFuzzer log is build-fuzz/logs/<target>.log; the last
# lines (executions, coverage) are printed.
#
# Environment: FUZZ_BUILD (default build-fuzz), FUZZ_JOBS (build jobs, default 2),
# FUZZ_FLAGS (extra libFuzzer flags).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(scene mesh)
build=${FUZZ_BUILD:-build-fuzz}

for tool in clang clang++; do
  command -v "$tool" >/dev/null || { echo "fuzz.sh: $tool not found (scripts/install-deps.sh installs it)" >&2; exit 1; }
done

if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTISSU_FUZZ=ON
fi
cmake --build "$build" -j "${FUZZ_JOBS:-2}" --target $(printf 'fuzz_%s ' "${targets[@]}")

# Non-OBJ meshes are read in a child process with a time limit (src/mesh/isolated_read.cpp):
# keep it below libFuzzer's -timeout so a hanging reader is the loader's error, as in a run.
export TISSU_MESH_READ_TIMEOUT=${TISSU_MESH_READ_TIMEOUT:-2}

# Leaks inside third-party libraries (assimp) are suppressed, never the project's own.
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

mkdir -p "$build/logs"
status=0
for target in "${targets[@]}"; do
  seeds=tests/fuzz/corpus/$target
  work=$build/corpus/$target
  artifacts=$build/artifacts/$target
  regressions=tests/fuzz/regressions/$target
  mkdir -p "$work" "$artifacts" "$regressions"
  log=$build/logs/$target.log
  echo "fuzz.sh: $target for ${seconds}s (log $log)"
  # -rss_limit_mb: a scene or mesh file must not make the program use gigabytes.
  # -timeout: one input taking 10 s is a hang. Leaks are detected (ASan's LeakSanitizer).
  set +e
  "$build/fuzz/fuzz_$target" "$work" "$seeds" \
    -dict="tests/fuzz/$target.dict" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -max_len=4096 -print_final_stats=1 \
    -artifact_prefix="$artifacts/" ${FUZZ_FLAGS:-} >"$log" 2>&1
  rc=$?
  set -e
  found=0
  for f in "$artifacts"/*; do
    [ -f "$f" ] || continue
    name=$(basename "$f")
    if [ ! -f "$regressions/$name" ]; then
      cp "$f" "$regressions/$name"
      found=$((found + 1))
      echo "fuzz.sh: $target: new finding $regressions/$name"
    fi
  done
  grep -E '^#[0-9]+.*(DONE|pulse|NEW)' "$log" | tail -n 1 || true
  grep -E '^stat::' "$log" || true
  if [ $rc -ne 0 ] || [ $found -ne 0 ]; then
    echo "fuzz.sh: $target stopped with exit code $rc; see $log" >&2
    grep -E '^(==[0-9]+==ERROR|SUMMARY|.*runtime error)' "$log" | head -n 5 >&2 || true
    status=1
  fi
done
exit $status
