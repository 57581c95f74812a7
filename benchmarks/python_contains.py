#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The Python binding's overhead on Foam.contains for 10^6 points, against the C++ batch call.

Same foam, field type and points (bit for bit) as bench_foam's BM_FoamPointBatchRuntimeField (density 0.02 -> 0.4
seeds/mm^3 along x over 20 mm, tau 0.25 mm, cell 4 mm, seed 2016; 10^6 uniform points in a 40 mm cube, a
warm pass first):
    PYTHONPATH=build/release/python python3 benchmarks/python_contains.py build/release/benchmarks/bench_foam
prints the mean time of the calls through Python over at least 3 s (the statistic and minimum time of the
C++ benchmark, MinTime(3.0)) and the C++ figure of BM_FoamPointBatchRuntimeField/2 (2 threads).
"""
import json
import statistics
import subprocess
import sys
import time

import numpy as np

import fabsynth

foam = fabsynth.foam.Foam(density_x=(0.02, 0.4, 0, 20), radius=0.25, cell=4, seed=2016)
M = (1 << 64) - 1
GOLDEN = 0x9E3779B97F4A7C15


def mix64(z):  # core/rng.hpp's SplitMix64 finaliser, on uint64 arrays (wrapping arithmetic)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def cube_points(n):
    """bench_foam's cube_points(): counter_rng(17, 0), three uniform(0, 40) draws per point, the same bits."""
    h = int(mix64(np.array([(17 + GOLDEN) & M], np.uint64))[0])
    h = int(mix64(np.array([h ^ int(mix64(np.array([(0 + GOLDEN * 2) & M], np.uint64))[0])], np.uint64))[0])
    counters = np.arange(1, 3 * n + 1, dtype=np.uint64)
    with np.errstate(over="ignore"):
        bits = mix64(np.uint64(h) + np.uint64(GOLDEN) * counters)
    u = (bits >> np.uint64(11)).astype(np.float64) * 2.0**-53
    return (0 + 40 * u).reshape(n, 3)


points = cube_points(1_000_000)
# warm: each thread's cache fills with the blocks it visits over the first calls (1.5, 1.2, 0.5, 0.35 s here,
# then steady); Google Benchmark likewise discards its first, calibrating runs
for _ in range(5):
    foam.contains(points)
times = []
while sum(times) < 3.0:
    t0 = time.perf_counter()
    foam.contains(points)
    times.append(time.perf_counter() - t0)
py_ms = 1e3 * statistics.mean(times)
print(f"python Foam.contains, 10^6 points, {fabsynth.num_threads()} threads: mean {py_ms:.1f} ms over {len(times)} calls "
      f"(median {1e3 * statistics.median(times):.1f}, min {1e3 * min(times):.1f})")
if len(sys.argv) > 1:
    out = subprocess.run([sys.argv[1], "--benchmark_filter=BM_FoamPointBatchRuntimeField/2", "--benchmark_format=json"], check=True,
                         capture_output=True, text=True).stdout
    bench = json.loads(out)["benchmarks"][0]
    cpp_ms = bench["real_time"] if bench["time_unit"] == "ms" else bench["real_time"] / 1e6
    print(f"C++ BM_FoamPointBatchRuntimeField/2: {cpp_ms:.1f} ms; binding overhead {100 * (py_ms / cpp_ms - 1):+.1f}%")
