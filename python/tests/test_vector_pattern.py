# SPDX-License-Identifier: MIT
import numpy as np
import pytest

import fabsynth

vp = fabsynth.vector_pattern


def same_files(tmp_path, r, stem):
    fabsynth.io.write_mesh(tmp_path / "ours.stl", *r.mesh)
    fabsynth.io.write_png(tmp_path / "ours.png", r.preview)
    return ((tmp_path / "ours.stl").read_bytes() == (tmp_path / f"{stem}.stl").read_bytes()
            and (tmp_path / "ours.png").read_bytes() == (tmp_path / f"{stem}.png").read_bytes())


def test_closed_band_equals_curve_patterns_and_keeps_its_topology(tmp_path, tool, data):
    svg = data / "vector" / "greek_key.svg"
    tool("curve_patterns", "--exemplar", svg, "--circle", 30, "--height", 8, "--components", 1, "--seed", 1, "-o", tmp_path / "c.svg")
    r = vp.make_pattern(vp.exemplar_from_svg(svg), height=8, circle=30, components=1, seed=1)
    assert same_files(tmp_path, r, "c")
    rep = r.report
    assert rep["closed"] and rep["components"] == 1 and len(r.drawn) == 1  # the requested topology
    outer, holes = r.drawn[0]
    # the drawn ring's holes: the pattern's holes plus the inner side of the closed band itself
    assert len(holes) == rep["holes"] + 1 and rep["rings"] == 1 + len(holes) and outer.shape[1] == 2
    assert rep["band_length_mm"] == pytest.approx(2 * np.pi * 30)


def test_rectangle_and_space_curve_equal_curve_patterns(tmp_path, tool, data):
    svg = data / "vector" / "quatrefoil.svg"
    tool("curve_patterns", "--exemplar", svg, "--rect", 60, 30, "--height", 8, "--seed", 2, "-o", tmp_path / "r.svg")
    assert same_files(tmp_path, vp.make_pattern(vp.exemplar_from_svg(svg), height=8, rect=(60, 30), seed=2), "r")
    t = np.linspace(0, 4 * np.pi, 200)
    helix = np.stack([20 * np.cos(t), 20 * np.sin(t), 5 * t], axis=1)
    np.savetxt(tmp_path / "helix.csv", helix, delimiter=",", fmt="%.17g")
    key = data / "vector" / "greek_key.svg"
    tool("curve_patterns", "--exemplar", key, "--curve3d", tmp_path / "helix.csv", "--height", 6, "--seed", 1, "-o", tmp_path / "h.svg")
    r = vp.make_pattern(vp.exemplar_from_svg(key), height=6, curve3d=np.loadtxt(tmp_path / "helix.csv", delimiter=","), seed=1)
    assert same_files(tmp_path, r, "h") and r.report["in_space"] and r.preview.shape[2] == 3


def test_impossible_topology_is_no_solution_and_bad_calls_are_refused(data):
    disks = vp.exemplar_from_svg(data / "vector" / "disks.svg")
    with pytest.raises(fabsynth.NoSolution):
        vp.make_pattern(disks, height=8, rect=(60, 30), components=1, seed=2)  # separate disks cannot make one piece
    with pytest.raises(ValueError, match="exactly one"):
        vp.make_pattern(disks, height=8, line=50, circle=10)
    with pytest.raises(ValueError, match="emboss"):
        vp.make_pattern(disks, height=8, line=50, emboss=1.0)
