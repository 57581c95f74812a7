# SPDX-License-Identifier: MIT
"""A topology-constrained vector pattern: a Greek key band closed into a ring.

Synthesizes the greek_key exemplar along a circle of radius 30 mm as a band 8 mm high made of exactly
one connected piece, writes band.stl, its preview and vector_pattern.png (the drawing filled with matplotlib).
Run from the repository root after building:

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/vector_pattern.py [OUTDIR]
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

ex = fabsynth.vector_pattern.exemplar_from_svg(DATA / "vector" / "greek_key.svg")
with tqdm(total=1.0, bar_format="{l_bar}{bar}| {elapsed}{postfix}") as bar:
    def progress(fraction, stage):
        bar.set_postfix_str(stage, refresh=False)
        bar.update(fraction - bar.n)
    r = fabsynth.vector_pattern.make_pattern(ex, height=8, circle=30, components=1, seed=1, progress=progress)
fabsynth.io.write_mesh(out / "band.stl", *r.mesh)
fabsynth.io.write_png(out / "band_preview.png", r.preview)
print("components:", r.report["components"], " holes:", r.report["holes"])

fig, ax = plt.subplots(figsize=(7, 7), constrained_layout=True)
for outer, holes in r.drawn:  # mm, y down as in SVG
    ax.fill(outer[:, 0], outer[:, 1], color="steelblue", linewidth=0)
    for hole in holes:
        ax.fill(hole[:, 0], hole[:, 1], color="white", linewidth=0)
ax.set_aspect("equal")
ax.invert_yaxis()
ax.set_xlabel("x (mm)")
ax.set_ylabel("y (mm, down)")
ax.set_title(f"greek key ring: {r.report['components']} component, {r.report['holes']} holes")
fig.savefig(out / "vector_pattern.png", dpi=100)
print(f"wrote band.stl, band_preview.png and vector_pattern.png to {out}")
