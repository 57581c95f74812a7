# SPDX-License-Identifier: MIT
import numpy as np
import pytest

import fabsynth


def test_mesh_round_trip_is_exact_in_obj(tmp_path, data):
    V, F = fabsynth.io.read_mesh(data / "meshes" / "egg_stand.obj")
    assert V.dtype == np.float64 and V.shape[1] == 3 and F.shape[1] == 3 and F.dtype == np.int64
    fabsynth.io.write_mesh(tmp_path / "m.obj", V, F.astype(np.int32))  # int32 faces are accepted too
    V2, F2 = fabsynth.io.read_mesh(tmp_path / "m.obj")
    assert np.array_equal(V, V2) and np.array_equal(F, F2)


def test_bad_meshes_are_refused_naming_the_problem():
    V = np.zeros((3, 3))
    with pytest.raises(ValueError, match="refers to vertex 7"):
        fabsynth.io.write_mesh("/tmp/never.obj", V, np.array([[0, 1, 7]]))
    with pytest.raises(fabsynth.InvalidInput, match="integers"):
        fabsynth.io.write_mesh("/tmp/never.obj", V, np.array([[0.0, 1.0, 2.0]]))
    with pytest.raises(ValueError, match="n x 3"):
        fabsynth.io.write_mesh("/tmp/never.obj", np.zeros((3, 2)), np.array([[0, 1, 2]]))


def test_missing_file_is_an_oserror():
    with pytest.raises(OSError) as e:
        fabsynth.io.read_mesh("/nonexistent/m.obj")
    assert isinstance(e.value, fabsynth.IoError) and isinstance(e.value, fabsynth.Error)
    with pytest.raises(ValueError, match="unknown mesh extension"):
        fabsynth.io.read_mesh("/tmp/m.xyz")


def test_png_round_trip_keeps_pixels_channels_and_pixel_size(tmp_path):
    rng = np.random.default_rng(3)
    grey = rng.integers(0, 256, (17, 31), dtype=np.uint8)
    rgb = rng.integers(0, 256, (5, 4, 3), dtype=np.uint8)
    fabsynth.io.write_png(tmp_path / "g.png", grey, pixel_mm=0.05)
    fabsynth.io.write_png(tmp_path / "c.png", rgb)
    assert np.array_equal(fabsynth.io.read_png(tmp_path / "g.png"), grey)
    assert np.array_equal(fabsynth.io.read_png(tmp_path / "c.png"), rgb)
    info = fabsynth.io.read_png_info(tmp_path / "g.png")
    assert (info["width"], info["height"], info["channels"]) == (31, 17, 1)
    assert info["pixel_mm"] == pytest.approx((0.05, 0.05), rel=1e-9)  # 20000 pixels per metre, exactly
    assert fabsynth.io.read_png_info(tmp_path / "c.png")["pixel_mm"] is None
    with pytest.raises(ValueError, match="uint8"):
        fabsynth.io.write_png(tmp_path / "f.png", grey.astype(np.float32))


def test_svg_shapes_come_out_as_point_arrays(tmp_path):
    (tmp_path / "d.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="20mm" height="10mm" viewBox="0 0 20 10">'
                                    '<rect id="r" x="1" y="2" width="3" height="4" fill="red"/>'
                                    '<path d="M 0 0 L 5 5" stroke="black" fill="none" stroke-width="0.5"/></svg>')
    doc = fabsynth.io.read_svg(tmp_path / "d.svg")
    assert (doc["width"], doc["width_unit"], doc["view_box"]) == (20, "mm", (0, 0, 20, 10))
    rect, line = doc["shapes"]
    assert rect["id"] == "r" and rect["fill"] == "red" and rect["closed"] == [True]
    assert sorted(map(tuple, rect["subpaths"][0])) == [(1, 2), (1, 6), (4, 2), (4, 6)]
    assert line["closed"] == [False] and line["stroke_width"] == 0.5
    assert np.array_equal(line["subpaths"][0], [[0, 0], [5, 5]])


@pytest.mark.skipif(not fabsynth.io.has_3mf, reason="built without lib3mf")
def test_3mf_round_trip(tmp_path, data):
    V, F = fabsynth.io.read_mesh(data / "meshes" / "icosphere.obj")
    fabsynth.io.write_3mf(tmp_path / "m.3mf", V, F, name="sphere")
    V2, F2 = fabsynth.io.read_3mf(tmp_path / "m.3mf")
    assert np.allclose(V2, V, atol=1e-6) and np.array_equal(F2, F)  # 3MF stores decimals of floats
