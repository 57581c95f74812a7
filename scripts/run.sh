#!/usr/bin/env bash
# The main job: builds the tools in Release (only the tools: no tests or benchmarks) and runs every
# pipeline on the bundled data in data/, writing results and PNG previews under out/. Each example
# contributes its part as examples/<name>/main_job.sh, called with BIN (example binaries), DATA and
# OUT set. Run it as yourself: scripts/setup.sh uses sudo for apt-get only.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DFABSYNTH_BUILD_EXAMPLES=ON >/dev/null
tools=()
for job in examples/*/main_job.sh; do tools+=("$(basename "$(dirname "$job")")"); done
cmake --build build/release -j "$(nproc)" --target "${tools[@]}"
export BIN=$PWD/build/release/examples DATA=$PWD/data OUT=$PWD/out
mkdir -p "$OUT"
for job in examples/*/main_job.sh; do
  [[ -f $job ]] || continue
  name=$(basename "$(dirname "$job")")
  echo "== $name"
  mkdir -p "$OUT/$name"
  OUT_DIR="$OUT/$name" bash "$job"
done
echo
echo "Results and PNG previews are in $OUT:"
find "$OUT" -maxdepth 2 -type f | sort | sed 's/^/  /'
