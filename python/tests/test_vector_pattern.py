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
    tool("curve_patterns", "--no-simplify", "--exemplar", svg, "--circle", 30, "--height", 8, "--components", 1, "--seed", 1, "-o", tmp_path / "c.svg")
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
    tool("curve_patterns", "--no-simplify", "--exemplar", svg, "--rect", 60, 30, "--height", 8, "--seed", 2, "-o", tmp_path / "r.svg")
    assert same_files(tmp_path, vp.make_pattern(vp.exemplar_from_svg(svg), height=8, rect=(60, 30), seed=2), "r")
    t = np.linspace(0, 4 * np.pi, 200)
    helix = np.stack([20 * np.cos(t), 20 * np.sin(t), 5 * t], axis=1)
    np.savetxt(tmp_path / "helix.csv", helix, delimiter=",", fmt="%.17g")
    key = data / "vector" / "greek_key.svg"
    tool("curve_patterns", "--no-simplify", "--exemplar", key, "--curve3d", tmp_path / "helix.csv", "--height", 6, "--seed", 1, "-o", tmp_path / "h.svg")
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


def test_band_carved_into_a_surface_equals_curve_patterns(tmp_path, tool, data):
    # the egg stand of the main job (Fig. 23): separate disks carved out of a 2 mm shell along a wavy loop
    a = 2 * np.pi * np.arange(8) / 8
    t = 1.35 + 0.12 * np.sin(2 * a)
    r = 21 * np.sin(t) * (1 + 0.08 * np.cos(t))
    points = np.stack([r * np.cos(a), r * np.sin(a), 28 * (1 - np.cos(t))], axis=1)
    np.savetxt(tmp_path / "egg.csv", points, delimiter=",", fmt="%.17g")
    mesh, disks = data / "meshes" / "egg_stand.obj", data / "vector" / "disks.svg"
    tool("curve_patterns", "--no-simplify", "--exemplar", disks, "--mesh", mesh, "--points", tmp_path / "egg.csv", "--closed", "--height", 12, "--carve", 2,
         "--cell", 1.0, "-o", tmp_path / "e.svg")
    V, F = fabsynth.io.read_mesh(mesh)
    r = vp.make_pattern(vp.exemplar_from_svg(disks), height=12, surface=(V, F), points=np.loadtxt(tmp_path / "egg.csv", delimiter=","),
                        closed=True, carve=2, cell=1.0)
    assert same_files(tmp_path, r, "e")
    rep = r.report
    # one printable piece with a round window per disk: genus = the pattern's components
    assert rep["solid_components"] == 1 and rep["solid_genus"] == rep["components"] == len(r.drawn) > 1


def test_planar_curves_take_the_requested_topology(data):
    key = vp.exemplar_from_svg(data / "vector" / "greek_key.svg")
    straight = vp.make_pattern(key, height=8, line=120, components=1, seed=3)
    assert straight.report["components"] == 1 and len(straight.drawn) == 1 and not straight.report["closed"]
    assert straight.report["band_length_mm"] == pytest.approx(120)
    s = np.linspace(0, 1, 400)
    wave = np.stack([150 * s, 10 * np.sin(2 * np.pi * 2 * s)], axis=1)
    r = vp.make_pattern(key, height=8, curve=wave, components=1, holes=20, seed=1)
    assert r.report["components"] == 1 and r.report["holes"] == 20 and len(r.drawn) == 1 and len(r.drawn[0][1]) == 20
    assert r.mesh[1].shape[1] == 3 and r.preview.ndim == 2  # planar forms: a grey coverage picture
