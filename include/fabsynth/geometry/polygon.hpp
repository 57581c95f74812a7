// SPDX-License-Identifier: MIT
#pragma once
/// @file polygon.hpp  Planar rings and polygons with holes: area, orientation, point location,
/// simplicity, and grouping a set of nested rings into polygons with holes.
///
/// A ring is a closed polyline stored WITHOUT repeating its first point at the end: the edges are
/// (r[i], r[(i+1) % n]). Orientation follows the shoelace sign in the coordinates as given:
/// positive area = counter-clockwise in a y-up frame (which looks clockwise on screen in a y-down
/// frame such as SVG user space).
///
/// Usage:
///   fabsynth::ring2 sq{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
///   double a = fabsynth::signed_area(sq);                 // 1 (counter-clockwise)
///   bool in = fabsynth::point_in_ring(sq, {0.5, 0.5});    // true
///   double c = fabsynth::convex_intersection_area(sq, other_convex_ccw_ring);
///   auto polys = fabsynth::group_rings({outer, hole});    // outer with one hole
///
/// Predicates use plain double arithmetic (no exact arithmetic): results are exact for integer
/// coordinates below 2^26 and otherwise reliable unless points are within ~1e-15 relative of a
/// degenerate configuration.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth {

/// Closed ring of points, first point not repeated at the end (units: whatever the caller uses, mm
/// by convention).
using ring2 = std::vector<vec2>;

/// How overlapping rings decide "inside" (SVG / PostScript semantics).
enum class fill_rule {
    nonzero,  ///< inside where the winding number is not 0 (SVG default)
    evenodd   ///< inside where the winding number is odd
};

/// A polygon: one outer ring and the holes inside it. group_rings() and orient() produce outer
/// rings with positive signed area and holes with negative signed area.
struct polygon_with_holes {
    ring2 outer;
    std::vector<ring2> holes;
    friend bool operator==(const polygon_with_holes&, const polygon_with_holes&) = default;
};

/// Twice the signed area of triangle (a, b, c): > 0 if counter-clockwise (y up), 0 if collinear.
[[nodiscard]] inline double orient2d(vec2 a, vec2 b, vec2 c) noexcept {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/// Barycentric coordinates of p over the triangle (a, b, c), either orientation; the triangle
/// must have non-zero area (orient2d(a, b, c) != 0).
[[nodiscard]] inline vec3 barycentric(vec2 p, vec2 a, vec2 b, vec2 c) noexcept {
    const double area2 = orient2d(a, b, c);
    const double l1 = orient2d(p, b, c) / area2, l2 = orient2d(p, c, a) / area2;
    return {l1, l2, 1.0 - l1 - l2};
}

/// Signed area by the shoelace formula; positive = counter-clockwise in a y-up frame. Rings with
/// fewer than 3 points have area 0. Coordinates are taken relative to r[0] to limit cancellation.
[[nodiscard]] inline double signed_area(const ring2& r) noexcept {
    const std::size_t n = r.size();
    if (n < 3) return 0.0;
    double a = 0.0;
    for (std::size_t i = 1; i + 1 < n; ++i) a += orient2d(r[0], r[i], r[i + 1]);
    return 0.5 * a;
}

/// Area of a polygon with holes: |outer| - sum |hole| (independent of ring orientation).
[[nodiscard]] inline double area(const polygon_with_holes& p) noexcept {
    double a = std::abs(signed_area(p.outer));
    for (const ring2& h : p.holes) a -= std::abs(signed_area(h));
    return a;
}

/// Area (mm^2 for mm input) of the intersection of two convex counter-clockwise rings: a clipped
/// by every edge of b (Sutherland-Hodgman), then the shoelace formula. Written by hand because the
/// general boolean (geometry/clip.hpp, Clipper) costs an integer snap and allocations per call,
/// and this runs per candidate move in the filigree placement search. 0 if either ring has fewer
/// than 3 points.
[[nodiscard]] inline double convex_intersection_area(const ring2& a, const ring2& b) {
    if (a.size() < 3 || b.size() < 3) return 0.0;
    ring2 cur = a, next;
    for (std::size_t i = 0, n = b.size(); i < n && !cur.empty(); ++i) {
        const vec2 p = b[i], q = b[(i + 1) % n];
        next.clear();
        for (std::size_t k = 0, m = cur.size(); k < m; ++k) {
            const vec2 s = cur[k], e = cur[(k + 1) % m];
            const double ds = orient2d(p, q, s), de = orient2d(p, q, e);  // >= 0: inside (left of p->q)
            if (ds >= 0) next.push_back(s);
            if ((ds >= 0) != (de >= 0)) next.push_back(s + (ds / (ds - de)) * (e - s));
        }
        std::swap(cur, next);
    }
    return std::max(0.0, signed_area(cur));
}

/// Length of the closed ring (including the closing edge).
[[nodiscard]] inline double perimeter(const ring2& r) noexcept {
    double l = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) l += glm::length(r[(i + 1) % r.size()] - r[i]);
    return l;
}

/// Bounding box of the points (empty box for an empty ring).
[[nodiscard]] inline box2 bounding_box(const ring2& r) noexcept {
    box2 b;
    for (const vec2& p : r) b.extend(p);
    return b;
}

/// True iff the signed area is > 0 (counter-clockwise in a y-up frame).
[[nodiscard]] inline bool is_ccw(const ring2& r) noexcept { return signed_area(r) > 0.0; }

/// Reverses the ring in place if needed so that its signed area has the requested sign
/// (ccw = true: positive). The first point stays first. Degenerate (zero-area) rings are kept.
inline void orient(ring2& r, bool ccw) {
    const double a = signed_area(r);
    if ((ccw && a < 0.0) || (!ccw && a > 0.0)) std::reverse(r.begin() + 1, r.end());
}

/// Orients the outer ring counter-clockwise (positive area) and every hole clockwise.
inline void orient(polygon_with_holes& p) {
    orient(p.outer, true);
    for (ring2& h : p.holes) orient(h, false);
}

/// True iff p lies on the closed segment [a, b] (collinear and within its extent).
[[nodiscard]] inline bool on_segment(vec2 a, vec2 b, vec2 p) noexcept {
    return orient2d(a, b, p) == 0.0 && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
           std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
}

/// Winding number of the ring around p (number of counter-clockwise turns, y up; negative for
/// clockwise rings). Points exactly on the boundary give the value of one adjacent side; use
/// point_in_ring() for a boundary-inclusive test. O(n). Crossing rule after D. Sunday (2001),
/// "Inclusion of a point in a polygon": upward edges count +1 when p is strictly left of them.
[[nodiscard]] inline int winding_number(const ring2& r, vec2 p) noexcept {
    int w = 0;
    const std::size_t n = r.size();
    for (std::size_t i = 0; i < n; ++i) {
        const vec2 a = r[i], b = r[(i + 1) % n];
        if (a.y <= p.y) {
            if (b.y > p.y && orient2d(a, b, p) > 0.0) ++w;
        } else if (b.y <= p.y && orient2d(a, b, p) < 0.0) {
            --w;
        }
    }
    return w;
}

/// True iff p is inside the ring or on its boundary (either orientation; a self-intersecting
/// ring uses the even-odd rule). O(n).
[[nodiscard]] inline bool point_in_ring(const ring2& r, vec2 p) noexcept {
    const std::size_t n = r.size();
    if (n == 0) return false;
    for (std::size_t i = 0; i < n; ++i)
        if (on_segment(r[i], r[(i + 1) % n], p)) return true;
    return (winding_number(r, p) & 1) != 0;
}

/// True iff p is filled by the set of rings under `rule` (boundaries count as inside only through
/// the winding numbers, i.e. unspecified exactly on a boundary). O(total points).
[[nodiscard]] inline bool point_in_rings(const std::vector<ring2>& rings, vec2 p, fill_rule rule) noexcept {
    int w = 0;
    for (const ring2& r : rings) w += winding_number(r, p);
    return rule == fill_rule::nonzero ? w != 0 : (w & 1) != 0;
}

/// True iff p is inside the outer ring and not strictly inside any hole (boundaries are inside).
[[nodiscard]] inline bool point_in_polygon(const polygon_with_holes& poly, vec2 p) noexcept {
    if (!point_in_ring(poly.outer, p)) return false;
    for (const ring2& h : poly.holes) {
        if (!point_in_ring(h, p)) continue;
        bool on_boundary = false;
        for (std::size_t i = 0; i < h.size() && !on_boundary; ++i) on_boundary = on_segment(h[i], h[(i + 1) % h.size()], p);
        if (!on_boundary) return false;
    }
    return true;
}

namespace detail {
/// True iff closed segments [a,b] and [c,d] share at least one point.
[[nodiscard]] inline bool segments_intersect(vec2 a, vec2 b, vec2 c, vec2 d) noexcept {
    const double o1 = orient2d(a, b, c), o2 = orient2d(a, b, d), o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
    return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) || (o3 == 0 && on_segment(c, d, a)) ||
           (o4 == 0 && on_segment(c, d, b));
}

/// Calls test(i, j), i < j, for every pair of segments that come within one grid cell of each
/// other (a superset of the pairs that touch) until one returns true; returns whether one did.
/// Segments are bucketed in a uniform grid whose cell is the median segment length, coarsened to
/// at most ~4 cells per segment: O(n log n + sum over cells of k^2) for k segments per cell, so
/// linear for outlines whose segments do not crowd into a few cells. (An x-sweep, used before,
/// degenerates to O(n^2) on spirals and zigzags, whose segments all overlap in x.) A pair may be
/// tested more than once. Coordinates must be finite.
template <class Test>
[[nodiscard]] bool any_segment_pair(const std::vector<std::pair<vec2, vec2>>& segs, Test&& test) {
    if (segs.size() < 2) return false;
    vec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    std::vector<double> lengths;
    lengths.reserve(segs.size());
    for (const auto& [a, b] : segs) {
        lo = glm::min(lo, glm::min(a, b));
        hi = glm::max(hi, glm::max(a, b));
        lengths.push_back(glm::length(b - a));
    }
    const double w = hi.x - lo.x, h = hi.y - lo.y;
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
    double cell = lengths[lengths.size() / 2];
    if (!(cell > 0.0) || !std::isfinite(cell)) cell = std::max({w, h, 1.0});
    const double max_cells = 4.0 * static_cast<double>(segs.size()) + 16.0;
    while ((std::floor(w / cell) + 1.0) * (std::floor(h / cell) + 1.0) > max_cells) cell *= 1.5;
    const auto nx = static_cast<std::int64_t>(std::floor(w / cell)) + 1, ny = static_cast<std::int64_t>(std::floor(h / cell)) + 1;
    auto cell_of = [&](double v, double o, std::int64_t count) {
        return std::clamp(static_cast<std::int64_t>(std::floor((v - o) / cell)), std::int64_t{0}, count - 1);
    };
    // (cell, segment) entries: samples every half cell along the segment, each with its 3 x 3
    // block, so every cell the segment passes through is listed (each of its points is within a
    // quarter cell of a sample)
    std::vector<std::pair<std::int64_t, std::size_t>> entries;
    for (std::size_t k = 0; k < segs.size(); ++k) {
        const auto& [a, b] = segs[k];
        const double len = glm::length(b - a);
        const auto steps = static_cast<std::int64_t>(std::min(std::ceil(len / (0.5 * cell)), 4.0 * static_cast<double>(nx + ny)));
        const std::size_t first = entries.size();
        for (std::int64_t t = 0; t <= steps; ++t) {
            const vec2 q = steps ? a + (b - a) * (static_cast<double>(t) / static_cast<double>(steps)) : a;
            const std::int64_t ix = cell_of(q.x, lo.x, nx), iy = cell_of(q.y, lo.y, ny);
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dx = -1; dx <= 1; ++dx)
                    if (ix + dx >= 0 && ix + dx < nx && iy + dy >= 0 && iy + dy < ny) entries.emplace_back((iy + dy) * nx + ix + dx, k);
        }
        std::sort(entries.begin() + static_cast<std::ptrdiff_t>(first), entries.end());
        entries.erase(std::unique(entries.begin() + static_cast<std::ptrdiff_t>(first), entries.end()), entries.end());
    }
    std::sort(entries.begin(), entries.end());
    for (std::size_t g = 0; g < entries.size();) {
        std::size_t end = g;
        while (end < entries.size() && entries[end].first == entries[g].first) ++end;
        for (std::size_t i = g; i < end; ++i)
            for (std::size_t j = i + 1; j < end; ++j)
                if (test(entries[i].second, entries[j].second)) return true;
        g = end;
    }
    return false;
}
}  // namespace detail

/// True iff the ring is a simple closed curve: at least 3 points, no zero-length edge, adjacent
/// edges meet only at their shared vertex (no fold-back), non-adjacent edges do not touch.
/// Candidate pairs from detail::any_segment_pair's grid: near-linear unless edges crowd.
[[nodiscard]] inline bool is_simple(const ring2& r) {
    const std::size_t n = r.size();
    if (n < 3) return false;
    for (std::size_t i = 0; i < n; ++i)
        if (!all_finite(r[i]) || r[i] == r[(i + 1) % n]) return false;
    // Adjacent edges (a,b),(b,c) overlap iff they are collinear and fold back onto each other.
    for (std::size_t i = 0; i < n; ++i) {
        const vec2 a = r[i], b = r[(i + 1) % n], c = r[(i + 2) % n];
        if (orient2d(a, b, c) == 0.0 && glm::dot(b - a, c - b) < 0.0) return false;
    }
    std::vector<std::pair<vec2, vec2>> segs(n);
    for (std::size_t i = 0; i < n; ++i) segs[i] = {r[i], r[(i + 1) % n]};
    const bool touch = detail::any_segment_pair(segs, [&](std::size_t e, std::size_t f) {
        const std::size_t d = e > f ? e - f : f - e;
        if (d == 1 || d == n - 1) return false;  // adjacent: checked above
        return detail::segments_intersect(r[e], r[(e + 1) % n], r[f], r[(f + 1) % n]);
    });
    if (touch) return false;
    return true;
}

/// Groups non-crossing rings (e.g. the subpaths of an SVG path) into polygons with holes by
/// nesting depth: a ring inside an even number of other rings is an outer boundary, one inside an
/// odd number is a hole of the smallest ring enclosing it. This equals the even-odd fill of the
/// rings, and also the nonzero fill when outer rings and holes have opposite orientations (as in
/// the bundled data). Rings with fewer than 3 points or zero area are dropped. The result is
/// oriented by orient(polygon_with_holes&) and ordered by first appearance of its outer ring.
/// Throws invalid_input if a coordinate is not finite. O(R^2 * n) in the worst case, with
/// bounding-box pruning.
[[nodiscard]] inline std::vector<polygon_with_holes> group_rings(const std::vector<ring2>& rings) {
    std::vector<std::size_t> idx;
    std::vector<box2> boxes(rings.size());
    std::vector<double> areas(rings.size(), 0.0);
    for (std::size_t i = 0; i < rings.size(); ++i) {
        for (const vec2& p : rings[i])
            if (!all_finite(p)) throw invalid_input("group_rings: ring " + std::to_string(i) + " has a non-finite point");
        areas[i] = std::abs(signed_area(rings[i]));
        boxes[i] = bounding_box(rings[i]);
        if (rings[i].size() >= 3 && areas[i] > 0.0) idx.push_back(i);
    }
    // A point of ring i that is not on ring j decides containment for non-crossing rings; the
    // first vertex can lie on j when rings touch, so look for a vertex strictly off j's boundary.
    auto inside = [&](std::size_t i, std::size_t j) {
        if (areas[j] <= areas[i] || !boxes[j].contains(boxes[i].lo) || !boxes[j].contains(boxes[i].hi)) return false;
        const ring2& rj = rings[j];
        for (const vec2& p : rings[i]) {
            bool on = false;
            for (std::size_t k = 0; k < rj.size() && !on; ++k) on = on_segment(rj[k], rj[(k + 1) % rj.size()], p);
            if (!on) return (winding_number(rj, p) & 1) != 0;
        }
        return false;  // every vertex on j's boundary: treat as not nested
    };
    std::vector<int> depth(rings.size(), 0);
    std::vector<std::size_t> parent(rings.size(), rings.size());
    for (std::size_t i : idx)
        for (std::size_t j : idx)
            if (i != j && inside(i, j)) {
                ++depth[i];
                if (parent[i] == rings.size() || areas[j] < areas[parent[i]]) parent[i] = j;
            }
    std::vector<polygon_with_holes> out;
    std::vector<std::size_t> slot(rings.size(), rings.size());
    for (std::size_t i : idx)
        if (depth[i] % 2 == 0) slot[i] = out.size(), out.push_back({rings[i], {}});
    for (std::size_t i : idx)
        if (depth[i] % 2 == 1) out[slot[parent[i]]].holes.push_back(rings[i]);
    for (polygon_with_holes& p : out) orient(p);
    return out;
}

}  // namespace fabsynth
