# SPDX-License-Identifier: MIT
"""Procedural Voronoi foams (Martinez, Dumas & Lefebvre 2016; fabsynth::foam).

    f = fabsynth.foam.Foam(density=0.2, radius=0.25, cell=3, seed=1)    # foam_slicer's options
    inside = f.contains(points)                                          # n x 3 mm -> n bools
    img = f.slice(5.0, region=(0, 0, 20, 20), pixel=0.1)                 # uint8 (200, 200), 255 = solid
    for img in f.slices([1.0, 1.1, 1.2], (0, 0, 20, 20), 0.1): ...       # one pass, an iterator
    obj = fabsynth.foam.MeshFoam(f, V, F, frame=0.5)                     # the foam inside a closed mesh
    plan = obj.plan(pixel=0.05)                                          # the stack foam_slicer slices
"""
from ._fabsynth import foam as _foam
from ._fabsynth.foam import density_for_elasticity, elasticity, plan, reachable_elasticity

__all__ = ["Foam", "MeshFoam", "density_for_elasticity", "elasticity", "plan", "reachable_elasticity"]

#: slices computed per call of the C++ slicer by the iterators (it builds the foam's edges once per call)
SLICES_PER_BATCH = 16


def _slices(obj, zs, region, pixel, supersample=1, progress=None):
    zs = [float(z) for z in zs]
    for start in range(0, len(zs), SLICES_PER_BATCH):
        batch = zs[start:start + SLICES_PER_BATCH]
        report = None
        if progress is not None:
            def report(fraction, stage, start=start, n=len(batch)):
                return progress((start + fraction * n) / len(zs), stage)
        yield from obj._slices(batch, region, pixel, supersample, report)


class _Stack:
    """Slicing methods shared by Foam and MeshFoam (both have the C++ _slices)."""

    def slices(self, zs, region, pixel, supersample=1, progress=None):
        """Slices at the increasing heights zs (mm) over region (x0, y0, x1, y1) (mm), each as slice() gives
        it: an iterator of uint8 arrays, computed SLICES_PER_BATCH at a time (the foam's edges are built once
        per batch). progress(fraction, stage) as the slices finish; returning False cancels."""
        return _slices(self, zs, region, pixel, supersample, progress)

    def layers(self, plan, layers=None, supersample=1, progress=None):
        """The slices of layer indices `layers` (increasing; default plan["selected"]) of a stack planned by
        plan(): an iterator of uint8 arrays, the images foam_slicer writes as slice_NNNNN.png."""
        layers = plan["selected"] if layers is None else layers
        z = [plan["z0"] + (k + 0.5) * plan["layer"] for k in layers]
        return _slices(self, z, plan["region"], plan["pixel"], supersample, progress)


class Foam(_Stack, _foam.Foam):
    __doc__ = _foam.Foam.__doc__

    def __reduce__(self):
        return (_rebuild_foam, (self.params,))


def _rebuild_foam(params):
    return Foam(**params)


class MeshFoam(_Stack, _foam.MeshFoam):
    __doc__ = _foam.MeshFoam.__doc__

    def slice(self, z, region, pixel, supersample=1):
        """Slice at height z (mm) over region (x0, y0, x1, y1) (mm): uint8 (h, w), row 0 at y0, 255 = solid
        (frame, or foam inside the mesh)."""
        return self._slices([float(z)], region, pixel, supersample, None)[0]

    def __reduce__(self):
        V, F = self.mesh
        return (_rebuild_mesh_foam, (self.foam.params, V, F, self.frame, self.cuts))


def _rebuild_mesh_foam(params, V, F, frame, cuts):
    return MeshFoam(Foam(**params), V, F, frame=frame, cuts=cuts)
