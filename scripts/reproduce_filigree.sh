#!/bin/bash
# Reruns the experiments of Chen et al. 2016 (filigree-synthesis.md §7.3, §8.3-8.4: Table 2, the
# class-percentage series of Fig. 17 (2D) and Fig. 18 (3D), Table 3, the PME curves of Fig. 22) with
# the filigree tool and the three motifs drawn for them (data/filigree/scroll_curls.svg, flower.svg,
# leaf_spray.svg; scripts/make_filigree_motifs.py), and prints them side by side with the paper's
# figures, as markdown, to OUT/tables.md.
#
#   scripts/reproduce_filigree.sh [-b BUILD_DIR] [-o OUT] [--no-3d]
#
#   BUILD_DIR   build tree holding examples/filigree/filigree (default build/release)
#   OUT         output directory (default reproduce_filigree): NAME.svg/.stl/.png/.json per run,
#               pictures/NAME.png (the tool's preview), tables.md
#   --no-3d     skip the surface runs (Fig. 18 and Table 3)
#
# The paper's input elements and domains are not published: its Table 2 rows are its own figures,
# each with its elements and outline. Here every 2D run uses one of our motifs in the main job's
# 90 x 70 mm rectangle or its frame with an elliptical hole, with element sizes chosen so the counts
# fall in the paper's range (20-57), the structural optimization (§5) on (ABS, the default), seed 1. Fig. 17/18's
# series mix flowers and leaf sprays at three proportions; the paper sets them through Wei 2010's
# size factor, this tool through class weights (initialization.hpp), and the table gives the
# proportions reached. On the 2-core machine the whole script takes about 5 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/release out=reproduce_filigree three_d=1
while [ $# -gt 0 ]; do
    case "$1" in
        -b) build=$2; shift 2 ;;
        -o) out=$2; shift 2 ;;
        --no-3d) three_d=0; shift ;;
        *) echo "reproduce_filigree.sh: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
fg="$build/examples/filigree/filigree"
[ -x "$fg" ] || { echo "reproduce_filigree.sh: no tool at $fg (build it first)" >&2; exit 2; }
mkdir -p "$out/pictures"
el=data/filigree

# name | tool arguments
run() {
    local name=$1; shift
    echo "== $name" >&2
    "$fg" "$@" --seed 1 -q -o "$out/$name.svg"
    cp "$out/$name.png" "$out/pictures/$name.png"
}
rect=(--rect 90 70)
# Table 2: single classes
run scroll_curls --element $el/scroll_curls.svg "${rect[@]}" --scale 26
run flower --element $el/flower.svg "${rect[@]}" --scale 26
run leaf_spray --element $el/leaf_spray.svg "${rect[@]}" --scale 34
run flower_frame --element $el/flower.svg --domain $el/frame_with_hole.svg --scale 20
# Fig. 17: flowers and leaf sprays at 1:3, 1:1, 3:1 (the single-class end is the flower row above)
run mix_25 --element $el/flower.svg:1 --element $el/leaf_spray.svg:3 "${rect[@]}" --scale 28
run mix_50 --element $el/flower.svg:1 --element $el/leaf_spray.svg:1 "${rect[@]}" --scale 28
run mix_75 --element $el/flower.svg:3 --element $el/leaf_spray.svg:1 "${rect[@]}" --scale 28
if [ "$three_d" = 1 ]; then
    vase=(--mesh data/meshes/vase.obj --up 0 0 1 --width 0.8)
    # Fig. 18: the vase's outer shell with flowers and leaf sprays at three proportions
    run vase_25 --element $el/flower.svg:1 --element $el/leaf_spray.svg:3 "${vase[@]}" --scale 24
    run vase_50 --element $el/flower.svg:1 --element $el/leaf_spray.svg:1 "${vase[@]}" --scale 24
    run vase_75 --element $el/flower.svg:3 --element $el/leaf_spray.svg:1 "${vase[@]}" --scale 24
    # Table 3: the bunny (closed up to its holes, 100 mm) with scrolls
    run bunny --element $el/scroll_curls.svg --mesh data/meshes/bunny.obj --mesh-size 100 --up 0 1 0 --width 0.8 --scale 20
fi

python3 - "$out" "$three_d" > "$out/tables.md" <<'EOF'
import json, os, sys
out, three_d = sys.argv[1], sys.argv[2] == "1"
load = lambda n: json.load(open(f"{out}/{n}.json"))
def classes(r):
    per = r["instances_per_class"] if "instances_per_class" in r else [e["instances"] for e in r["elements"]]
    total = sum(per)
    return " / ".join(f"{100 * c / total:.0f}%" for c in per) if len(per) > 1 else "-"
def analyses(r):  # structural analyses: phase 1's rounds and phase 2's steps share the analysis between them
    s = r["structure"]
    return len(s["weak_fraction_phase1"]) + len(s["weak_fraction_phase2"]) - 1 if s["analysed"] else 0
def pme(r):
    return " ".join(f"{x:.1f}" for x in r["pme_per_instance_per_round"])
# Chen et al. 2016, Table 2 (element count, iterations, total seconds on an i7-4770)
print("### Table 2 (2D): the paper's rows\n")
print("Fig. 12a 31 / 2 / 10.2 s; 12b 25 / 2 / 6.6; 12c 28 / 2 / 8.3; 12d 20 / 2 / 11.4; 13c 28 / 2 / 7.9; 13f 23 / 2 / 7.3; "
      "14a 34 / 2 / 13.7; 14b 57 / 3 / 25.3; 15b 32 / 2 / 11.3; 15d 32 / 2 / 11.9; 17a 41 / 2 / 16.2; 17b 35 / 2 / 14.2; 17c 26 / 2 / 8.0 "
      "(elements / iterations / total).\n")
print("### Table 2 (2D) here, with the Fig. 17 series and the PME per instance by round (Fig. 22)\n")
print("| run | elements | classes (flower / leaf spray) | iterations | structure analyses | thickness mm | crossings per instance | components | synthesis s | structure s | total s | PME per instance by round |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for n in ("scroll_curls", "flower", "leaf_spray", "flower_frame", "mix_25", "mix_50", "mix_75"):
    r = load(n)
    s = r["seconds"]
    syn = s["initialization"] + s["placement"] + s["boosting"] + s["topology_cut"]
    print(f"| {n} | {r['instances']} | {classes(r)} | {r['rounds']} | {analyses(r)} | {r['thickness_mm']:.2f} | "
          f"{r['appearance']['crossings_per_instance']:.2f} | {r['connected_components']} | {syn:.1f} | {s['structure']:.1f} | {s['total']:.1f} | {pme(r)} |")
if three_d:
    # Table 3: vertices, faces, elements, synthesis iterations, structure iterations, t_syn, t_sct
    paper = {"bunny": ("Bunny", 57154, 114304, 242, 6, 2, 630, 186), "vase_50": ("Vase", 5419, 10787, 129, 5, 2, 252, 72)}
    print("\n### Table 3 (3D) and Fig. 18: here (the paper's row in brackets where it has one)\n")
    print("| run | vertices | faces | elements | classes (flower / leaf spray) | synthesis iterations | structure analyses | t_syn s | t_sct s | total s | PME per instance by round |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for n in ("bunny", "vase_25", "vase_50", "vase_75"):
        r = load(n)
        s = r["seconds"]
        syn = s["initialization"] + s["placement"] + s["boosting"] + s["topology_cut"]
        p = paper.get(n)
        b = (lambda i: f" ({p[i]})") if p else (lambda i: "")
        print(f"| {n}{' (' + p[0] + ')' if p else ''} | {r['mesh']['vertices']}{b(1)} | {r['mesh']['faces']}{b(2)} | {r['instances']}{b(3)} | {classes(r)} | "
              f"{r['rounds']}{b(4)} | {analyses(r)}{b(5)} | {syn:.1f}{b(6)} | {s['bake_and_structure']:.1f}{b(7)} | {s['total']:.1f} | {pme(r)} |")
EOF
cat "$out/tables.md"
