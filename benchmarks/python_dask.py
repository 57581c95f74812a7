#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Slice-stack throughput of fabsynth.distributed.write_stack: one process, then 1 and 2 Dask workers.

A foam (density 0.2 seeds/mm^3, tau 0.25 mm, cell 3 mm, seed 1) in a sphere of radius 20 mm with a
0.5 mm frame, 96 layers of 802 x 802 pixels at 0.05 mm, PNGs written into a temporary directory:
    PYTHONPATH=build/release/python python3 benchmarks/python_dask.py
Workers run one thread each (fabsynth.set_num_threads(1) in every worker), so 2 workers use the two
cores as the one process does with its 2 threads.
"""
import tempfile
import time

import distributed

import fabsynth


def one_thread():
    fabsynth.set_num_threads(1)


def main():
    V, F = fabsynth.io.read_mesh(__import__("pathlib").Path(__file__).resolve().parents[1] / "data" / "meshes" / "icosphere.obj")
    obj = fabsynth.foam.MeshFoam(fabsynth.foam.Foam(density=0.2, radius=0.25, cell=3, seed=1), V * 20.0, F, frame=0.5)
    plan = obj.plan(0.05, count=96)

    def run(client):
        with tempfile.TemporaryDirectory() as d:
            t0 = time.perf_counter()
            m = fabsynth.distributed.write_stack(obj, plan, d, client=client, layers_per_task=8)
            t = time.perf_counter() - t0
        return t, m["width_px"] * m["height_px"] * m["count"] / 1e6

    t, mp = run(None)
    print(f"one process, {fabsynth.num_threads()} threads: {t:.2f} s, {mp / t:.2f} Mpixel/s ({mp:.1f} Mpixel)")
    for n in (1, 2):
        with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
                distributed.Client(cluster) as client:
            client.run(one_thread)
            run(client)  # warm: workers import the package and receive the object once
            t, mp = run(client)
            print(f"{n} Dask worker(s), 1 thread each: {t:.2f} s, {mp / t:.2f} Mpixel/s")


if __name__ == "__main__":
    main()
