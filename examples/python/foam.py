# SPDX-License-Identifier: MIT
"""A procedural Voronoi foam inside a sphere, sliced for printing, and a graded foam.

Writes four slices of the foam inside a 20 mm sphere (icosphere.obj scaled by 20) as PNG files with
their pixel size, one slice of a foam whose density grows along x, and foam.png showing them all.
Run from the repository root after building:

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/foam.py [OUTDIR]
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

# A foam (0.2 seeds/mm^3, bars of radius 0.25 mm) clipped to the sphere, with a 0.5 mm skin.
V, F = fabsynth.io.read_mesh(DATA / "meshes" / "icosphere.obj")
foam = fabsynth.foam.Foam(density=0.2, radius=0.25, cell=3, seed=1)
obj = fabsynth.foam.MeshFoam(foam, V * 20.0, F, frame=0.5)
plan = obj.plan(pixel=0.1, count=4)  # 4 evenly spaced layers of the full stack

with tqdm(total=1.0, desc="slicing", bar_format="{l_bar}{bar}| {elapsed}") as bar:
    slices = list(obj.layers(plan, progress=lambda f, stage: bar.update(f - bar.n)))
zs = [plan["z0"] + (k + 0.5) * plan["layer"] for k in plan["selected"]]
for k, img in zip(plan["selected"], slices):
    fabsynth.io.write_png(out / f"foam_slice_{k:05d}.png", img, pixel_mm=plan["pixel"])

# A graded foam: density 0.05 at x = -20 mm rising to 0.6 at x = 20 mm.
graded = fabsynth.foam.Foam(density_x=(0.05, 0.6, -20, 20), radius=0.25, cell=3, seed=1)
region = (-20, -20, 20, 20)
g = graded.slice(0.0, region, 0.05)
fabsynth.io.write_png(out / "graded_z0.png", g, pixel_mm=0.05)

x0, y0, x1, y1 = plan["region"]
fig, axes = plt.subplots(1, 5, figsize=(20, 4.5), constrained_layout=True)
for ax, img, z in zip(axes, slices, zs):
    ax.imshow(img, cmap="gray", origin="lower", extent=(x0, x1, y0, y1))
    ax.set_title(f"foam in sphere, z = {z:.2f} mm")
axes[-1].imshow(g, cmap="gray", origin="lower", extent=(region[0], region[2], region[1], region[3]))
axes[-1].set_title("graded foam, z = 0 mm")
for ax in axes:
    ax.set_xlabel("x (mm)")
axes[0].set_ylabel("y (mm)")
fig.savefig(out / "foam.png", dpi=100)
print(f"wrote {len(slices) + 1} slices and foam.png to {out}")
