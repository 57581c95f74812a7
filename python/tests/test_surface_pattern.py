# SPDX-License-Identifier: MIT

import numpy as np
import pytest

import fabsynth

sp = fabsynth.surface_pattern


def hooks(data):
    return sp.make_exemplar(fabsynth.io.read_png(data / "exemplars" / "hooks.png"), feature_px=2)


def test_make_pattern_equals_the_surface_patterns_tool(tmp_path, tool, data):
    mesh = data / "meshes" / "bunny_lowres.obj"
    tool("surface_patterns", "--no-simplify", mesh, "--exemplar", data / "exemplars" / "hooks.png", "--feature", 2, "-r", 48, "--size", 40,
         "--thickness", 1.2, "--up", 0, 1, 0, "--gravity", 0, -1, 0, "--max-iterations", 2, "--preview-size", 256, "-o", tmp_path / "tool")
    V, F = fabsynth.io.read_mesh(mesh)
    r = sp.make_pattern(V, F, hooks(data), size_mm=40, thickness_mm=1.2, resolution=48, up=(0, 1, 0), gravity=(0, -1, 0),
                        max_iterations=2, preview_size=256)
    fabsynth.io.write_mesh(tmp_path / "py.stl", *r.mesh)
    fabsynth.io.write_png(tmp_path / "py.png", r.preview)
    assert (tmp_path / "py.stl").read_bytes() == (tmp_path / "tool" / "pattern.stl").read_bytes()
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "tool" / "preview.png").read_bytes()
    rep = r.report
    assert rep["components_26"] >= 1 and rep["pattern_watertight"]
    assert r.state.shape == (rep["shell_voxels"],) and set(np.unique(r.state)) <= {1, 2, 3, 4}
    assert rep["final_voxels"] == int(np.count_nonzero(r.state >= 2))
    assert r.solid_voxels.shape == (rep["solid_voxels"], 3) and r.preview.shape[2] == 3
    assert 0.05 < rep["solid_fraction_synthesized"] < 0.4  # the hooks exemplar is 18% solid
    assert [lv["level"] for lv in rep["levels"]] == list(range(len(rep["levels"])))


def test_exemplar_properties(data):
    mask = fabsynth.io.read_png(data / "exemplars" / "hooks.png")
    ex = sp.make_exemplar(mask, fabsynth.io.read_png(data / "exemplars" / "hooks_color.png"), feature_px=2)
    assert (ex.width, ex.height, ex.channels, ex.tileable) == (mask.shape[1], mask.shape[0], 5, True)
    assert ex.solid_fraction == pytest.approx(np.count_nonzero(mask > 127) / mask.size, abs=0.01)
    assert hooks(data).channels == 2


def test_options_are_checked(data):
    V, F = fabsynth.io.read_mesh(data / "meshes" / "bunny_lowres.obj")
    with pytest.raises(ValueError, match="below one voxel"):
        sp.make_pattern(V, F, hooks(data), size_mm=40, thickness_mm=0.1, resolution=64)
    with pytest.raises(ValueError, match="feature"):
        sp.make_exemplar(np.zeros((8, 8), np.uint8), feature_px=0)
    with pytest.raises(ValueError, match="material"):
        sp.make_pattern(V, F, hooks(data), size_mm=40, thickness_mm=1.2, resolution=32, material="wood")


def test_ctrl_c_stops_a_surface_pattern_within_a_second(data, interrupt):
    # 2 s after the start the child is in the shell or the synthesis (the whole run takes about a minute)
    rc, elapsed = interrupt(f"""
        import fabsynth
        sp = fabsynth.surface_pattern
        V, F = fabsynth.io.read_mesh({str(data / "meshes" / "bunny.obj")!r})
        ex = sp.make_exemplar(fabsynth.io.read_png({str(data / "exemplars" / "hooks.png")!r}), feature_px=2)
        print("started", flush=True)
        sp.make_pattern(V, F, ex, size_mm=100, thickness_mm=1.2, resolution=256, up=(0, 1, 0), gravity=(0, -1, 0))
    """, 2.0)
    assert rc == 3 and elapsed < 1.0, f"exit {rc}, took {elapsed:.2f} s to stop"
