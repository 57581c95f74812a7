#!/usr/bin/env bash
# Builds the Google Benchmark binaries in Release and prints their tables.
# Usage: scripts/bench.sh [FILTER-REGEX for binary names] [extra benchmark flags...]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DFABSYNTH_BUILD_BENCHMARKS=ON >/dev/null
cmake --build build/release -j "$(nproc)"
filter=${1:-.}
shift || true
for b in build/release/benchmarks/bench_*; do
  [[ -x $b && $(basename "$b") =~ $filter ]] || continue
  echo "== $(basename "$b")"
  "$b" "$@"
done
