# SPDX-License-Identifier: MIT
"""Meshes: simplification with guarantees and the Hausdorff distance (fabsynth::simplify_mesh, hausdorff_distance)."""
from ._fabsynth.geometry import hausdorff_distance, simplify_mesh

__all__ = ["hausdorff_distance", "simplify_mesh"]
