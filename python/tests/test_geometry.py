# SPDX-License-Identifier: MIT
import numpy as np
import pytest

import fabsynth


def _sphere_points_error(V, F, samples):
    """Largest distance of points inside the faces (barycentric `samples`) from the unit sphere."""
    worst = 0.0
    for w in samples:
        P = w[0] * V[F[:, 0]] + w[1] * V[F[:, 1]] + w[2] * V[F[:, 2]]
        worst = max(worst, float(np.max(np.abs(np.linalg.norm(P, axis=1) - 1.0))))
    return worst


def test_simplify_mesh_keeps_a_sphere_within_the_tolerance_of_the_true_sphere(data):
    # oracle: the unit sphere the icosphere's vertices lie on (to 1e-6), not the library's Hausdorff
    V, F = fabsynth.io.read_mesh(data / "meshes" / "icosphere.obj")
    assert np.allclose(np.linalg.norm(V, axis=1), 1.0, atol=1e-5)
    tol = 0.01
    V2, F2, source, report = fabsynth.geometry.simplify_mesh(V, F, tolerance=tol)
    assert report["simplified"], report["warning"]
    assert report["raw_triangles"] == len(F) and report["triangles"] == len(F2) < len(F) / 2
    assert report["hausdorff_measured_mm"] <= report["hausdorff_mm"] <= tol
    # every result vertex is the input vertex `source` names, at its exact position
    assert np.array_equal(V2, V[source])
    # closed, one piece, genus 0: Euler characteristic 2, every edge in exactly two faces
    edges = np.sort(np.concatenate([F2[:, [0, 1]], F2[:, [1, 2]], F2[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert np.all(counts == 2)
    assert len(V2) - len(counts) + len(F2) == 2
    # points inside the faces: within the tolerance of the sphere plus the input's own chord error
    raw_error = _sphere_points_error(V, F, [(1 / 3, 1 / 3, 1 / 3)])
    assert _sphere_points_error(V2, F2, [(1 / 3, 1 / 3, 1 / 3), (0.6, 0.2, 0.2), (0.5, 0.5, 0.0)]) <= tol + raw_error


def test_hausdorff_distance_of_two_concentric_spheres(data):
    V, F = fabsynth.io.read_mesh(data / "meshes" / "icosphere.obj")
    lower, upper = fabsynth.geometry.hausdorff_distance(V, F, 1.25 * V, F, precision=0.01)
    # the vertices are 0.25 apart radially (to the 1e-6 the file stores them with); faces of the
    # larger one lie at most its chord error inside it
    assert lower <= upper <= lower + 0.01 + 1e-12
    assert 0.25 - 0.01 <= lower <= 0.25 + 1e-5


def test_simplify_mesh_refuses_bad_options(data):
    V, F = fabsynth.io.read_mesh(data / "meshes" / "icosphere.obj")
    with pytest.raises(fabsynth.InvalidInput, match="tolerance"):
        fabsynth.geometry.simplify_mesh(V, F, tolerance=0.0)
    with pytest.raises(ValueError, match="attempts"):
        fabsynth.geometry.simplify_mesh(V, F, attempts=0)


@pytest.mark.skipif(not fabsynth.io.has_3mf, reason="built without lib3mf")
def test_3mf_face_colours_round_trip_and_are_in_the_package(tmp_path, data):
    import zipfile
    V, F = fabsynth.io.read_mesh(data / "meshes" / "icosphere.obj")
    C = np.zeros((len(F), 3), dtype=np.uint8)
    C[:, 0] = 200
    C[len(F) // 2:, 2] = 90  # two colours
    fabsynth.io.write_3mf(tmp_path / "c.3mf", V, F, name="two colours", face_colours=C)
    V2, F2, RGBA = fabsynth.io.read_3mf(tmp_path / "c.3mf", colours=True)
    assert np.array_equal(F2, F) and RGBA.shape == (len(F), 4)
    assert np.array_equal(RGBA[:, :3], C) and np.all(RGBA[:, 3] == 255)
    # read independently of lib3mf: the model part names both sRGB colours
    with zipfile.ZipFile(tmp_path / "c.3mf") as z:
        model = z.read("3D/3dmodel.model").decode().upper()
    assert "#C80000" in model and "#C8005A" in model
    with pytest.raises(ValueError, match="face_colours"):
        fabsynth.io.write_3mf(tmp_path / "d.3mf", V, F, face_colours=C[:, :2].copy())
