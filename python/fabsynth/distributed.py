# SPDX-License-Identifier: MIT
"""Slice stacks over a Dask cluster (python3-dask, python3-distributed).

    from dask.distributed import Client
    client = Client("tcp://scheduler:8786")                # or Client(LocalCluster(n_workers=2))
    obj = fabsynth.foam.MeshFoam(fabsynth.foam.Foam(density=0.2, radius=0.25), V, F, frame=0.5)
    plan = obj.plan(pixel=0.05)
    manifest = fabsynth.distributed.write_stack(obj, plan, "out/stack", client=client)

Each task is a range of consecutive layers: the worker receives the object (pickled: a foam is its
parameters, a MeshFoam adds its mesh) and the plan, slices its layers in one pass and writes each as
DIR/slice_NNNNN.png with the pixel size in its pHYs chunk (atomically), returning only the file names.
The manifest DIR/slices.json, in foam_slicer's form, is written last by the caller, after every task
succeeded: a directory without it is an incomplete stack. DIR must be a directory every worker can
write (a shared file system on a real cluster). The bytes of every slice are those of a one-process
run and of foam_slicer with the same options: slices depend only on the object, the plan and the layer.
"""
import json
import os
import tempfile

from . import io as _io

__all__ = ["write_stack", "write_layers"]

VALUE = "255 = solid, 0 = empty (grey levels with --supersample)"


def write_layers(obj, plan, layers, out_dir, supersample=1):
    """Slices `layers` (increasing layer indices of `plan`) of obj (anything with .layers(plan, layers,
    supersample), e.g. fabsynth.foam.Foam or MeshFoam) and writes each as out_dir/slice_NNNNN.png with the
    plan's pixel size. Returns [(layer, z_mm, file name, width, height)]. This is one task's work."""
    written = []
    for k, img in zip(layers, obj.layers(plan, layers, supersample)):
        name = "slice_%05d.png" % k
        _io.write_png(os.path.join(out_dir, name), img, pixel_mm=plan["pixel"])
        written.append((k, plan["z0"] + (k + 0.5) * plan["layer"], name, img.shape[1], img.shape[0]))
    return written


def write_stack(obj, plan, out_dir, client=None, layers_per_task=16, supersample=1):
    """Writes the slice stack `plan` of obj into out_dir, the layers split into tasks of `layers_per_task`
    consecutive layers run on the Dask `client` (None: here, one task after the other), then the manifest
    slices.json. Returns the manifest (a dict)."""
    if layers_per_task < 1:
        raise ValueError("layers_per_task must be >= 1")
    os.makedirs(out_dir, exist_ok=True)
    selected = list(plan["selected"])
    chunks = [selected[i:i + layers_per_task] for i in range(0, len(selected), layers_per_task)]
    if client is None:
        results = [write_layers(obj, plan, c, out_dir, supersample) for c in chunks]
    else:
        futures = [client.submit(write_layers, obj, plan, c, out_dir, supersample, pure=False) for c in chunks]
        results = client.gather(futures)  # raises the first failed task's error: no manifest then
    files = [r for chunk in results for r in chunk]
    manifest = {
        "pixel_mm": plan["pixel"],
        "layer_mm": plan["layer"],
        "origin_mm": [plan["region"][0], plan["region"][1]],
        "width_px": files[0][3] if files else 0,
        "height_px": files[0][4] if files else 0,
        "value": VALUE,
        "count": len(files),
        "slices": [{"layer": k, "z_mm": z, "file": name} for k, z, name, _, _ in files],
    }
    fd, tmp = tempfile.mkstemp(prefix=".slices.json.", dir=out_dir)
    with os.fdopen(fd, "w") as f:
        json.dump(manifest, f, indent=2)
        f.write("\n")
    os.replace(tmp, os.path.join(out_dir, "slices.json"))
    return manifest
