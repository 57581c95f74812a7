# SPDX-License-Identifier: MIT
"""Topology-constrained vector patterns (Zhou, Jiang, Lefebvre et al. 2014; fabsynth::vector_pattern).

    ex = fabsynth.vector_pattern.exemplar_from_svg("data/vector/greek_key.svg")
    r = fabsynth.vector_pattern.make_pattern(ex, height=8, circle=30, components=1, holes=0)
    r.drawn            # [(outer n x 2, [holes])], mm, y down
    fabsynth.io.write_mesh("band.stl", *r.mesh)
"""
from ._fabsynth.vector_pattern import Exemplar, PatternResult, exemplar_from_svg, make_pattern

__all__ = ["Exemplar", "PatternResult", "exemplar_from_svg", "make_pattern"]
