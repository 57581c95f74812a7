# SPDX-License-Identifier: MIT
"""A structurally sound surface pattern by example on the Stanford bunny.

Carves the "hooks" exemplar into the surface of an 80 mm bunny (160 voxels along it, 0.5 mm),
reinforcing it until it holds its own weight standing upright, and writes pattern.stl, the preview
and surface_pattern.png (the preview and the synthesis time of each level of the multiresolution
pyramid). Takes tens of seconds.
Run from the repository root after building:

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/surface_pattern.py [OUTDIR]
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

V, F = fabsynth.io.read_mesh(DATA / "meshes" / "bunny_lowres.obj")
mask = fabsynth.io.read_png(DATA / "exemplars" / "hooks.png")
colour = fabsynth.io.read_png(DATA / "exemplars" / "hooks_color.png")
ex = fabsynth.surface_pattern.make_exemplar(mask, colour, feature_px=2)

with tqdm(total=1.0, bar_format="{l_bar}{bar}| {elapsed}{postfix}") as bar:
    def progress(fraction, stage):
        bar.set_postfix_str(stage, refresh=False)
        bar.update(fraction - bar.n)
    r = fabsynth.surface_pattern.make_pattern(V, F, ex, size_mm=80, thickness_mm=1.2, resolution=160,
                                              up=(0, 1, 0), gravity=(0, -1, 0), progress=progress)

fabsynth.io.write_mesh(out / "pattern.stl", *r.mesh)
fabsynth.io.write_png(out / "pattern_preview.png", r.preview)
print("reinforcement ratio:", r.report["reinforcement_ratio"])

levels = r.report["levels"]
fig, (a, b) = plt.subplots(1, 2, figsize=(14, 4.5), width_ratios=(2.2, 1), constrained_layout=True)
a.imshow(r.preview)
a.set_axis_off()
a.set_title("pattern.stl, two views")
b.bar([f"{lv['spacing_mm']:g}" for lv in levels], [lv["seconds"] for lv in levels])
b.set_yscale("log")
b.set_xlabel("pyramid level: voxel spacing (mm)")
b.set_ylabel("synthesis time (s)")
b.set_title("synthesis time per level")
fig.savefig(out / "surface_pattern.png", dpi=100)
print(f"wrote pattern.stl, pattern_preview.png and surface_pattern.png to {out}")
