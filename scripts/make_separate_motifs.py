#!/usr/bin/env python3
"""Writes data/vector/disks.svg and data/vector/leaves.svg: bands of separate motifs (no connection
between them), the case of issue 18 item 1. Conventions of data/README.md (vector/): one path per
component, absolute M/L/Z only, outer rings of positive shoelace area in SVG user units, periodic in
x with the band's width a multiple of the period; each band is cut at x = 0 and x = width through
empty space, so its ends carry half the gap between motifs. Deterministic; run from the repository
root."""
import math


def ring_path(points):
    area = sum(points[i][0] * points[(i + 1) % len(points)][1] - points[(i + 1) % len(points)][0] * points[i][1]
               for i in range(len(points)))
    if area < 0:
        points = points[::-1]
    return "M " + " L ".join(f"{x:.3f} {y:.3f}" for x, y in points) + " Z"


def write(path, title, desc, width, height, rings):
    with open(path, "w") as f:
        f.write('<?xml version="1.0" encoding="UTF-8"?>\n')
        f.write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}">\n')
        f.write(f"  <title>{title}</title>\n  <desc>{desc}</desc>\n")
        for r in rings:
            f.write(f'  <path fill="#000000" fill-rule="evenodd" stroke="none" d="{ring_path(r)}"/>\n')
        f.write("</svg>\n")


# 8 disks of diameter 60 (the band height) at a pitch of 125: gaps of 65, half a gap at each end.
disks = []
for i in range(8):
    cx, cy, r = 62.5 + 125 * i, 30.0, 30.0
    disks.append([(cx + r * math.cos(2 * math.pi * k / 128), cy + r * math.sin(2 * math.pi * k / 128)) for k in range(128)])
write("data/vector/disks.svg", "disks", "Separate equal disks, diameter 60 = band height, pitch 125; "
      "periodic in x with period 125; 8 component(s), 0 hole(s). Generated.", 1000, 60, disks)

# 10 pointed leaves (lens shapes, 56 long and 20 wide), tilted +-30 degrees and alternately raised and
# lowered by 8, at a pitch of 80 (period 160: two leaves).
leaves = []
for i in range(10):
    cx, cy = 40 + 80 * i, 30.0 + (6.0 if i % 2 else -6.0)
    tilt = math.radians(30.0 if i % 2 else -30.0)
    a, b = 28.0, 10.0
    R = (a * a + b * b) / (2 * b)  # radius of the two arcs through the tips
    pts = []
    for sign in (1, -1):  # upper arc tip to tip, then the lower arc back
        for k in range(64):
            x = -a + 2 * a * k / 64 if sign > 0 else a - 2 * a * k / 64
            y = sign * (math.sqrt(max(R * R - x * x, 0.0)) - (R - b))
            pts.append((cx + x * math.cos(tilt) - y * math.sin(tilt), cy + x * math.sin(tilt) + y * math.cos(tilt)))
    leaves.append(pts)
write("data/vector/leaves.svg", "leaves", "Separate pointed leaves without a stem, tilted +-30 degrees and "
      "alternately raised and lowered, pitch 80; periodic in x with period 160; 10 component(s), 0 hole(s). "
      "Generated.", 800, 60, leaves)
