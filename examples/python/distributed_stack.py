# SPDX-License-Identifier: MIT
"""Slicing the sphere foam of foam.py into a full stack of PNG files on a Dask cluster.

Starts a local cluster of two worker processes, has them write the 400 slices (0.1 mm pixels and
layers) into OUTDIR/stack with the manifest slices.json, then reads the stack back to draw its middle
slice and a vertical section through it in distributed_stack.png.
Run from the repository root after building:

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/distributed_stack.py [OUTDIR]

(Not named distributed.py: a script of that name would hide Dask's own `distributed` package.)
"""
import pathlib
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from dask.distributed import Client, LocalCluster

import fabsynth

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"


def main():
    out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python")
    out.mkdir(parents=True, exist_ok=True)
    V, F = fabsynth.io.read_mesh(DATA / "meshes" / "icosphere.obj")
    foam = fabsynth.foam.Foam(density=0.2, radius=0.25, cell=3, seed=1)
    obj = fabsynth.foam.MeshFoam(foam, V * 20.0, F, frame=0.5)
    plan = obj.plan(pixel=0.1)  # every layer

    # On a real cluster: client = Client("tcp://scheduler:8786"), with OUTDIR on a shared file system.
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        manifest = fabsynth.distributed.write_stack(obj, plan, out / "stack", client=client, layers_per_task=8)
    print("slices written:", manifest["count"])

    stack = [fabsynth.io.read_png(out / "stack" / s["file"]) for s in manifest["slices"]]
    middle = stack[len(stack) // 2]
    section = np.array([img[img.shape[0] // 2] for img in stack])  # the row at y = 0 of every slice
    x0, y0, x1, y1 = plan["region"]
    z0, z1 = plan["z0"], plan["z0"] + plan["layers"] * plan["layer"]
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 5), constrained_layout=True)
    a.imshow(middle, cmap="gray", origin="lower", extent=(x0, x1, y0, y1))
    a.set(title=f"slice {len(stack) // 2} of {len(stack)}", xlabel="x (mm)", ylabel="y (mm)")
    b.imshow(section, cmap="gray", origin="lower", extent=(x0, x1, z0, z1))
    b.set(title="section y = 0 through the stack", xlabel="x (mm)", ylabel="z (mm)")
    fig.savefig(out / "distributed_stack.png", dpi=100)
    print(f"wrote {out / 'stack'} and distributed_stack.png")


if __name__ == "__main__":  # the worker processes import this file again
    main()
