#!/usr/bin/env bash
# Linear-static FEM on the bundled decks: displacements.csv, stresses.csv and result.vtk per deck.
set -euo pipefail
: "${BIN:?BIN must point at the built examples}" "${DATA:?DATA must point at data/}" "${OUT_DIR:?OUT_DIR must be set}"
for deck in cantilever_c3d8 plate_s3_simply_supported mixed_c3d8_c3d6_s3; do
  "$BIN/fem_solve/fem_solve" "$DATA/fem/$deck.inp" -o "$OUT_DIR/$deck"
done
