#!/usr/bin/env bash
# Runs the example programs in the command forms that scripts depend on and checks their outputs.
# Usage: command_forms.sh BIN_DIR DATA_DIR WORK_DIR
set -euo pipefail
bin=$1 data=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }

# fem_solve DECK.inp -o OUTDIR
"$bin/fem_solve/fem_solve" "$data/fem/cantilever_c3d8.inp" -o "$work/fem" >"$work/fem.log"
[[ $(head -1 "$work/fem/displacements.csv") == "node,ux,uy,uz" ]] || fail "displacements.csv header"
[[ $(head -1 "$work/fem/stresses.csv") == "element,sxx,syy,szz,sxy,syz,szx,von_mises" ]] || fail "stresses.csv header"
[[ $(($(wc -l <"$work/fem/displacements.csv") - 1)) -eq 189 ]] || fail "one displacement row per node (189)"
[[ $(($(wc -l <"$work/fem/stresses.csv") - 1)) -eq 80 ]] || fail "one stress row per element (80)"
grep -q "UNSTRUCTURED_GRID" "$work/fem/result.vtk" || fail "result.vtk"
# An unsupported keyword is named, with a non-zero exit and no output written.
printf '*NODE\n1, 0, 0, 0\n*CONTACT PAIR\n' >"$work/bad.inp"
if "$bin/fem_solve/fem_solve" "$work/bad.inp" -o "$work/bad" 2>"$work/bad.log"; then fail "bad deck accepted"; fi
grep -qi "CONTACT PAIR" "$work/bad.log" || fail "unsupported keyword not named: $(cat "$work/bad.log")"
[[ ! -e $work/bad/displacements.csv ]] || fail "half-finished output after an error"

# homogenize GRID.vtk --E 200 --nu 0.3 on a full solid block (4^3 voxels, POINT_DATA form):
# must return the base material (E 200, nu 0.3) and volume fraction 1.
{
  printf '# vtk DataFile Version 3.0\nsolid block\nASCII\nDATASET STRUCTURED_POINTS\n'
  printf 'DIMENSIONS 4 4 4\nORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 64\nSCALARS density double 1\nLOOKUP_TABLE default\n'
  for _ in $(seq 64); do echo 1; done
} >"$work/block.vtk"
"$bin/homogenize/homogenize" "$work/block.vtk" --E 200 --nu 0.3 --json >"$work/block.json" 2>/dev/null
grep -Eq '"E": *200(\.0*)?[,[:space:]]|"E": *199\.99999' "$work/block.json" || fail "homogenize E: $(cat "$work/block.json")"
grep -Eq '"volume_fraction": *1(\.0*)?[,[:space:]}]' "$work/block.json" || fail "homogenize volume_fraction: $(cat "$work/block.json")"

# foam_slicer seeds / eval: seeds lie in the box at about the requested density; eval answers one
# 0/1 line per point (exactness is tested in tests/foam against an explicit Voronoi construction).
fs="$bin/foam_slicer/foam_slicer"
opts=(--density 0.2 --radius 0.25 --cell 3 --seed 7)
"$fs" seeds --box 0 0 0 9 9 9 --out "$work/seeds.csv" "${opts[@]}"
n=$(wc -l <"$work/seeds.csv")
awk -v n="$n" 'BEGIN{exit !(n > 100 && n < 190)}' || fail "seed count $n, expected about 0.2 * 9^3 = 145.8"
awk -F, 'NF != 3 || $1 < 0 || $1 > 9 || $2 < 0 || $2 > 9 || $3 < 0 || $3 > 9 {exit 1}' "$work/seeds.csv" || fail "seed outside the box"
awk 'BEGIN{for (i = 0; i < 500; ++i) printf "%.4f,%.4f,%.4f\n", (i*37%97)/10.0, (i*53%89)/10.0, (i*71%83)/10.0}' >"$work/points.csv"
"$fs" eval --points "$work/points.csv" --out "$work/eval.csv" "${opts[@]}"
[[ $(wc -l <"$work/eval.csv") -eq 500 ]] || fail "eval must answer one line per point"
grep -qvE '^[01]$' "$work/eval.csv" && fail "eval lines must be 0 or 1"
# The same request twice gives byte-identical output (determinism), also with one thread.
FABSYNTH_NUM_THREADS=1 "$fs" eval --points "$work/points.csv" --out "$work/eval1.csv" "${opts[@]}"
cmp -s "$work/eval.csv" "$work/eval1.csv" || fail "eval differs between thread counts"
# --- curve_patterns (section owned by the curve/mapping work) ----------------------------------
# Every accepted form: --line, --curve (open), --curve --closed, --circle, --rect. Outputs are
# re-counted independently by tests/check_pattern_output (even-odd raster of the SVG read back,
# STL watertightness after reading it back). On a closed curve a pattern winding around the loop
# (--closed-loop) encloses the curve's inside in the plane: one more raster hole than the pattern's
# own holes (paper Fig. 6).
cp="$bin/curve_patterns/curve_patterns"
check="$bin/../tests/check_pattern_output"
[[ -x $check ]] || fail "check_pattern_output is not built ($check)"
vec="$data/vector"
# run_form NAME EXPECTED_RASTER_HOLES_OFFSET PIXEL ARGS...: runs, checks files, prints the claimed holes
run_form() {
  local name=$1 extra=$2 pixel=$3
  shift 3
  "$cp" "$@" -o "$work/cp_$name.svg" >"$work/cp_$name.log" 2>&1 || fail "curve_patterns $name: $(cat "$work/cp_$name.log")"
  for ext in svg stl png; do [[ -s $work/cp_$name.$ext ]] || fail "curve_patterns $name: no .$ext written"; done
  [[ $(head -c 4 "$work/cp_$name.png" | tail -c 3) == PNG ]] || fail "curve_patterns $name: .png is not a PNG"
  local claim_c claim_h
  read -r claim_c claim_h < <(sed -n 's/^topology: \([0-9]*\) components, \([0-9]*\) holes.*/\1 \2/p' "$work/cp_$name.log")
  [[ -n $claim_c ]] || fail "curve_patterns $name: no topology summary: $(cat "$work/cp_$name.log")"
  local _c c _h h _w w _s s _f f
  read -r _c c _h h _w w _s s _f f < <("$check" "$work/cp_$name.svg" "$work/cp_$name.stl" "$pixel") || fail "check $name"
  [[ $c == "$claim_c" ]] || fail "curve_patterns $name: SVG has $c components (raster re-count), summary says $claim_c"
  [[ $h == $((claim_h + extra)) ]] || fail "curve_patterns $name: SVG has $h raster holes, expected $claim_h + $extra"
  [[ $w == 1 ]] || fail "curve_patterns $name: STL is not watertight"
  [[ $f == 1 && $s -ge 1 ]] || fail "curve_patterns $name: SVG must hold filled shapes only"
  echo "$claim_c $claim_h"
}
read -r c h < <(run_form line 0 0.02 --exemplar "$vec/greek_key.svg" --line 120 --height 10 --components 1)
[[ $c == 1 ]] || fail "curve_patterns line: asked 1 component, got $c"
# the same request with the hole count just achieved is feasible and must be met exactly
read -r c2 h2 < <(run_form line_holes 0 0.02 --exemplar "$vec/greek_key.svg" --line 120 --height 10 --components 1 --holes "$h")
[[ $c2 == 1 && $h2 == "$h" ]] || fail "curve_patterns line --holes $h: got $c2 components, $h2 holes"
read -r c h < <(run_form wave 0 0.02 --exemplar "$vec/greek_key.svg" --curve "$data/curves/wave.svg" --height 10 --components 1 --seed 3)
[[ $c == 1 ]] || fail "curve_patterns wave: asked 1 component, got $c"
read -r c h < <(run_form circle 1 0.02 --exemplar "$vec/greek_key.svg" --circle 40 --height 10 --components 1 --closed-loop)
[[ $c == 1 ]] || fail "curve_patterns circle: asked 1 component, got $c"
read -r c h < <(run_form blob 1 0.05 --exemplar "$vec/greek_key.svg" --curve "$data/curves/blob.svg" --closed --height 10 --components 1 --closed-loop)
[[ $c == 1 ]] || fail "curve_patterns blob: asked 1 component, got $c"
read -r c h < <(run_form rect 0 0.02 --exemplar "$vec/greek_key.svg" --rect 60 40 --height 10 --components 1)
[[ $c == 1 ]] || fail "curve_patterns rect: asked 1 component, got $c"
# determinism: same seed, one thread or several -> byte-identical files
FABSYNTH_NUM_THREADS=1 "$cp" --exemplar "$vec/greek_key.svg" --curve "$data/curves/wave.svg" --height 10 --components 1 --seed 3 \
  -o "$work/cp_wave1.svg" >/dev/null
for ext in svg stl png; do cmp -s "$work/cp_wave.$ext" "$work/cp_wave1.$ext" || fail "curve_patterns: .$ext differs between runs"; done
# bad input: non-zero exit, a message naming the problem, nothing written
printf '<svg xmlns="http://www.w3.org/2000/svg"></svg>\n' >"$work/empty.svg"
bad_form() {
  local name=$1 pattern=$2
  shift 2
  if "$cp" "$@" -o "$work/bad_$name.svg" >"$work/bad_$name.log" 2>&1; then fail "curve_patterns accepted bad input ($name)"; fi
  grep -qiE "$pattern" "$work/bad_$name.log" || fail "curve_patterns $name: message does not say '$pattern': $(cat "$work/bad_$name.log")"
  [[ ! -e $work/bad_$name.svg && ! -e $work/bad_$name.stl && ! -e $work/bad_$name.png ]] || fail "curve_patterns $name: output written"
}
bad_form missing "not exist|missing" --exemplar "$work/nope.svg" --line 100 --height 10
bad_form empty "no filled shape" --exemplar "$work/empty.svg" --line 100 --height 10
bad_form nan_height "height.*finite" --exemplar "$vec/greek_key.svg" --line 100 --height nan
bad_form nan_line "length.*finite" --exemplar "$vec/greek_key.svg" --line nan --height 10
bad_form empty_curve "no shape|no path" --exemplar "$vec/greek_key.svg" --curve "$work/empty.svg" --height 10
bad_form short "length|short|no sequence" --exemplar "$vec/greek_key.svg" --line 1 --height 10
bad_form tight "radius of curvature" --exemplar "$vec/greek_key.svg" --circle 4 --height 10
bad_form topology "no sequence|cannot|impossible" --exemplar "$vec/zigzag.svg" --line 100 --height 10 --components 1 --holes 3
bad_form two_curves "exactly one|excludes" --exemplar "$vec/greek_key.svg" --line 100 --circle 10 --height 10
echo "command forms: all checks passed"
