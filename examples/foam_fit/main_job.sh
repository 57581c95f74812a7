#!/usr/bin/env bash
# foam_fit, quick version: the shipped grid shape (5 radii 0.2..0.3 mm, densities up to 0.2 of the
# full-block bound) with 3 densities per radius, one seed, 16^3-element samples (the shipped fit uses
# 60^3, see data/foam/README.md): CSV, coefficients header and plot in OUT_DIR.
set -euo pipefail
: "${BIN:?BIN must point at the built examples}" "${DATA:?DATA must point at data/}" "${OUT_DIR:?OUT_DIR must be set}"
"$BIN/foam_fit/foam_fit" --rho-count 3 --seeds 1 --elements 16 \
  --csv "$OUT_DIR/foam_fit_samples.csv" --header "$OUT_DIR/foam_fit_elasticity_fit.hpp" --plot "$OUT_DIR/foam_fit_plot.png"
