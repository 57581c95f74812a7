#!/usr/bin/env bash
# Structurally sound patterns carved along surfaces at the paper's settings (256^3, 8 levels, 26
# planes, 16x16 translations, 64 rotations, 128 candidates; 1000 abstract vertices, ABS, gravity):
# the bunny with hooks and with zebra (colour previews, the full loop of Algorithm 1),
# the kitten (z-up) with hooks. The bunny is y-up, hence --up 0 1 0 and
# --gravity 0 -1 0. Each run writes pattern.stl (and pattern.3mf), shell.vtk (states 0-4), solid.vtk, preview.png
# (reinforcements blue, enlarged thin features green) and report.json (every iteration).
# --feature is r_pattern, the exemplar's feature radius in pixels: the hooks are strokes 4 px wide
# (their horizontal runs: 4 px in 276 of 584), so 2; bridges are dilated by it (§5.2).
set -euo pipefail
: "${BIN:?BIN must point at the built examples}" "${DATA:?DATA must point at data/}" "${OUT_DIR:?OUT_DIR must be set}"
sp="$BIN/surface_patterns/surface_patterns"
"$sp" "$DATA/meshes/bunny.obj" --exemplar "$DATA/exemplars/hooks.png" --color "$DATA/exemplars/hooks_color.png" \
  --size 100 --thickness 1.2 --feature 2 --up 0 1 0 --gravity 0 -1 0 --seed 1 -o "$OUT_DIR/surface_patterns_bunny_hooks"
"$sp" "$DATA/meshes/bunny.obj" --exemplar "$DATA/exemplars/zebra.png" --color "$DATA/exemplars/zebra_color.png" \
  --size 100 --thickness 1.2 --feature 6 --up 0 1 0 --gravity 0 -1 0 --seed 1 -o "$OUT_DIR/surface_patterns_bunny_zebra"
"$sp" "$DATA/meshes/kitten.obj" --exemplar "$DATA/exemplars/hooks.png" --color "$DATA/exemplars/hooks_color.png" \
  --size 80 --thickness 1.2 --feature 2 --up 0 0 1 --gravity 0 0 -1 --seed 1 -o "$OUT_DIR/surface_patterns_kitten_hooks"
