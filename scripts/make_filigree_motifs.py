#!/usr/bin/env python3
"""Writes data/filigree/scroll_curls.svg, flower.svg and leaf_spray.svg: three elements drawn for this
project after the kinds of motif filigree jewellery uses (issue 33 item 6: a scroll with side curls,
a flower, a leaf spray). Conventions of data/README.md (filigree/): open polylines only, one
<polyline> per curve, the viewBox the bounding box plus a margin of 2 units; where a curve branches
it is split at the junction so that the pieces share that end point exactly (the element reader
welds shared end points only). Stroke widths are part of the drawing: main strokes wider than the
curls and veins, in proportion to the element, so a run without --width uses them.

The curls are Euler-type spirals: the curvature grows with arc length (as kappa(s) = kappa1 (s/L)^p),
so a stroke leaves a body straight and winds into a tightening curl, the shape of a wire scroll;
with p < 1 the inner turn stays open wider than a strip. Deterministic; run from the repository root.
"""
import math

STEP = 0.25  # sampling step along every curve, in drawing units


def curl(p, heading, length, turns, left=True, power=0.7):
    """Points of a curl starting at p in direction `heading` (radians), `length` long, turning
    `turns` full turns in all, to the left (counter-clockwise in y-up axes) or right."""
    total = 2 * math.pi * turns
    # integral of kappa1 (s/L)^p over [0, L] = kappa1 L / (p + 1) = total
    k1 = total * (power + 1) / length
    n = max(2, int(length / STEP))
    pts = [p]
    x, y, th = p[0], p[1], heading
    ds = length / n
    sign = 1 if left else -1
    for i in range(n):
        s = (i + 0.5) * ds
        th_mid = th + sign * 0.5 * ds * k1 * (s / length) ** power
        x += ds * math.cos(th_mid)
        y += ds * math.sin(th_mid)
        th += sign * ds * k1 * (s / length) ** power
        pts.append((x, y))
    return pts


def bezier(p0, p1, p2, p3, n=None):
    if n is None:
        chord = math.dist(p0, p1) + math.dist(p1, p2) + math.dist(p2, p3)
        n = max(4, int(chord / STEP))
    out = []
    for i in range(n + 1):
        t = i / n
        a, b, c, d = (1 - t) ** 3, 3 * t * (1 - t) ** 2, 3 * t * t * (1 - t), t ** 3
        out.append((a * p0[0] + b * p1[0] + c * p2[0] + d * p3[0], a * p0[1] + b * p1[1] + c * p2[1] + d * p3[1]))
    return out


def split_at(pts, fractions):
    """Splits a polyline at the given arc-length fractions; returns the pieces (sharing end points)."""
    cum = [0.0]
    for a, b in zip(pts, pts[1:]):
        cum.append(cum[-1] + math.dist(a, b))
    cuts = sorted(min(range(len(pts)), key=lambda i: abs(cum[i] - f * cum[-1])) for f in fractions)
    pieces, start = [], 0
    for c in cuts:
        pieces.append(pts[start:c + 1])
        start = c
    pieces.append(pts[start:])
    return pieces, [pts[c] for c in cuts]


def heading_at(pts, i):
    a, b = pts[max(0, i - 2)], pts[min(len(pts) - 1, i + 2)]
    return math.atan2(b[1] - a[1], b[0] - a[0])


def mirror_x(pts, x0):
    return [(2 * x0 - x, y) for x, y in pts]


def write(path, title, desc, strokes):
    """strokes: list of (points, width). Writes with y down (SVG), the drawing having been made y up."""
    xs = [x for pts, _ in strokes for x, _ in pts]
    ys = [y for pts, _ in strokes for _, y in pts]
    lo_x, hi_x, lo_y, hi_y = min(xs), max(xs), min(ys), max(ys)
    w, h = hi_x - lo_x + 4, hi_y - lo_y + 4
    with open(path, "w") as f:
        f.write('<?xml version="1.0" encoding="UTF-8"?>\n')
        f.write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.3f}" height="{h:.3f}" viewBox="0 0 {w:.3f} {h:.3f}">\n')
        f.write(f"  <title>{title}</title>\n  <desc>{desc} {len(strokes)} open polyline(s). Generated.</desc>\n")
        for pts, width in strokes:
            coords = " ".join(f"{x - lo_x + 2:.3f},{hi_y - y + 2:.3f}" for x, y in pts)
            f.write(f'  <polyline fill="none" stroke="#000000" stroke-width="{width:g}" points="{coords}"/>\n')
        f.write("</svg>\n")


# --- scroll with side curls: a C-scroll (an arch whose ends wind inward into volutes) with two
# tendrils that leave the top of the arch and curl outward, as on an acanthus scroll.
def scroll_curls():
    main_w, curl_w = 1.6, 1.2
    # right half of the arch: from the apex (0, 14) going right and down, then the volute winding in
    arch = bezier((0, 14), (8, 14), (15, 11), (16.5, 4))
    vol = curl(arch[-1], heading_at(arch, len(arch) - 1), 30, 1.15, left=False, power=0.6)
    right = arch + vol[1:]
    left = mirror_x(right, 0)[::-1]
    body = left[:-1] + right
    pieces, joints = split_at(body, [0.33, 0.67])
    strokes = [(p, main_w) for p in pieces]
    # tendrils: leave each joint upward and outward, curl back toward the apex side
    for j, (x, y) in enumerate(joints):
        outward = 1 if x > 0 else -1
        hd = math.atan2(1.0, 0.55 * outward)  # up and outward
        t = curl((x, y), hd, 15, 0.95, left=(outward < 0), power=0.8)
        strokes.append((t, curl_w))
    return strokes


# --- flower: five teardrop petals on a ring around a small centre curl (the curl touches the ring
# from inside at one point, so the element is one connected wire).
def flower():
    petal_w, ring_w = 1.4, 1.2
    n, r_ring, r_tip = 5, 4.0, 17.0
    strokes = []
    bases = []
    for k in range(n):
        a = math.pi / 2 + 2 * math.pi * k / n
        bases.append((r_ring * math.cos(a), r_ring * math.sin(a), a))
    # petals: two cubic arcs from the base point to the tip, bulging to either side
    for x, y, a in bases:
        tip = (r_tip * math.cos(a), r_tip * math.sin(a))
        for side in (-1, 1):
            b = a + side * 0.9  # leave the ring at an angle to the radial direction
            c1 = (x + 6.5 * math.cos(b), y + 6.5 * math.sin(b))
            c2 = (tip[0] - 5.5 * math.cos(a) + side * 3.2 * math.cos(a + math.pi / 2),
                  tip[1] - 5.5 * math.sin(a) + side * 3.2 * math.sin(a + math.pi / 2))
            strokes.append((bezier((x, y), c1, c2, tip), petal_w))
    # ring arcs between consecutive petal bases
    for k in range(n):
        a0 = bases[k][2]
        pts = [(r_ring * math.cos(a0 + t * 2 * math.pi / n / 24), r_ring * math.sin(a0 + t * 2 * math.pi / n / 24))
               for t in range(25)]
        strokes.append((pts, ring_w))
    # centre: a curl from the top base point winding inward (clockwise, against the ring's direction)
    x, y, a = bases[0]
    strokes.append((curl((x, y), a + math.pi + 0.9, 11, 1.0, left=False, power=0.6), ring_w))
    return strokes


# --- leaf spray: a curved stem ending in a curl at its base, with four leaves on alternate sides
# and a leaf at the tip; each leaf two arcs from its base on the stem to its point and a midrib.
def leaf_spray():
    stem_w, leaf_w, vein_w = 1.4, 1.2, 0.9
    stem = bezier((0, 0), (3, 10), (-2, 22), (5, 34))
    attach = [0.22, 0.42, 0.62, 0.80]
    pieces, joints = split_at(stem, attach)
    strokes = [(p, stem_w) for p in pieces]
    idx = [min(range(len(stem)), key=lambda i: math.dist(stem[i], j)) for j in joints]

    def leaf(base, direction, length, width):
        tip = (base[0] + length * math.cos(direction), base[1] + length * math.sin(direction))
        out = []
        for side in (-1, 1):
            # leave the stem at 1.1 rad to the leaf's axis, widest at about two thirds of its length
            c1 = (base[0] + 0.3 * length * math.cos(direction) + 0.9 * width * math.cos(direction + side * 1.1),
                  base[1] + 0.3 * length * math.sin(direction) + 0.9 * width * math.sin(direction + side * 1.1))
            c2 = (tip[0] - 0.35 * length * math.cos(direction) + side * width * math.cos(direction + math.pi / 2),
                  tip[1] - 0.35 * length * math.sin(direction) + side * width * math.sin(direction + math.pi / 2))
            out.append((bezier(base, c1, c2, tip), leaf_w))
        mid = bezier(base, (base[0] + 0.3 * length * math.cos(direction), base[1] + 0.3 * length * math.sin(direction)),
                     (tip[0] - 0.5 * length * math.cos(direction), tip[1] - 0.5 * length * math.sin(direction)), tip)
        out.append((mid[: int(len(mid) * 0.72)], vein_w))
        return out

    for k, (j, i) in enumerate(zip(joints, idx)):
        side = 1 if k % 2 == 0 else -1  # left, right, left, right
        hd = heading_at(stem, i) + side * 0.85
        strokes += leaf(j, hd, 9.5 - 0.8 * k, 2.6 - 0.15 * k)
    strokes += leaf(stem[-1], heading_at(stem, len(stem) - 1), 8.0, 2.2)
    # the stem's base winds into a curl
    strokes.append((curl(stem[0], heading_at(stem, 0) + math.pi, 16, 1.0, left=False, power=0.6), stem_w))
    return strokes


if __name__ == "__main__":
    write("data/filigree/scroll_curls.svg", "scroll_curls",
          "C-scroll with volutes at both ends and two side curls leaving the top of the arch.", scroll_curls())
    write("data/filigree/flower.svg", "flower",
          "Five teardrop petals on a ring around a centre curl.", flower())
    write("data/filigree/leaf_spray.svg", "leaf_spray",
          "Curved stem with four alternate leaves and a leaf at the tip, curled at its base.", leaf_spray())
