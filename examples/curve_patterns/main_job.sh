#!/usr/bin/env bash
# Topology-constrained vector patterns (Zhou et al. 2014): three bundled exemplars along an open
# curve (data/curves/wave.svg), a straight line, a circle and a closed curve (data/curves/blob.svg),
# a rectangle (§6.2), one piece each (--components 1), two bands of separate motifs, a twisted band
# along a helix, two bands on the bundled vase (embossed and carved, §6.3) and one carved out of an
# egg-shaped stand; each run writes
# NAME.svg (filled shapes), NAME.stl (1 mm thick, watertight) and NAME.png (preview) to $OUT_DIR.
set -euo pipefail
: "${BIN:?BIN must point at the built examples}" "${DATA:?DATA must point at data/}" "${OUT_DIR:?OUT_DIR must be set}"
cp="$BIN/curve_patterns/curve_patterns"
vec="$DATA/vector"
run() {
  local name=$1
  shift
  echo "== curve_patterns $name"
  "$cp" "$@" -o "$OUT_DIR/curve_patterns_$name.svg"
}
run greek_key_wave   --exemplar "$vec/greek_key.svg"    --curve "$DATA/curves/wave.svg" --height 10 --components 1 --seed 1
run lace_line        --exemplar "$vec/lace_scallop.svg" --line 100 --height 12 --components 1
run quatrefoil_line  --exemplar "$vec/quatrefoil.svg"   --line 100 --height 10 --components 1
run greek_key_circle --exemplar "$vec/greek_key.svg"    --circle 40 --height 10 --components 1 --closed-loop
run greek_key_blob   --exemplar "$vec/greek_key.svg"    --curve "$DATA/curves/blob.svg" --closed --height 10 --components 1 --closed-loop
run greek_key_rect   --exemplar "$vec/greek_key.svg"    --rect 60 40 --height 10 --components 1
# Separate motifs (no connection between them): exactly 3 disks along 200 mm (natural length 187.5 mm),
# and 20 leaves along the 400 mm wave (natural length 389 mm).
run disks_line       --exemplar "$vec/disks.svg"        --line 200 --height 30 --components 3
run leaves_wave      --exemplar "$vec/leaves.svg"       --curve "$DATA/curves/wave.svg" --height 10 --components 20
# A band along a curve in space: a helix of radius 30 mm rising 40 mm over 1.5 turns, turned half a
# turn about the curve over its length (--twist 180); the PNG is a shaded render from two sides.
awk 'BEGIN { for (i = 0; i <= 300; ++i) { a = 3 * 3.14159265358979 * i / 300; printf "%.6f,%.6f,%.6f\n", 30 * cos(a), 30 * sin(a), 40 * i / 300 } }' > "$OUT_DIR/helix.csv"
run greek_key_helix  --exemplar "$vec/greek_key.svg"    --curve3d "$OUT_DIR/helix.csv" --twist 180 --height 8 --components 1
# Bands on a surface (§6.3, Fig. 23): a wavy loop around the bundled vase (data/meshes/vase.obj,
# profile r(z) = 20 + 9 sin(pi z / 70) mm) through 8 points; a Greek key in one piece winding around
# the vase, embossed 1.2 mm above a 2 mm shell, and leaves without holes carved out of a 2.5 mm shell
# (one piece with 7 windows). The STL is the whole decorated vase; the PNG a shaded render.
awk 'BEGIN { pi = 3.14159265358979; for (i = 0; i < 8; ++i) { a = 2 * pi * i / 8; z = 45 + 6 * sin(2 * a); r = 20 + 9 * sin(pi * z / 70); printf "%.6f,%.6f,%.6f\n", r * cos(a), r * sin(a), z } }' > "$OUT_DIR/vase_band.csv"
run greek_key_vase   --exemplar "$vec/greek_key.svg"    --mesh "$DATA/meshes/vase.obj" --points "$OUT_DIR/vase_band.csv" --closed --height 12 --components 1 --closed-loop --emboss 1.2 --cell 0.4
run leaves_vase      --exemplar "$vec/leaves.svg"       --mesh "$DATA/meshes/vase.obj" --points "$OUT_DIR/vase_band.csv" --closed --height 14 --holes 0 --carve 2.5 --cell 0.4
# The egg stand of Fig. 23 (data/meshes/egg_stand.obj): separate disks carved out of a 2 mm shell
# along a wavy loop through 8 points of its profile; one piece with 5 round windows.
awk 'BEGIN { pi = 3.14159265358979; for (i = 0; i < 8; ++i) { a = 2 * pi * i / 8; t = 1.35 + 0.12 * sin(2 * a); r = 21 * sin(t) * (1 + 0.08 * cos(t)); z = 28 * (1 - cos(t)); printf "%.6f,%.6f,%.6f\n", r * cos(a), r * sin(a), z } }' > "$OUT_DIR/egg_band.csv"
run disks_egg_stand  --exemplar "$vec/disks.svg"        --mesh "$DATA/meshes/egg_stand.obj" --points "$OUT_DIR/egg_band.csv" --closed --height 12 --carve 2 --cell 0.35
