# SPDX-License-Identifier: MIT
import json

import pytest

import fabsynth

distributed = pytest.importorskip("distributed")


def test_two_dask_workers_write_the_bytes_of_one_process(tmp_path, data):
    V, F = fabsynth.io.read_mesh(data / "meshes" / "icosphere.obj")
    V = V * 8.0  # a closed sphere of radius 8 mm (a power of two: exact)
    obj = fabsynth.foam.MeshFoam(fabsynth.foam.Foam(density=0.2, radius=0.25, cell=3, seed=1), V, F, frame=0.5)
    plan = obj.plan(0.25, count=12)
    local = fabsynth.distributed.write_stack(obj, plan, tmp_path / "local")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        shared = fabsynth.distributed.write_stack(obj, plan, tmp_path / "dask", client=client, layers_per_task=3)
        workers = {w for w in client.run(lambda: 1)}
    assert len(workers) == 2
    assert shared == local and local["count"] == 12
    assert json.loads((tmp_path / "dask" / "slices.json").read_text()) == local
    for s in local["slices"]:
        assert (tmp_path / "dask" / s["file"]).read_bytes() == (tmp_path / "local" / s["file"]).read_bytes()
