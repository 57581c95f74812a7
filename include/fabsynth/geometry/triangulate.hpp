// SPDX-License-Identifier: MIT
#pragma once
/// @file triangulate.hpp  Triangulation of simple polygons with holes by ear clipping, holes
/// joined to the outer ring by bridges (D. Eberly, "Triangulation by ear clipping", 2002, §3-4).
///
/// Every vertex of every ring is kept and every ring edge is an edge of exactly one triangle; no
/// vertex is added. Triangles are returned counter-clockwise (positive signed area in the given
/// coordinates), whatever the orientation of the input rings.
///
/// Usage:
///   fabsynth::planar_triangulation t = fabsynth::triangulate(polygon);   // polygon_with_holes
///   for (auto [a, b, c] : t.triangles) draw(t.vertices[a], t.vertices[b], t.vertices[c]);
///
/// Algorithm. Holes are merged into the outer ring one at a time, rightmost hole first: from the
/// hole's rightmost vertex M a ray towards +x hits the nearest upward edge of the current ring;
/// the bridge goes to the hit edge's rightmost endpoint, or, if ring vertices lie in the triangle
/// spanned by M, the hit point and that endpoint, to the one of those seen at the smallest angle
/// from the ray (Eberly's visibility argument). The bridge is walked twice, so M and its partner
/// appear twice in the merged ring (a weakly simple polygon); a hole that touches the ring at a
/// vertex is joined at that vertex without a bridge. Ears are then clipped: a strictly
/// convex vertex whose triangle contains no other reflex or flat vertex (boundary included;
/// copies of the triangle's own corners made by bridges are ignored). Only initially reflex or
/// flat vertices can ever block an ear (clipping only makes angles smaller), so they are kept in
/// a uniform grid and each ear test looks only at the grid cells the triangle covers.
///
/// Cost: O(h n) for h holes plus O(n k) for the ears (k = reflex vertices per visited grid cell
/// range; about linear on typical outlines, O(n^2) worst case). Robust on the bundled exemplars
/// (thousands of vertices, up to 78 holes). Input requirement: rings simple (is_simple), holes
/// strictly inside the outer ring, no two rings crossing (what vector_pattern::exemplar and Clipper
/// produce). Throws invalid_input for rings with fewer than 3 points or non-finite points, and
/// solver_error if ear clipping gets stuck (input violating the requirement).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth {

/// A triangulated planar region: triangles index into vertices, counter-clockwise.
struct planar_triangulation {
    std::vector<vec2> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

namespace detail::ear {

struct node {
    vec2 p;
    std::uint32_t id;  // output vertex index
    std::uint32_t prev = 0, next = 0;
    bool removed = false;
};

class clipper {
public:
    explicit clipper(std::vector<node>& nodes) : n_(nodes) {}

    /// Appends ring `ids` (already oriented) as a circular list, returns its first node.
    std::uint32_t add_ring(const std::vector<vec2>& pts, std::uint32_t first_id, bool reverse) {
        const std::uint32_t base = static_cast<std::uint32_t>(n_.size());
        const std::size_t m = pts.size();
        for (std::size_t k = 0; k < m; ++k) {
            const std::size_t i = reverse ? (m - 1 - k) : k;
            n_.push_back({pts[i], first_id + static_cast<std::uint32_t>(i)});
        }
        for (std::size_t k = 0; k < m; ++k) {
            n_[base + k].next = base + static_cast<std::uint32_t>((k + 1) % m);
            n_[base + k].prev = base + static_cast<std::uint32_t>((k + m - 1) % m);
        }
        return base;
    }

    [[nodiscard]] double turn(std::uint32_t i) const { return orient2d(n_[n_[i].prev].p, n_[i].p, n_[n_[i].next].p); }

    /// True iff the segment from node i towards point q starts inside the polygon's interior
    /// wedge at i (interior on the left of a counter-clockwise ring).
    [[nodiscard]] bool locally_inside(std::uint32_t i, vec2 q) const {
        const vec2 a = n_[n_[i].prev].p, b = n_[i].p, c = n_[n_[i].next].p;
        if (orient2d(a, b, c) >= 0.0) return orient2d(a, b, q) >= 0.0 && orient2d(b, c, q) >= 0.0;
        return orient2d(a, b, q) >= 0.0 || orient2d(b, c, q) >= 0.0;
    }

    /// Joins the hole starting at node `hole` into the ring containing node `outer` (Eberly).
    void merge_hole(std::uint32_t outer, std::uint32_t hole) {
        if (merge_at_shared_vertex(outer, hole)) return;
        // M: rightmost hole vertex (largest x, then largest y: any rightmost vertex works).
        std::uint32_t m = hole;
        for (std::uint32_t i = n_[hole].next; i != hole; i = n_[i].next)
            if (n_[i].p.x > n_[m].p.x || (n_[i].p.x == n_[m].p.x && n_[i].p.y > n_[m].p.y)) m = i;
        const vec2 M = n_[m].p;
        // Nearest crossing of the ray M + t (1, 0), t >= 0, with an upward edge of the ring.
        double best_x = std::numeric_limits<double>::infinity();
        std::uint32_t hit = outer;
        bool found = false, hit_vertex = false;
        std::uint32_t i = outer;
        do {
            const std::uint32_t j = n_[i].next;
            const vec2 a = n_[i].p, b = n_[j].p;
            if (a.y <= M.y && M.y <= b.y && a.y < b.y) {
                const double x = a.x + (M.y - a.y) * (b.x - a.x) / (b.y - a.y);
                if (x >= M.x && x < best_x) {
                    best_x = x;
                    found = true;
                    if (x == a.x && M.y == a.y) hit = i, hit_vertex = true;
                    else if (x == b.x && M.y == b.y) hit = j, hit_vertex = true;
                    else hit = a.x > b.x ? i : j, hit_vertex = false;
                }
            }
            i = j;
        } while (i != outer);
        if (!found) throw solver_error("triangulate: a hole is not inside its outer ring (no bridge found)");
        std::uint32_t bridge = hit;
        if (!hit_vertex) {
            // Vertices inside triangle (M, I, P) may hide P; the one at the smallest angle from the
            // ray (then the nearest) is visible from M.
            const vec2 I{best_x, M.y}, P = n_[hit].p;
            double best_tan = std::numeric_limits<double>::infinity(), best_d = best_tan;
            i = outer;
            do {
                const vec2 q = n_[i].p;
                if (q.x >= M.x && q != P && point_in_triangle(M, I, P, q) && locally_inside(i, M)) {
                    const double tan = std::abs(q.y - M.y) / std::max(q.x - M.x, 1e-300);
                    const double d = glm::length(q - M);
                    if (tan < best_tan || (tan == best_tan && d < best_d)) best_tan = tan, best_d = d, bridge = i;
                }
                i = n_[i].next;
            } while (i != outer);
        }
        // Several nodes can sit at the bridge position (earlier bridges); take one whose wedge
        // contains the direction to M.
        if (!locally_inside(bridge, M)) {
            i = outer;
            do {
                if (n_[i].p == n_[bridge].p && locally_inside(i, M)) { bridge = i; break; }
                i = n_[i].next;
            } while (i != outer);
        }
        // Splice: ... bridge -> M -> (hole) -> M' -> bridge' -> next(bridge) ...
        const std::uint32_t m2 = static_cast<std::uint32_t>(n_.size());
        n_.push_back(n_[m]);
        const std::uint32_t b2 = static_cast<std::uint32_t>(n_.size());
        n_.push_back(n_[bridge]);
        const std::uint32_t bn = n_[bridge].next, mp = n_[m].prev;
        n_[bridge].next = m, n_[m].prev = bridge;
        n_[mp].next = m2, n_[m2].prev = mp;
        n_[m2].next = b2, n_[b2].prev = m2;
        n_[b2].next = bn, n_[bn].prev = b2;
    }

    /// A hole touching the ring at a vertex (Clipper output may do that) is joined there with no
    /// bridge: ... ov -> (hole after hv) ... -> hv -> next(ov) ..., the point visited twice.
    bool merge_at_shared_vertex(std::uint32_t outer, std::uint32_t hole) {
        std::map<std::pair<double, double>, std::uint32_t> hole_at;
        std::uint32_t i = hole;
        do hole_at.emplace(std::pair{n_[i].p.x, n_[i].p.y}, i), i = n_[i].next;
        while (i != hole);
        i = outer;
        do {
            const auto it = hole_at.find({n_[i].p.x, n_[i].p.y});
            if (it != hole_at.end()) {
                const std::uint32_t hv = it->second, h1 = n_[hv].next, hp = n_[hv].prev;
                // the hole's wedge at hv must open into the ring's interior wedge at i
                if (locally_inside(i, n_[h1].p) && locally_inside(i, n_[hp].p)) {
                    const std::uint32_t on = n_[i].next;
                    n_[i].next = h1, n_[h1].prev = i;
                    n_[hv].next = on, n_[on].prev = hv;
                    return true;
                }
            }
            i = n_[i].next;
        } while (i != outer);
        return false;
    }

    /// Closed triangle test for a counter-clockwise or clockwise triangle.
    static bool point_in_triangle(vec2 a, vec2 b, vec2 c, vec2 p) {
        if (orient2d(a, b, c) < 0.0) std::swap(b, c);
        return orient2d(a, b, p) >= 0.0 && orient2d(b, c, p) >= 0.0 && orient2d(c, a, p) >= 0.0;
    }

    /// Clips ears of the ring starting at `start` with `count` nodes, appending triangles.
    void clip(std::uint32_t start, std::size_t count, std::vector<std::array<std::uint32_t, 3>>& out) {
        if (count < 3) return;
        build_grid(start, count);
        std::uint32_t cur = start, stop = start;
        while (count > 3) {
            if (is_ear(cur)) {
                const node& c = n_[cur];
                out.push_back({n_[c.prev].id, c.id, n_[c.next].id});
                const std::uint32_t nx = c.next;
                remove(cur);
                --count;
                cur = stop = nx;
                continue;
            }
            cur = n_[cur].next;
            if (cur == stop) throw solver_error("triangulate: no ear found (rings are not simple, or cross each other)");
        }
        if (turn(cur) > 0.0) out.push_back({n_[n_[cur].prev].id, n_[cur].id, n_[n_[cur].next].id});
        else throw solver_error("triangulate: degenerate final triangle (rings are not simple)");
    }

private:
    void remove(std::uint32_t i) {
        n_[n_[i].prev].next = n_[i].next;
        n_[n_[i].next].prev = n_[i].prev;
        n_[i].removed = true;
    }

    void build_grid(std::uint32_t start, std::size_t count) {
        box2 b;
        std::uint32_t i = start;
        do b.extend(n_[i].p), i = n_[i].next;
        while (i != start);
        lo_ = b.lo;
        const vec2 size = glm::max(b.size(), vec2(1e-300));
        const double cells = std::max(1.0, std::sqrt(static_cast<double>(count)));
        cell_ = std::max(size.x, size.y) / cells;
        if (!(cell_ > 0.0)) cell_ = 1.0;
        nx_ = std::max(1, static_cast<int>(std::ceil(size.x / cell_)) + 1);
        ny_ = std::max(1, static_cast<int>(std::ceil(size.y / cell_)) + 1);
        cell_start_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_) + 1, 0);
        std::vector<std::uint32_t> blockers;
        i = start;
        do {
            if (turn(i) <= 0.0) blockers.push_back(i);
            i = n_[i].next;
        } while (i != start);
        for (std::uint32_t k : blockers) ++cell_start_[cell_of(n_[k].p) + 1];
        for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
        cell_items_.assign(blockers.size(), 0);
        std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
        for (std::uint32_t k : blockers) cell_items_[fill[cell_of(n_[k].p)]++] = k;
    }
    [[nodiscard]] int cx(double x) const { return std::clamp(static_cast<int>((x - lo_.x) / cell_), 0, nx_ - 1); }
    [[nodiscard]] int cy(double y) const { return std::clamp(static_cast<int>((y - lo_.y) / cell_), 0, ny_ - 1); }
    [[nodiscard]] std::size_t cell_of(vec2 p) const {
        return static_cast<std::size_t>(cy(p.y)) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(cx(p.x));
    }

    [[nodiscard]] bool is_ear(std::uint32_t i) const {
        const std::uint32_t ia = n_[i].prev, ic = n_[i].next;
        const vec2 a = n_[ia].p, b = n_[i].p, c = n_[ic].p;
        if (!(orient2d(a, b, c) > 0.0)) return false;
        const vec2 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
        const int x0 = cx(lo.x), x1 = cx(hi.x), y0 = cy(lo.y), y1 = cy(hi.y);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const std::size_t cell = static_cast<std::size_t>(y) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(x);
                for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
                    const std::uint32_t r = cell_items_[k];
                    if (n_[r].removed || r == ia || r == i || r == ic) continue;
                    const vec2 q = n_[r].p;
                    if (q == a || q == b || q == c) continue;
                    if (q.x < lo.x || q.x > hi.x || q.y < lo.y || q.y > hi.y) continue;
                    if (turn(r) > 0.0) continue;  // became convex: cannot block
                    if (point_in_triangle(a, b, c, q)) return false;
                }
            }
        return true;
    }

    std::vector<node>& n_;
    vec2 lo_{0, 0};
    double cell_ = 1.0;
    int nx_ = 1, ny_ = 1;
    std::vector<std::uint32_t> cell_start_, cell_items_;
};

inline void check_ring(const ring2& r, const char* what, std::size_t index) {
    if (r.size() < 3)
        throw invalid_input(std::string("triangulate: ") + what + " " + std::to_string(index) + " has fewer than 3 points");
    for (const vec2& p : r)
        if (!all_finite(p)) throw invalid_input(std::string("triangulate: ") + what + " " + std::to_string(index) + " has a non-finite point");
}

}  // namespace detail::ear

/// Appends the triangulation of `poly` to `out` (vertices: outer ring then holes, in input order).
inline void triangulate_into(const polygon_with_holes& poly, planar_triangulation& out) {
    detail::ear::check_ring(poly.outer, "outer ring", 0);
    for (std::size_t h = 0; h < poly.holes.size(); ++h) detail::ear::check_ring(poly.holes[h], "hole", h);
    const std::uint32_t base = static_cast<std::uint32_t>(out.vertices.size());
    std::vector<detail::ear::node> nodes;
    detail::ear::clipper ec(nodes);
    std::uint32_t id = base;
    const std::uint32_t outer = ec.add_ring(poly.outer, id, signed_area(poly.outer) < 0.0);
    id += static_cast<std::uint32_t>(poly.outer.size());
    out.vertices.insert(out.vertices.end(), poly.outer.begin(), poly.outer.end());
    std::vector<std::pair<double, std::uint32_t>> holes;  // (max x, first node)
    std::size_t count = 0;
    for (const ring2& h : poly.holes) {
        const std::uint32_t first = ec.add_ring(h, id, signed_area(h) > 0.0);
        id += static_cast<std::uint32_t>(h.size());
        out.vertices.insert(out.vertices.end(), h.begin(), h.end());
        double mx = -std::numeric_limits<double>::infinity();
        for (const vec2& p : h) mx = std::max(mx, p.x);
        holes.push_back({mx, first});
    }
    std::sort(holes.begin(), holes.end(), [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
    for (const auto& [mx, first] : holes) ec.merge_hole(outer, first);
    count = 0;  // bridges add two nodes, a hole joined at a shared vertex none
    std::uint32_t i = outer;
    do ++count, i = nodes[i].next;
    while (i != outer);
    ec.clip(outer, count, out.triangles);
}

/// Triangulation of one polygon with holes.
[[nodiscard]] inline planar_triangulation triangulate(const polygon_with_holes& poly) {
    planar_triangulation t;
    triangulate_into(poly, t);
    return t;
}

/// Triangulation of several polygons (vertex indices continue from one polygon to the next).
[[nodiscard]] inline planar_triangulation triangulate(const std::vector<polygon_with_holes>& polys) {
    planar_triangulation t;
    for (const polygon_with_holes& p : polys) triangulate_into(p, t);
    return t;
}

}  // namespace fabsynth
