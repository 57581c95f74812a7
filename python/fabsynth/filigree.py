# SPDX-License-Identifier: MIT
"""Filigrees (Chen, Zhang, Lefebvre et al. 2016; fabsynth::filigree), planar and on a base surface.

    spiral = fabsynth.filigree.element_from_svg("data/filigree/spiral.svg", size_mm=20, width_mm=0.8)
    f = fabsynth.filigree.make_filigree([spiral], rect=(90, 70), seed=1, structure=False)
    fabsynth.io.write_mesh("filigree.stl", *f.mesh); f.report["appearance"]
"""
from ._fabsynth.filigree import (Element, PlanarFiligree, SurfaceFiligree, element_from_svg, make_filigree,
                                 make_surface_filigree)

__all__ = ["Element", "PlanarFiligree", "SurfaceFiligree", "element_from_svg", "make_filigree", "make_surface_filigree"]
