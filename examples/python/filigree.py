# SPDX-License-Identifier: MIT
"""A planar filigree of spirals and leaves filling a 90 x 70 mm rectangle.

Packs two spirals for every leaf into the rectangle, joins them into one printable piece and writes
filigree.stl, the preview and filigree.png (the piece's outline drawn with matplotlib).
Run from the repository root after building:

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/filigree.py [OUTDIR]
"""
import pathlib
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from tqdm import tqdm

import fabsynth

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python")
out.mkdir(parents=True, exist_ok=True)

spiral = fabsynth.filigree.element_from_svg(DATA / "filigree" / "spiral.svg", size_mm=18, width_mm=0.8)
leaf = fabsynth.filigree.element_from_svg(DATA / "filigree" / "leaf.svg", size_mm=18, width_mm=0.8)

with tqdm(total=1.0, bar_format="{l_bar}{bar}| {elapsed}{postfix}") as bar:
    def progress(fraction, stage):
        bar.set_postfix_str(stage, refresh=False)
        bar.update(fraction - bar.n)
    f = fabsynth.filigree.make_filigree([spiral, leaf], [2, 1], rect=(90, 70), seed=2, structure=False,
                                        progress=progress)

fabsynth.io.write_mesh(out / "filigree.stl", *f.mesh)
fabsynth.io.write_png(out / "filigree_preview.png", f.preview)
print("instances per class (spiral, leaf):", f.report["instances_per_class"])

fig, ax = plt.subplots(figsize=(9, 7), constrained_layout=True)
for outer, holes in f.outline:  # mm, y down as drawn
    ax.fill(outer[:, 0], outer[:, 1], color="darkgoldenrod", linewidth=0)
    for hole in holes:
        ax.fill(hole[:, 0], hole[:, 1], color="white", linewidth=0)
ax.set_aspect("equal")
ax.invert_yaxis()
ax.set_xlabel("x (mm)")
ax.set_ylabel("y (mm, down)")
ax.set_title(f"{f.report['appearance']['instances']} elements, {f.report['components']} connected piece(s)")
fig.savefig(out / "filigree.png", dpi=120)
print(f"wrote filigree.stl, filigree_preview.png and filigree.png to {out}")
