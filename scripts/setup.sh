#!/usr/bin/env bash
# Installs exactly the Debian 12 packages fabsynth needs to build, test and benchmark.
# Idempotent; run as root (or with sudo) on a fresh machine.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config git
  clang libclang-rt-dev            # libFuzzer + sanitizer runtimes for the fuzz targets
  libeigen3-dev libglm-dev libnanoflann-dev
  libspng-dev libcli11-dev
  libpolyclipping-dev libsuitesparse-dev lib3mf-dev
  libopenblas0-pthread             # optimised BLAS/LAPACK: CHOLMOD's supernodal factorization (~3x the reference BLAS)
  libmetis-dev                     # nested-dissection ordering of the LDL^T solver (fem/detail/linear_backends.hpp)
  calculix-ccx                     # CalculiX: the independent FEM oracle of tests/fem/solve_context.cpp and bench_fem_decks
  calculix-ccx-test                # CalculiX's own test decks: the patterns of tests/fem/inp_ccx_suite.cpp
  libboost-dev                     # header-only: Boost.Polygon segment Voronoi (medial axis)
  catch2 libbenchmark-dev
  nlohmann-json3-dev               # the tools' --json summaries (examples/common/tool.hpp)
  pybind11-dev python3-dev python3-numpy   # the Python package (python/)
  python3-pytest python3-dask python3-distributed   # its tests, and fabsynth.distributed on a Dask cluster
  python3-matplotlib python3-tqdm  # examples/python: figures, progress bars
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  SUDO=""
  [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
echo "fabsynth: all ${#packages[@]} build packages present"
