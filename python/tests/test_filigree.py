# SPDX-License-Identifier: MIT
import numpy as np
import pytest

import fabsynth

fg = fabsynth.filigree


def test_planar_filigree_equals_the_filigree_tool(tmp_path, tool, data):
    svg = data / "filigree" / "spiral.svg"
    tool("filigree", "--no-simplify", "--element", svg, "--rect", 40, 30, "--scale", 15, "--width", 0.8, "--no-structure", "--seed", 1, "-o", tmp_path / "t.svg")
    f = fg.make_filigree([fg.element_from_svg(svg, size_mm=15, width_mm=0.8)], rect=(40, 30), seed=1, structure=False)
    fabsynth.io.write_mesh(tmp_path / "p.stl", *f.mesh)
    fabsynth.io.write_png(tmp_path / "p.png", f.preview)
    fabsynth.io.write_png(tmp_path / "p_steps.png", f.steps)
    for ours, theirs in (("p.stl", "t.stl"), ("p.png", "t.png"), ("p_steps.png", "t_steps.png")):
        assert (tmp_path / ours).read_bytes() == (tmp_path / theirs).read_bytes(), ours
    rep = f.report
    assert rep["components"] == 1 and len(f.outline) == 1
    outer, holes = f.outline[0]
    assert outer.shape[1] == 2 and len(holes) > 0  # lace: a piece with holes
    assert rep["appearance"]["instances"] == rep["instances_per_class"][0] > 5
    assert not rep["reinforcement"]["analysed"] and f.stress_map.size == 0


def test_surface_filigree_equals_the_filigree_tool(tmp_path, tool, data):
    V, F = fabsynth.io.read_mesh(data / "meshes" / "icosphere.obj")
    V = V * 16.0  # a sphere of radius 16 mm (exact)
    fabsynth.io.write_mesh(tmp_path / "sphere.obj", V, F)
    svg = data / "filigree" / "spiral.svg"
    tool("filigree", "--no-simplify", "--element", svg, "--mesh", tmp_path / "sphere.obj", "--scale", 12, "--width", 0.8, "--no-structure", "--seed", 1,
         "-o", tmp_path / "t.svg")
    f = fg.make_surface_filigree([fg.element_from_svg(svg, size_mm=12, width_mm=0.8)], None, V, F, up=(0, 0, 1), seed=1, structure=False)
    fabsynth.io.write_mesh(tmp_path / "p.stl", *f.solid)
    fabsynth.io.write_png(tmp_path / "p.png", f.preview)
    assert (tmp_path / "p.stl").read_bytes() == (tmp_path / "t.stl").read_bytes()
    assert (tmp_path / "p.png").read_bytes() == (tmp_path / "t.png").read_bytes()
    assert f.report["solid_components"] == 1
    # the solid lies on the sphere, within the thickness (1 mm) of its surface
    r = np.linalg.norm(f.solid[0], axis=1)
    assert r.min() > 16 - 1.5 and r.max() < 16 + 1.5


def test_filigree_options_are_checked(data):
    e = fg.element_from_svg(data / "filigree" / "spiral.svg", size_mm=15, width_mm=0.8)
    with pytest.raises(ValueError, match="rect"):
        fg.make_filigree([e])
    with pytest.raises(ValueError, match="material"):
        fg.make_filigree([e], rect=(40, 30), material="gold")
    with pytest.raises(OSError):
        fg.element_from_svg(data / "filigree" / "missing.svg")
