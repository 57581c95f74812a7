#!/usr/bin/env bash
# Builds every libFuzzer target with clang and runs each for SECONDS (default 20), seeded with
# the bundled data. Crash reproducers land in build/fuzz/crashes/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFABSYNTH_BUILD_FUZZERS=ON \
  -DFABSYNTH_BUILD_TESTS=OFF -DFABSYNTH_BUILD_EXAMPLES=OFF -DFABSYNTH_BUILD_BENCHMARKS=OFF -DFABSYNTH_PYTHON=OFF >/dev/null
cmake --build build/fuzz -j "$(nproc)"
mkdir -p build/fuzz/crashes
for fuzzer in build/fuzz/fuzz/fuzz_*; do
  [[ -x $fuzzer ]] || continue
  name=$(basename "$fuzzer")
  corpus=build/fuzz/corpus/$name
  mkdir -p "$corpus"
  # Seed corpus: the fuzz/corpus/<name>/ files plus bundled data of the matching kind.
  kind=${name#fuzz_}
  [[ -d fuzz/corpus/$kind ]] && cp -n fuzz/corpus/"$kind"/* "$corpus"/ 2>/dev/null || true
  case $kind in  # small bundled files of the same format
    svg) cp -n data/vector/*.svg data/filigree/*.svg "$corpus"/ ;;
    obj) cp -n data/meshes/cube.obj data/meshes/cube_subdiv.obj "$corpus"/ ;;
    stl) cp -n data/meshes/cube_ascii.stl "$corpus"/ ;;
    png) cp -n data/exemplars/*.png "$corpus"/ ;;
  esac
  echo "-- $name for $seconds s"
  "$fuzzer" "$corpus" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 -timeout=10 \
    -artifact_prefix=build/fuzz/crashes/"$name"- -print_final_stats=0 2>&1 | tail -n 3
done
