# SPDX-License-Identifier: MIT
"""Structurally sound surface patterns by example (Lu, Lefebvre, Dumas, Wu & Dick 2015; fabsynth::surface_pattern).

    V, F = fabsynth.io.read_mesh("data/meshes/bunny.obj")
    ex = fabsynth.surface_pattern.make_exemplar(fabsynth.io.read_png("data/exemplars/hooks.png"), feature_px=2)
    r = fabsynth.surface_pattern.make_pattern(V, F, ex, size_mm=100, thickness_mm=1.2, up=(0, 1, 0), gravity=(0, -1, 0))
    fabsynth.io.write_mesh("pattern.stl", *r.mesh); r.report["reinforcement_ratio"]
"""
from ._fabsynth.surface_pattern import Exemplar, PatternResult, make_exemplar, make_pattern

__all__ = ["Exemplar", "PatternResult", "make_exemplar", "make_pattern"]
