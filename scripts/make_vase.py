#!/usr/bin/env python3
"""Writes data/meshes/vase.obj: an open vase (surface of revolution with a closed bottom), the
open base surface of the filigree main job (filigree-synthesis.md Table 3 uses a 5.4 k-vertex
vase). Profile r(z) = 20 + 9 sin(pi z / 70) mm for 0 <= z <= 90 mm, 72 segments around, rings
every 1.2 mm, the bottom a fan of rings; z is up. Also writes data/filigree/vase_halves.txt, one
label per face in the OBJ's face order (the filigree tool's --face-labels): 0 where the face's
centroid lies below z = 45 mm (the bottom and the lower half), 1 above. Deterministic; run from
the repository root."""
import math

AROUND, HEIGHT, DZ = 72, 90.0, 1.2


def radius(z):
    return 20.0 + 9.0 * math.sin(math.pi * z / 70.0)


rings = int(round(HEIGHT / DZ))
verts, faces = [], []
# bottom: concentric rings from the centre out to r(0)
BOTTOM_RINGS = 8
verts.append((0.0, 0.0, 0.0))
for k in range(1, BOTTOM_RINGS + 1):
    r = radius(0.0) * k / BOTTOM_RINGS
    for i in range(AROUND):
        a = 2 * math.pi * i / AROUND
        verts.append((r * math.cos(a), r * math.sin(a), 0.0))


def bid(k, i):  # bottom ring k >= 1
    return 1 + (k - 1) * AROUND + (i % AROUND)


for i in range(AROUND):  # faces seen from below are the outside: normals -z
    faces.append((0, bid(1, i + 1), bid(1, i)))
for k in range(1, BOTTOM_RINGS):
    for i in range(AROUND):
        faces.append((bid(k, i), bid(k + 1, i + 1), bid(k + 1, i)))
        faces.append((bid(k, i), bid(k, i + 1), bid(k + 1, i + 1)))
# wall: ring 0 is the bottom's outer ring
base = len(verts)


def wid(j, i):
    return bid(BOTTOM_RINGS, i) if j == 0 else base + (j - 1) * AROUND + (i % AROUND)


for j in range(1, rings + 1):
    z = j * DZ
    for i in range(AROUND):
        a = 2 * math.pi * i / AROUND
        verts.append((radius(z) * math.cos(a), radius(z) * math.sin(a), z))
for j in range(rings):
    for i in range(AROUND):  # outward normals
        faces.append((wid(j, i), wid(j, i + 1), wid(j + 1, i + 1)))
        faces.append((wid(j, i), wid(j + 1, i + 1), wid(j + 1, i)))
with open("data/meshes/vase.obj", "w") as f:
    f.write("# open vase, scripts/make_vase.py (generated, public domain)\n")
    for v in verts:
        f.write("v %.6f %.6f %.6f\n" % v)
    for t in faces:
        f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
with open("data/filigree/vase_halves.txt", "w") as f:
    for t in faces:
        f.write("%d\n" % (0 if sum(verts[k][2] for k in t) / 3 < 45.0 else 1))
print(len(verts), "vertices", len(faces), "faces")
