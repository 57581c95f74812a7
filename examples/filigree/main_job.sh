#!/usr/bin/env bash
# Filigree synthesis (Chen et al. 2016) in 2D: every bundled element alone in a 90 x 70 mm rectangle,
# a multi-class run (spiral 2 : leaf 1), a field-controlled run (element scale from a grayscale
# gradient, data/filigree/gradient_field.png), a run inside an SVG domain with a hole
# (data/filigree/frame_with_hole.svg) and three element sets in the three regions of a label
# picture. The multi-class and domain runs include the shell-FEM structural optimization (§5); each run writes NAME.svg, NAME.stl, NAME.png, NAME_steps.png and
# NAME.json to $OUT_DIR, and every result is re-counted independently as one connected piece with a
# watertight STL (tests/check_pattern_output).
set -euo pipefail
: "${BIN:?BIN must point at the built examples}" "${DATA:?DATA must point at data/}" "${OUT_DIR:?OUT_DIR must be set}"
fg="$BIN/filigree/filigree"
check="$BIN/../tests/check_pattern_output"
el="$DATA/filigree"
run() {
  local name=$1
  shift
  echo "== filigree $name"
  "$fg" "$@" -o "$OUT_DIR/filigree_$name.svg"
  if [[ -x $check ]]; then
    local line
    line=$("$check" "$OUT_DIR/filigree_$name.svg" "$OUT_DIR/filigree_$name.stl" 0.05)
    echo "   $line"
    [[ $line == "components 1 "*"watertight 1"* ]] || { echo "filigree $name: not one watertight piece: $line" >&2; exit 1; }
  fi
}
for e in spiral s_curl c_scroll leaf heart_curls; do
  run "$e" --element "$el/$e.svg" --rect 90 70 --scale 20 --width 0.8 --no-structure --seed 1
done
run multi_class --element "$el/spiral.svg:2" --element "$el/leaf.svg:1" --rect 90 70 --scale 18 --width 0.8 --seed 2
run field --element "$el/s_curl.svg" --rect 90 70 --scale 18 --width 0.8 --field-image "$el/gradient_field.png" --field-scale 0.6 1.4 \
  --no-structure --seed 3
run domain_hole --element "$el/c_scroll.svg" --domain "$el/frame_with_hole.svg" --scale 18 --width 0.8 --seed 4
# element sets per region: spirals where data/filigree/three_regions.png is black, S-scrolls where
# it is grey, leaves where it is white, one piece across the borders
run regions --element "$el/spiral.svg@0" --element "$el/s_curl.svg@128" --element "$el/leaf.svg@255" --labels "$el/three_regions.png" \
  --rect 90 70 --scale 18 --width 0.8 --no-structure --seed 2
# On base surfaces (part 2): the bunny (closed up to its 5 holes, scaled to 100 mm, y up) and the
# generated open vase (data/meshes/vase.obj, z up); OUT.stl printable solid, OUT.obj baked M_b,
# OUT.png the base with the filigree from two sides, OUT.json the report.
echo "== filigree on the bunny"
"$fg" --element "$el/c_scroll.svg" --mesh "$DATA/meshes/bunny.obj" --mesh-size 100 --up 0 1 0 --scale 16 --width 0.8 --seed 1 \
  -o "$OUT_DIR/filigree_bunny.stl"
echo "== filigree on the vase"
"$fg" --element "$el/c_scroll.svg" --mesh "$DATA/meshes/vase.obj" --up 0 0 1 --scale 14 --width 0.8 --seed 1 -o "$OUT_DIR/filigree_vase.stl"
# element sets per region on a mesh: C-scrolls on the vase's lower half, leaves on its upper half
# (data/filigree/vase_halves.txt: one label per face, scripts/make_vase.py)
echo "== filigree on the vase, two element sets"
"$fg" --element "$el/c_scroll.svg@0" --element "$el/leaf.svg@1" --face-labels "$el/vase_halves.txt" --mesh "$DATA/meshes/vase.obj" --up 0 0 1 \
  --scale 14 --width 0.8 --seed 1 -o "$OUT_DIR/filigree_vase_regions.stl"
