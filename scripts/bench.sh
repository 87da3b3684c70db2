#!/usr/bin/env bash
# Runs every benchmark: the C++ micro-benchmarks (Google Benchmark) and the Blender curves bridge
# (inside blender -b). Benchmarks measure; they never pass or fail on time.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}

for bench in "$build_dir"/cpp/bench/*_bench; do
  echo "== $(basename "$bench")"
  "$bench" --benchmark_min_time=0.5 --benchmark_counters_tabular=true
done

echo "== Blender curves bridge (100k curves x 16 points)"
TMPDIR=${TMPDIR:-/tmp} blender -b --factory-startup --python-exit-code 1 \
  --python scripts/bench_blender_curves.py 2>/dev/null | grep -E '^\{' || {
  echo "bench_blender_curves.py failed" >&2
  exit 1
}
