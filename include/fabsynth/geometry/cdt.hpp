// SPDX-License-Identifier: MIT
#pragma once
/// @file cdt.hpp  Constrained Delaunay triangulations of polygonal regions: an incremental
/// triangulation with neighbour links (Lawson flips, point insertion, edge and triangle splits,
/// point location by straight walks), the base of filigree/reconstruct.hpp's Ruppert refinement
/// and of the per-face triangulation in bake.hpp (filigree-synthesis.md §6.1, Fig. 11c).
///
/// Usage:
///   fabsynth::planar_triangulation t = fabsynth::triangulate(polys);   // ear clipping
///   fabsynth::planar_triangulation d = fabsynth::constrained_delaunay(t);
///
/// Method: any triangulation of a polygonal region becomes its constrained Delaunay triangulation
/// (CDT) by flipping every interior edge that is not locally Delaunay (Lawson; the flip algorithm
/// reaches the CDT from any triangulation of the domain, the outline edges being the constraints).
/// The in-circle test flips only on a violation well above rounding, so flips cannot cycle; the
/// result is Delaunay up to that margin. Written by hand: CGAL (GPL parts) and Triangle (non-free
/// licence) are the packaged CDTs; the core target stays free of both.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/triangulate.hpp"

namespace fabsynth {

namespace detail::cdt {

inline constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

/// Triangle: counter-clockwise vertices; nbr[i] is the triangle across edge (v[i+1], v[i+2])
/// (none on the outline).
struct triangle {
    std::array<std::uint32_t, 3> v;
    std::array<std::uint32_t, 3> nbr;
};

inline int next(int i) { return i == 2 ? 0 : i + 1; }
inline int prev(int i) { return i == 0 ? 2 : i - 1; }

/// > 0 iff d lies inside the circumcircle of the counter-clockwise triangle (a, b, c), by more than
/// a relative rounding margin (so that a flip and its reverse cannot both pass).
inline bool clearly_in_circle(vec2 a, vec2 b, vec2 c, vec2 d) {
    const vec2 p = a - d, q = b - d, r = c - d;
    const double p2 = glm::dot(p, p), q2 = glm::dot(q, q), r2 = glm::dot(r, r);
    const double t1 = p2 * (q.x * r.y - q.y * r.x), t2 = q2 * (r.x * p.y - r.y * p.x), t3 = r2 * (p.x * q.y - p.y * q.x);
    const double det = t1 + t2 + t3;
    const double mag = p2 * (std::abs(q.x * r.y) + std::abs(q.y * r.x)) + q2 * (std::abs(r.x * p.y) + std::abs(r.y * p.x)) +
                       r2 * (std::abs(p.x * q.y) + std::abs(p.y * q.x));
    return det > 1e-10 * mag;
}

/// Circumcentre of triangle (a, b, c).
inline vec2 circumcentre(vec2 a, vec2 b, vec2 c) {
    const vec2 B = b - a, C = c - a;
    const double d = 2.0 * (B.x * C.y - B.y * C.x);
    const double b2 = glm::dot(B, B), c2 = glm::dot(C, C);
    return a + vec2((C.y * b2 - B.y * c2) / d, (B.x * c2 - C.x * b2) / d);
}

/// Smallest angle of triangle (a, b, c) in radians.
inline double min_angle(vec2 a, vec2 b, vec2 c) {
    auto angle = [](vec2 o, vec2 p, vec2 q) {
        const vec2 u = p - o, w = q - o;
        return std::atan2(std::abs(u.x * w.y - u.y * w.x), glm::dot(u, w));
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

/// Where a point lies in the triangulation.
struct location {
    enum kind_t { inside, behind_boundary, not_found } kind = not_found;
    std::uint32_t tri = none;  ///< inside: the triangle; behind_boundary: the triangle whose edge blocks
    int edge = -1;             ///< behind_boundary: that edge
};

/// Incremental constrained Delaunay triangulation of a polygonal domain; every edge without a
/// neighbour is an outline segment (the only constraints).
class triangulation {
public:
    std::vector<vec2> pts;
    std::vector<triangle> tris;

    /// Adopts an edge-conforming triangulation (vertices at equal positions merged) and flips it
    /// to the CDT. Returns per input vertex its vertex in pts. Throws solver_error for a flat or
    /// clockwise triangle or an edge used by more than two triangles.
    std::vector<std::uint32_t> adopt(const planar_triangulation& t) {
        std::map<std::pair<double, double>, std::uint32_t> at;
        std::vector<std::uint32_t> id(t.vertices.size());
        for (std::size_t i = 0; i < t.vertices.size(); ++i) {
            const auto [it, fresh] = at.emplace(std::pair{t.vertices[i].x, t.vertices[i].y}, static_cast<std::uint32_t>(pts.size()));
            if (fresh) pts.push_back(t.vertices[i]);
            id[i] = it->second;
        }
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> half;  // directed edge -> triangle
        for (const auto& f : t.triangles) {
            const std::array<std::uint32_t, 3> v{id[f[0]], id[f[1]], id[f[2]]};
            if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;  // collapsed by the merge: zero area
            if (!(orient2d(pts[v[0]], pts[v[1]], pts[v[2]]) > 0.0)) throw solver_error("constrained Delaunay: a flat or clockwise input triangle");
            tris.push_back({v, {none, none, none}});
        }
        for (std::uint32_t k = 0; k < tris.size(); ++k)
            for (int i = 0; i < 3; ++i) {
                const std::pair<std::uint32_t, std::uint32_t> e{tris[k].v[next(i)], tris[k].v[prev(i)]};
                if (!half.emplace(e, k).second) throw solver_error("constrained Delaunay: a directed edge is used twice (overlapping rings)");
            }
        for (std::uint32_t k = 0; k < tris.size(); ++k)
            for (int i = 0; i < 3; ++i) {
                const auto it = half.find({tris[k].v[prev(i)], tris[k].v[next(i)]});
                if (it != half.end()) tris[k].nbr[i] = it->second;
            }
        std::vector<std::pair<std::uint32_t, int>> stack;
        for (std::uint32_t k = 0; k < tris.size(); ++k)
            for (int i = 0; i < 3; ++i)
                if (tris[k].nbr[i] != none && tris[k].nbr[i] > k) stack.push_back({k, i});
        legalize_edges(stack);
        return id;
    }

    /// Index of vertex x in triangle t.
    [[nodiscard]] int index_of(std::uint32_t t, std::uint32_t x) const {
        for (int i = 0; i < 3; ++i)
            if (tris[t].v[i] == x) return i;
        return -1;
    }
    [[nodiscard]] vec2 P(std::uint32_t t, int i) const { return pts[tris[t].v[i]]; }

    /// Straight walk from the centroid of `start` towards p (at most a few thousand steps).
    [[nodiscard]] location walk(std::uint32_t start, vec2 p) const {
        const vec2 q = (P(start, 0) + P(start, 1) + P(start, 2)) / 3.0;
        std::uint32_t t = start;
        for (std::size_t step = 0; step < tris.size() + 16; ++step) {  // a straight walk visits a triangle once
            int exit = -1, any = -1;
            for (int i = 0; i < 3; ++i) {
                const vec2 a = P(t, next(i)), b = P(t, prev(i));
                if (!(orient2d(a, b, p) < 0.0)) continue;
                any = i;
                const double oa = orient2d(q, p, a), ob = orient2d(q, p, b);
                if ((oa <= 0.0 && ob >= 0.0) || (oa >= 0.0 && ob <= 0.0)) exit = i;
            }
            if (any < 0) return {location::inside, t, -1};
            if (exit < 0) exit = any;
            if (tris[t].nbr[exit] == none) return {location::behind_boundary, t, exit};
            t = tris[t].nbr[exit];
        }
        return {};
    }

    /// Triangle containing p by a scan (for when a walk is blocked by a hole), or none.
    [[nodiscard]] std::uint32_t scan(vec2 p) const {
        for (std::uint32_t t = 0; t < tris.size(); ++t)
            if (orient2d(P(t, 0), P(t, 1), p) >= 0.0 && orient2d(P(t, 1), P(t, 2), p) >= 0.0 && orient2d(P(t, 2), P(t, 0), p) >= 0.0) return t;
        return none;
    }

    /// Inserts p inside triangle t (split into three, or the two triangles of the edge p lies on
    /// into four), then restores the CDT. Returns false (nothing inserted) if p is (nearly) on a
    /// vertex or on an outline segment.
    bool insert(std::uint32_t t, vec2 p) {
        std::array<double, 3> o{};
        int on = -1, zeros = 0;
        for (int i = 0; i < 3; ++i) {
            const vec2 a = P(t, next(i)), b = P(t, prev(i));
            o[i] = orient2d(a, b, p);
            if (std::abs(o[i]) <= 1e-9 * glm::dot(b - a, b - a)) on = i, ++zeros;
        }
        if (zeros > 1) return false;
        if (on >= 0) {
            if (tris[t].nbr[on] == none) return false;
            split_edge(t, on, p);
            return true;
        }
        if (o[0] < 0.0 || o[1] < 0.0 || o[2] < 0.0) return false;
        split_triangle(t, p);
        return true;
    }

    /// Splits outline segment `edge` of triangle t at its midpoint and restores the CDT.
    void split_segment(std::uint32_t t, int edge) { split_edge(t, edge, 0.5 * (P(t, next(edge)) + P(t, prev(edge)))); }

    /// Triangles created or changed since the last call (ids may repeat).
    std::vector<std::uint32_t> touched;

private:
    void set_back(std::uint32_t n, std::uint32_t from, std::uint32_t to) {
        if (n == none) return;
        for (std::uint32_t& x : tris[n].nbr)
            if (x == from) {
                x = to;
                return;
            }
    }
    std::uint32_t add(const triangle& t) {
        tris.push_back(t);
        touched.push_back(static_cast<std::uint32_t>(tris.size() - 1));
        return static_cast<std::uint32_t>(tris.size() - 1);
    }

    /// 1 -> 3 split; the new vertex is vertex 0 of the three triangles.
    void split_triangle(std::uint32_t t, vec2 p) {
        const std::uint32_t x = static_cast<std::uint32_t>(pts.size());
        pts.push_back(p);
        const auto [a, b, c] = tris[t].v;
        const auto [n_bc, n_ca, n_ab] = tris[t].nbr;
        const std::uint32_t t1 = static_cast<std::uint32_t>(tris.size()), t2 = t1 + 1;
        tris[t] = {{x, b, c}, {n_bc, t1, t2}};
        touched.push_back(t);
        add({{x, c, a}, {n_ca, t2, t}});
        add({{x, a, b}, {n_ab, t, t1}});
        set_back(n_ca, t, t1);
        set_back(n_ab, t, t2);
        std::vector<std::pair<std::uint32_t, int>> stack{{t, 0}, {t1, 0}, {t2, 0}};
        legalize_edges(stack);
    }

    /// Splits edge i of t (and its neighbour's, if any) at p; the new vertex is vertex 0 of the
    /// new triangles.
    void split_edge(std::uint32_t t, int i, vec2 p) {
        const std::uint32_t x = static_cast<std::uint32_t>(pts.size());
        pts.push_back(p);
        const std::uint32_t a = tris[t].v[i], b = tris[t].v[next(i)], c = tris[t].v[prev(i)];
        const std::uint32_t n_ca = tris[t].nbr[next(i)], n_ab = tris[t].nbr[prev(i)];
        const std::uint32_t u = tris[t].nbr[i];
        std::vector<std::pair<std::uint32_t, int>> stack;
        if (u == none) {
            const std::uint32_t tB = static_cast<std::uint32_t>(tris.size());
            tris[t] = {{x, a, b}, {n_ab, none, tB}};
            touched.push_back(t);
            add({{x, c, a}, {n_ca, t, none}});
            set_back(n_ca, t, tB);
            stack = {{t, 0}, {tB, 0}};
        } else {
            int j = 0;
            while (tris[u].nbr[j] != t) ++j;
            const std::uint32_t d = tris[u].v[j];
            const std::uint32_t n_bd = tris[u].nbr[next(j)], n_dc = tris[u].nbr[prev(j)];
            const std::uint32_t tB = static_cast<std::uint32_t>(tris.size()), uB = tB + 1;
            tris[t] = {{x, a, b}, {n_ab, uB, tB}};
            touched.push_back(t);
            add({{x, c, a}, {n_ca, t, u}});
            tris[u] = {{x, d, c}, {n_dc, tB, uB}};
            touched.push_back(u);
            add({{x, b, d}, {n_bd, u, t}});
            set_back(n_ca, t, tB);
            set_back(n_bd, u, uB);
            stack = {{t, 0}, {tB, 0}, {u, 0}, {uB, 0}};
        }
        legalize_edges(stack);
    }

    /// True iff edge i of t is interior and its neighbour's apex clearly violates the empty circle.
    [[nodiscard]] bool flippable(std::uint32_t t, int i) const {
        const std::uint32_t u = tris[t].nbr[i];
        if (u == none) return false;
        const int j = [&] {
            for (int k = 0; k < 3; ++k)
                if (tris[u].nbr[k] == t) return k;
            return -1;
        }();
        if (j < 0) return false;
        const vec2 a = P(t, i), b = P(t, next(i)), c = P(t, prev(i)), d = P(u, j);
        return clearly_in_circle(a, b, c, d) && orient2d(a, b, d) > 0.0 && orient2d(a, d, c) > 0.0;
    }

    /// Flips edge i of t: t = (a, b, c), neighbour u = (d, c, b) become t = (a, b, d), u = (a, d, c).
    void flip(std::uint32_t t, int i) {
        const std::uint32_t u = tris[t].nbr[i];
        int j = 0;
        while (tris[u].nbr[j] != t) ++j;
        const std::uint32_t a = tris[t].v[i], b = tris[t].v[next(i)], c = tris[t].v[prev(i)], d = tris[u].v[j];
        const std::uint32_t n_ca = tris[t].nbr[next(i)], n_ab = tris[t].nbr[prev(i)];
        const std::uint32_t n_bd = tris[u].nbr[next(j)], n_dc = tris[u].nbr[prev(j)];
        tris[t] = {{a, b, d}, {n_bd, u, n_ab}};
        tris[u] = {{a, d, c}, {n_dc, n_ca, t}};
        set_back(n_bd, u, t);
        set_back(n_ca, t, u);
        touched.push_back(t);
        touched.push_back(u);
    }

    /// Lawson: flips edges from the stack until every one popped is locally Delaunay; each flip
    /// pushes the four outer edges of its quadrilateral.
    void legalize_edges(std::vector<std::pair<std::uint32_t, int>>& stack) {
        while (!stack.empty()) {
            const auto [t, i] = stack.back();
            stack.pop_back();
            if (!flippable(t, i)) continue;
            const std::uint32_t u = tris[t].nbr[i];
            flip(t, i);
            // t = (a, b, d): outer edges opposite a (b-d) and d (a-b); u = (a, d, c): opposite a (d-c), d (c-a)
            stack.push_back({t, 0});
            stack.push_back({t, 2});
            stack.push_back({u, 0});
            stack.push_back({u, 1});
        }
    }
};

}  // namespace detail::cdt

/// The constrained Delaunay triangulation of the region a triangulation covers (its boundary
/// edges are the constraints), by Lawson flips (see the file comment). Vertices keep their
/// positions; vertices at the same position (rings touching at a point) become one.
/// @param t          counter-clockwise triangles over t.vertices (mm), e.g. from triangulate()
/// @param vertex_of  if given: per vertex of t, its vertex in the result
/// Throws solver_error for a flat or clockwise triangle or an edge in more than two triangles.
[[nodiscard]] inline planar_triangulation constrained_delaunay(const planar_triangulation& t, std::vector<std::uint32_t>* vertex_of = nullptr) {
    detail::cdt::triangulation T;
    std::vector<std::uint32_t> id = T.adopt(t);
    planar_triangulation out;
    out.vertices = std::move(T.pts);
    for (const detail::cdt::triangle& f : T.tris) out.triangles.push_back(f.v);
    if (vertex_of) *vertex_of = std::move(id);
    return out;
}

}  // namespace fabsynth
