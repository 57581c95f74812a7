# SPDX-License-Identifier: MIT
import pickle

import numpy as np
import pytest

import fabsynth

FOAM = dict(density=0.2, radius=0.25, cell=3, seed=1)
TOOL_FOAM = ["--density", 0.2, "--radius", 0.25, "--cell", 3, "--seed", 1]


def test_contains_equals_foam_slicer_eval(tmp_path, tool):
    pts = np.random.default_rng(7).uniform(-10, 10, (20000, 3))
    np.savetxt(tmp_path / "p.csv", pts, delimiter=",", fmt="%.17g")
    tool("foam_slicer", "eval", "--points", tmp_path / "p.csv", "--out", tmp_path / "r.txt", *TOOL_FOAM)
    expected = np.loadtxt(tmp_path / "r.txt", dtype=np.int64).astype(bool)
    got = fabsynth.foam.Foam(**FOAM).contains(pts)
    assert got.dtype == bool and np.array_equal(got, expected)
    assert 0.1 < got.mean() < 0.5  # a foam, not all solid or all empty


def test_seeds_equal_foam_slicer_seeds(tmp_path, tool):
    box = (0, 0, 0, 12, 9, 6)
    tool("foam_slicer", "seeds", "--box", *box, "--out", tmp_path / "s.csv", *TOOL_FOAM)
    expected = np.loadtxt(tmp_path / "s.csv", delimiter=",")
    got = fabsynth.foam.Foam(**FOAM).seeds(box)
    assert got.shape == expected.shape and np.allclose(got, expected, rtol=0, atol=1e-12)
    # density 0.2 seeds/mm^3 in 648 mm^3: about 130 seeds (Poisson, sd ~11)
    assert 80 < len(got) < 180


def test_graded_and_elasticity_foams_follow_their_field():
    ramp = fabsynth.foam.Foam(density_x=(0.05, 1.0, 0, 30), radius=0.25, cell=3, seed=2)
    box_lo, box_hi = ramp.seeds((0, 0, 0, 6, 30, 30)), ramp.seeds((24, 0, 0, 30, 30, 30))
    assert len(box_hi) > 5 * len(box_lo)
    e = np.array([0.01, 0.02, 0.04])
    rho = fabsynth.foam.density_for_elasticity(e, 0.25)
    assert np.all(np.diff(rho) > 0)
    assert np.allclose(fabsynth.foam.elasticity(rho, 0.25), e, rtol=1e-9)  # the inverse of the shipped fit
    lo, hi = fabsynth.foam.reachable_elasticity(0.25)
    assert lo < 0.01 and hi > 0.04
    stiff = fabsynth.foam.Foam(density=0.04, radius=0.25, elasticity=True, seed=1, cell=3)
    assert stiff.seeds((0, 0, 0, 20, 20, 20)).shape[0] == pytest.approx(8000 * rho[2], rel=0.15)


def test_slices_iterate_like_single_slices_and_pickle():
    f = fabsynth.foam.Foam(**FOAM)
    region = (0, 0, 12, 8)
    zs = np.linspace(0.5, 6, 20)
    stack = list(f.slices(zs, region, 0.1))
    assert len(stack) == 20 and stack[0].shape == (80, 120) and stack[0].dtype == np.uint8
    for z, img in zip(zs, stack):
        assert np.array_equal(img, f.slice(z, region, 0.1))
    g = pickle.loads(pickle.dumps(f))
    assert g.params == f.params and np.array_equal(g.slice(3, region, 0.1), f.slice(3, region, 0.1))
    grey = f.slice(3, region, 0.1, supersample=4)
    assert len(np.unique(grey)) > 2  # grey levels on the beams' borders
    with pytest.raises(ValueError, match="increase"):
        list(f.slices([2, 1], region, 0.1))


def test_mesh_foam_stack_equals_foam_slicer_slice(tmp_path, tool, data):
    V, F = fabsynth.io.read_mesh(data / "meshes" / "icosphere.obj")
    V = V * 8.0  # a closed sphere of radius 8 mm (a power of two: exact)
    fabsynth.io.write_mesh(tmp_path / "sphere.obj", V, F)  # exact decimals
    tool("foam_slicer", "slice", tmp_path / "sphere.obj", "--out-dir", tmp_path / "tool", "--pixel", 0.2, "--slices", 5, *TOOL_FOAM)
    obj = fabsynth.foam.MeshFoam(fabsynth.foam.Foam(**FOAM), V, F, frame=0.5)
    plan = obj.plan(0.2, count=5)
    manifest = fabsynth.distributed.write_stack(obj, plan, tmp_path / "py")
    assert manifest["count"] == 5
    for s in manifest["slices"]:
        assert (tmp_path / "py" / s["file"]).read_bytes() == (tmp_path / "tool" / s["file"]).read_bytes()
    # the frame closes every section: the middle slice's solid pixels include a ring at the mesh
    mid = fabsynth.io.read_png(tmp_path / "py" / manifest["slices"][2]["file"])
    assert 0.05 < (mid == 255).mean() < 0.6
    pts = np.array([[0, 0, 7.9], [0, 0, 8.1], [100, 100, 100]])  # in the frame, just outside, far away
    assert list(obj.contains(pts)) == [True, False, False]
    assert np.array_equal(obj.slice(manifest["slices"][2]["z_mm"], plan["region"], plan["pixel"]), mid)
    cut = fabsynth.foam.MeshFoam(obj.foam, V, F, frame=0.5, cuts=[((0, 0, 0), (0, 0, 2))])  # keeps z <= 0
    assert cut.cuts == [((0, 0, 0), (0, 0, 1))]  # normals are unit vectors
    assert not cut.slice(4.0, plan["region"], 0.2).any() and cut.slice(-4.0, plan["region"], 0.2).any()
    twin = pickle.loads(pickle.dumps(obj))
    assert np.array_equal(next(twin.layers(plan, [plan["selected"][2]])), mid)


def test_foam_options_are_checked():
    with pytest.raises(ValueError, match="radius"):
        fabsynth.foam.Foam(radius=5, cell=2)
    with pytest.raises(ValueError, match="density_x"):
        fabsynth.foam.Foam(density_x=(0.1, 0.2, 3))
    with pytest.raises(ValueError, match="x0 < x1"):
        fabsynth.foam.Foam().seeds((0, 0, 0, -1, 1, 1))
    with pytest.raises(ValueError, match="supersample"):
        fabsynth.foam.Foam().slice(0, (0, 0, 1, 1), 0.1, supersample=0)


def test_beams_are_the_foam_edges_in_the_box():
    f = fabsynth.foam.Foam(**FOAM)
    net = f.beams((0, 0, 0, 6, 6, 6))
    nodes, edges, radii = net["nodes"], net["edges"], net["radii"]
    assert len(edges) > 50 and edges.shape[1] == 2 and edges.max() < len(nodes)
    assert np.all(radii == 0.25)
    assert np.all(nodes >= -1e-9) and np.all(nodes <= 6 + 1e-9)
    # a beam's axis is solid: its midpoint is inside the foam
    mid = 0.5 * (nodes[edges[:, 0]] + nodes[edges[:, 1]])
    assert f.contains(mid).all()


def test_plan_follows_foam_slicer_layers():
    p = fabsynth.foam.plan((0, 0, 1, 10, 10, 3), 0.5, count=2)
    assert p["region"] == (-0.5, -0.5, 10.5, 10.5) and p["layers"] == 4 and p["selected"] == [1, 3] and p["z0"] == 1
    assert fabsynth.foam.plan((0, 0, 0, 1, 1, 1), 0.1, layer=0.25)["selected"] == [0, 1, 2, 3]
    with pytest.raises(ValueError, match="only 4 layers"):
        fabsynth.foam.plan((0, 0, 1, 10, 10, 3), 0.5, count=5)
