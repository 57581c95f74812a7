# SPDX-License-Identifier: MIT
import csv

import numpy as np
import pytest

import fabsynth


def test_solve_inp_equals_fem_solve(tmp_path, tool, data):
    deck = data / "fem" / "mixed_c3d8_c3d6_s3.inp"
    tool("fem_solve", deck, "-o", tmp_path)
    r = fabsynth.fem.solve_inp(deck)
    with open(tmp_path / "displacements.csv") as f:
        rows = list(csv.reader(f))[1:]
    assert [int(row[0]) for row in rows] == list(r["node_labels"])
    # the tool prints shortest round-trip decimals: equal to the double
    assert np.array_equal(np.array([[float(v) for v in row[1:]] for row in rows]), r["displacements"])
    with open(tmp_path / "stresses.csv") as f:
        srows = list(csv.reader(f))[1:]
    assert np.array_equal(np.array([[float(v) for v in row[1:7]] for row in srows]), r["stresses"])
    assert np.array_equal(np.array([float(row[7]) for row in srows]), r["von_mises"])
    assert r["displacements"].shape == r["nodes"].shape and np.abs(r["displacements"]).max() > 0


def test_a_deck_given_as_text_solves_the_same(data):
    deck = data / "fem" / "mixed_c3d8_c3d6_s3.inp"
    a, b = fabsynth.fem.solve_inp(deck), fabsynth.fem.solve_inp_text(deck.read_text())
    assert np.array_equal(a["displacements"], b["displacements"]) and a["solver"] == b["solver"] == "ldlt"
    with pytest.raises(ValueError, match="cholmod"):
        fabsynth.fem.solve_inp(deck, solver="cholmod")


def test_plate_deflection_is_near_plate_theory(data):
    # data/fem/README.md: simply supported square plate, w_max = 0.00406 q a^4 / D = 4.4335 mm (Timoshenko &
    # Woinowsky-Krieger); its 8 x 8 S3 mesh gives 4.39
    r = fabsynth.fem.solve_inp(data / "fem" / "plate_s3_simply_supported.inp")
    assert np.abs(r["displacements"][:, 2]).max() == pytest.approx(4.4335, rel=0.02)


def test_homogenizing_a_solid_cell_gives_the_material():
    r = fabsynth.fem.homogenize(np.ones((4, 4, 4)), 0.5, E=200.0, nu=0.3)
    lam, mu = 200 * 0.3 / (1.3 * 0.4), 200 / 2.6
    C = np.zeros((6, 6))
    C[:3, :3] = lam
    C[np.arange(3), np.arange(3)] = lam + 2 * mu
    C[np.arange(3, 6), np.arange(3, 6)] = mu
    assert np.allclose(r["C"], C, rtol=1e-6, atol=1e-6)
    assert r["E"] == pytest.approx(200, rel=1e-6) and r["nu"] == pytest.approx(0.3, rel=1e-6)
    assert r["volume_fraction"] == 1 and r["removed_fraction"] == 0


def test_homogenize_checks_its_input():
    with pytest.raises(ValueError, match="3D"):
        fabsynth.fem.homogenize(np.ones((4, 4)))
    with pytest.raises(ValueError, match="nu"):
        fabsynth.fem.homogenize(np.ones((2, 2, 2)), nu=0.5)
    with pytest.raises(fabsynth.NoSolution):
        fabsynth.fem.homogenize(np.zeros((2, 2, 2)))
