#!/usr/bin/env bash
# The whole test suite, as CI runs it (.ci/run calls exactly this):
#   1. install the Debian packages (scripts/setup.sh),
#   2. Release build + every test (incl. [slow] ones, the installed-package consumer and the Python
#      package's pytest suite),
#   3. each libFuzzer target for a short bounded time (clang),
#   4. the tests of the modules where memory errors hide (tests/CMakeLists.txt:
#      FABSYNTH_SANITIZE_MODULES) once more under AddressSanitizer + UndefinedBehaviorSanitizer; the
#      tools and the filigree and vector-pattern pipelines run their checks in the Release build only.
# Any failure, sanitizer report or fuzzer crash fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
jobs=$(nproc)

echo "== Release build and tests"
# the Python package is built for Debian's interpreter, whose python3-* packages setup.sh installs
python=()
[[ -x /usr/bin/python3 ]] && python=(-DPython_EXECUTABLE=/usr/bin/python3)
# the benchmarks are built and run by scripts/bench.sh, not here: their ~5 min of compiling kept CI
# above its hour once the Python package joined the build
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DFABSYNTH_BUILD_BENCHMARKS=OFF "${python[@]}" >/dev/null
cmake --build build/release -j "$jobs"
ctest --test-dir build/release --output-on-failure --no-tests=error -j "$jobs"

echo "== Fuzzers (${FABSYNTH_FUZZ_SECONDS:=20} s each)"
bash scripts/fuzz.sh "$FABSYNTH_FUZZ_SECONDS"

echo "== AddressSanitizer + UndefinedBehaviorSanitizer build and tests"
# -O1 -g1 (line tables): what the sanitizers need for useful reports, at half the compile time of -O2 -g
cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DFABSYNTH_SANITIZE=ON \
  -DFABSYNTH_BUILD_EXAMPLES=OFF -DFABSYNTH_BUILD_BENCHMARKS=OFF -DFABSYNTH_PYTHON=OFF >/dev/null
cmake --build build/asan -j "$jobs"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build/asan --output-on-failure --no-tests=error -j "$jobs" -E "consumer|readme_pipelines|headers"
