# SPDX-License-Identifier: MIT
"""Finite elements: a cantilever beam from an Abaqus deck, and the stiffness of a cubic lattice.

Solves data/fem/cantilever_c3d8.inp (a 100 mm PLA beam clamped at x = 0, 10 N down at its tip) and
plots each node's vertical displacement against x in fem.png; then homogenizes a periodic cell of
a cubic lattice (3 mm cell, 1 mm square bars) and prints its effective Young's modulus and Poisson ratio.
Run from the repository root after building:

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/fem.py [OUTDIR]
"""
import pathlib
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from tqdm import tqdm

import fabsynth

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python")
out.mkdir(parents=True, exist_ok=True)

r = fabsynth.fem.solve_inp(DATA / "fem" / "cantilever_c3d8.inp")
x, w = r["nodes"][:, 0], r["displacements"][:, 2]
print(f"tip deflection {-w.min():.3f} mm ({r['solver']} solver)")

# Euler-Bernoulli reference: P = 10 N, L = 100 mm, E = 3500 MPa, I = 10^4 / 12 mm^4 (see the deck's header).
xs = np.linspace(0, 100, 101)
beam = -10 * xs**2 * (3 * 100 - xs) / (6 * 3500 * 1e4 / 12)
fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
ax.scatter(x, w, s=12, label="FEM nodes (coarse C3D8 mesh locks: ~15% too stiff)")
ax.plot(xs, beam, "k--", linewidth=1, label="Euler-Bernoulli beam")
ax.set_xlabel("x (mm)")
ax.set_ylabel("z displacement (mm)")
ax.set_title("cantilever_c3d8.inp: 10 N tip load")
ax.legend()
fig.savefig(out / "fem.png", dpi=100)

# A 12^3 voxel cell (0.25 mm voxels) of bars 4 voxels wide along x, y and z through its centre.
band = (np.arange(12) >= 4) & (np.arange(12) < 8)
bx, by, bz = np.meshgrid(band, band, band, indexing="ij")
cell = ((bx & by) | (by & bz) | (bz & bx)).astype(float)
with tqdm(total=1.0, bar_format="{l_bar}{bar}| {elapsed}{postfix}") as bar:
    def progress(fraction, stage):
        bar.set_postfix_str(stage, refresh=False)
        bar.update(fraction - bar.n)
    h = fabsynth.fem.homogenize(cell, voxel_mm=0.25, E=2000, nu=0.35, progress=progress)
print(f"lattice: volume fraction {h['volume_fraction']:.3f}, isotropic fit E {h['E']:.1f} MPa, nu {h['nu']:.3f}")
print(f"wrote fem.png to {out}")
