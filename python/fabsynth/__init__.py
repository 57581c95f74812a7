# SPDX-License-Identifier: MIT
"""fabsynth: synthesis of 3D-printable structures, from Python.

The package wraps the C++ library's entry points (one submodule per C++ namespace) with NumPy arrays in
and out, following libigl's conventions: meshes are (V, F) with V float64 n x 3 (mm) and F integer m x 3,
pictures and slices are uint8 arrays (h, w) or (h, w, c), point sets n x 3 float64 (mm).

Submodules: fabsynth.io (files), fabsynth.geometry (mesh simplification, Hausdorff distance), fabsynth.foam (procedural Voronoi foams), fabsynth.fem (finite elements),
fabsynth.distributed (slice stacks over a Dask cluster).

Long calls release the GIL, take a ``progress=`` callable ``progress(fraction, stage)`` (returning False
cancels: fabsynth.Cancelled) and stop on Ctrl-C with KeyboardInterrupt. Errors are fabsynth.Error and its
subclasses; InvalidInput is also a ValueError, IoError also an OSError. Results are byte-identical to the
command-line tools' for the same options, for any thread count (set_num_threads).
"""
from ._fabsynth import (Cancelled, Error, InvalidInput, IoError, NoSolution, SolverError, __version__, num_threads,
                        set_num_threads)
from . import distributed, fem, filigree, foam, geometry, io, surface_pattern, vector_pattern

__all__ = ["Cancelled", "Error", "InvalidInput", "IoError", "NoSolution", "SolverError", "__version__", "distributed", "fem", "filigree", "foam", "geometry", "io", "surface_pattern", "vector_pattern",
           "num_threads", "set_num_threads"]
