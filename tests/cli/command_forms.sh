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
"$bin/homogenize/homogenize" "$work/block.vtk" --E 200 --nu 0.3 >"$work/block.json" 2>/dev/null
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
echo "command forms: all checks passed"
