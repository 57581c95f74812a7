#!/usr/bin/env python3
"""Writes data/meshes/egg_stand.obj: the lower part of an egg-shaped surface of revolution, open at
the top, a base to carve a band out of (the egg stand of topology-constrained-vector-patterns.md
Fig. 23). Meridian from the bottom pole by the angle t in [0, 0.62 pi]: z(t) = 28 (1 - cos t),
r(t) = 21 sin t (1 + 0.08 cos t) mm, so the bottom is slightly flatter than the top; 72 segments
around, rings about every 1.2 mm of meridian, the bottom pole a fan; z is up, outward normals.
Deterministic; run from the repository root."""
import math

AROUND, T_MAX, STEP = 72, 0.62 * math.pi, 1.2


def profile(t):
    return 21.0 * math.sin(t) * (1.0 + 0.08 * math.cos(t)), 28.0 * (1.0 - math.cos(t))


# ring angles: equal meridian arc steps of about STEP mm (measured on a fine polyline)
fine = [T_MAX * i / 20000 for i in range(20001)]
arc = [0.0]
for a, b in zip(fine, fine[1:]):
    (r0, z0), (r1, z1) = profile(a), profile(b)
    arc.append(arc[-1] + math.hypot(r1 - r0, z1 - z0))
rings = int(round(arc[-1] / STEP))
ts, k = [], 0
for j in range(1, rings + 1):
    want = arc[-1] * j / rings
    while arc[k + 1] < want:
        k += 1
    ts.append(fine[k] + (fine[k + 1] - fine[k]) * (want - arc[k]) / (arc[k + 1] - arc[k]))
verts, faces = [(0.0, 0.0, 0.0)], []
for t in ts:
    r, z = profile(t)
    for i in range(AROUND):
        a = 2 * math.pi * i / AROUND
        verts.append((r * math.cos(a), r * math.sin(a), z))


def vid(j, i):  # ring j >= 1
    return 1 + (j - 1) * AROUND + (i % AROUND)


for i in range(AROUND):  # the pole's fan, seen from below: normals -z
    faces.append((0, vid(1, i + 1), vid(1, i)))
for j in range(1, rings):
    for i in range(AROUND):  # outward normals
        faces.append((vid(j, i), vid(j, i + 1), vid(j + 1, i + 1)))
        faces.append((vid(j, i), vid(j + 1, i + 1), vid(j + 1, i)))
with open("data/meshes/egg_stand.obj", "w") as f:
    f.write("# open egg-shaped stand, scripts/make_egg_stand.py (generated, public domain)\n")
    for v in verts:
        f.write("v %.6f %.6f %.6f\n" % v)
    for t in faces:
        f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
print(len(verts), "vertices", len(faces), "faces")
