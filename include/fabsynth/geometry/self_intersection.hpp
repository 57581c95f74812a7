// SPDX-License-Identifier: MIT
#pragma once
/// @file self_intersection.hpp  Pairs of faces of a triangle mesh that intersect other than along
/// the edge or vertex they share: the check that a mesh meant for printing does not pass through
/// itself (after simplification, smoothing or any other vertex motion).
///
/// Usage:
///   auto r = fabsynth::find_self_intersections(mesh);
///   if (r.pairs) std::cerr << r.pairs << " intersecting face pairs, e.g. " << r.first[0] << "/" << r.first[1];
///
/// Definitions: two faces intersect improperly when
/// - they share no vertex and their closed triangles meet (touching counts);
/// - they share one vertex v and their intersection holds a point other than v;
/// - they share an edge and the two triangles are coplanar on the same side of it (a fold);
/// - they repeat the same three vertices.
/// Degenerate faces (repeated index) are skipped; mesh_topology.hpp counts them.
///
/// Predicates are exact on the vertices rounded to an integer grid of 2^-30 of the mesh's extent
/// (about 0.1 nm on a 100 mm part; orientation determinants in 128-bit integers): flat regions,
/// which decimation fills with large coplanar faces, are decided exactly, and only faces within a
/// grid step of touching can be misjudged. Written here because
/// the one Debian-packaged implementation (CGAL's Polygon Mesh Processing) is GPL and the core
/// target stays free of GPL-only code.
///
/// Broad phase: a uniform grid whose cell is twice the median face box side; each pair is tested
/// once, in the cell of the lowest corner of the overlap of their boxes. Time about linear in the
/// face count for surface meshes; parallel over grid rows, the result is independent of threads.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth {

/// Result of find_self_intersections.
struct self_intersection_report {
    std::size_t pairs = 0;                          ///< intersecting face pairs
    std::array<std::uint32_t, 2> first{0, 0};       ///< the lexicographically smallest pair (valid if pairs > 0)
    [[nodiscard]] bool any() const noexcept { return pairs > 0; }
};

namespace detail::selfx {

__extension__ typedef __int128 i128;  // GCC/Clang; __extension__ keeps -Wpedantic quiet
using ipoint = glm::vec<3, std::int64_t>;

inline int sgn(i128 x) { return (x > 0) - (x < 0); }
inline i128 orient(const ipoint& a, const ipoint& b, const ipoint& c, const ipoint& d) {
    const i128 bx = b.x - a.x, by = b.y - a.y, bz = b.z - a.z, cx = c.x - a.x, cy = c.y - a.y, cz = c.z - a.z,
               dx = d.x - a.x, dy = d.y - a.y, dz = d.z - a.z;
    return bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx) + bz * (cx * dy - cy * dx);
}
struct p2 {
    std::int64_t x, y;
};
inline i128 cross2(const p2& o, const p2& a, const p2& b) {
    return static_cast<i128>(a.x - o.x) * (b.y - o.y) - static_cast<i128>(a.y - o.y) * (b.x - o.x);
}
// The coordinate plane most parallel to the triangle abc: the axis to drop.
inline int dominant_axis(const ipoint& a, const ipoint& b, const ipoint& c) {
    const i128 ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z, vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
    const auto abs = [](i128 x) { return x < 0 ? -x : x; };
    const i128 nx = abs(uy * vz - uz * vy), ny = abs(uz * vx - ux * vz), nz = abs(ux * vy - uy * vx);
    return nx >= ny && nx >= nz ? 0 : (ny >= nz ? 1 : 2);
}
inline p2 drop(const ipoint& x, int axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    return {x[u], x[w]};
}

// Closed segment pq against closed triangle abc, all four in one plane.
inline bool coplanar_segment_triangle(const ipoint& p, const ipoint& q, const ipoint& a, const ipoint& b, const ipoint& c) {
    const int axis = dominant_axis(a, b, c);
    const p2 P0 = drop(p, axis), P1 = drop(q, axis), A = drop(a, axis), B = drop(b, axis), C = drop(c, axis);
    const int area = sgn(cross2(A, B, C));
    const auto inside = [&](const p2& x) {
        return sgn(cross2(A, B, x)) * area >= 0 && sgn(cross2(B, C, x)) * area >= 0 && sgn(cross2(C, A, x)) * area >= 0;
    };
    if (inside(P0) || inside(P1)) return true;
    const auto segs_meet = [&](const p2& s0, const p2& s1, const p2& t0, const p2& t1) {
        const int d0 = sgn(cross2(s0, s1, t0)), d1 = sgn(cross2(s0, s1, t1)), d2 = sgn(cross2(t0, t1, s0)), d3 = sgn(cross2(t0, t1, s1));
        if (d0 * d1 < 0 && d2 * d3 < 0) return true;
        const auto on = [](const p2& o, const p2& x, const p2& y, int d) {
            return d == 0 && std::min(o.x, x.x) <= y.x && y.x <= std::max(o.x, x.x) && std::min(o.y, x.y) <= y.y && y.y <= std::max(o.y, x.y);
        };
        return on(s0, s1, t0, d0) || on(s0, s1, t1, d1) || on(t0, t1, s0, d2) || on(t0, t1, s1, d3);
    };
    return segs_meet(P0, P1, A, B) || segs_meet(P0, P1, B, C) || segs_meet(P0, P1, C, A);
}

// Closed segment pq against closed triangle abc (exact on the integer grid).
inline bool segment_meets_triangle(const ipoint& p, const ipoint& q, const ipoint& a, const ipoint& b, const ipoint& c) {
    const int sp = sgn(orient(a, b, c, p)), sq = sgn(orient(a, b, c, q));
    if (sp != 0 && sp == sq) return false;
    if (sp == 0 && sq == 0) return coplanar_segment_triangle(p, q, a, b, c);
    const int s0 = sgn(orient(p, q, a, b)), s1 = sgn(orient(p, q, b, c)), s2 = sgn(orient(p, q, c, a));
    return (s0 <= 0 && s1 <= 0 && s2 <= 0) || (s0 >= 0 && s1 >= 0 && s2 >= 0);
}

// The improper-intersection test of the file comment for faces s and t with corners in V.
inline bool faces_intersect(const std::vector<ipoint>& V, const std::array<std::uint32_t, 3>& s, const std::array<std::uint32_t, 3>& t) {
    int shared = 0;
    for (auto x : s)
        for (auto y : t) shared += x == y;
    if (shared == 3) return true;
    if (shared == 0) {
        for (int i = 0; i < 3; ++i) {
            if (segment_meets_triangle(V[s[i]], V[s[(i + 1) % 3]], V[t[0]], V[t[1]], V[t[2]])) return true;
            if (segment_meets_triangle(V[t[i]], V[t[(i + 1) % 3]], V[s[0]], V[s[1]], V[s[2]])) return true;
        }
        return false;
    }
    const auto in = [](std::uint32_t x, const std::array<std::uint32_t, 3>& f) { return x == f[0] || x == f[1] || x == f[2]; };
    if (shared == 1) {
        // The intersection of two triangles sharing only v is a segment from v; it holds a point
        // other than v iff the edge opposite v of one face meets the other face.
        std::array<std::uint32_t, 2> so{}, to{};
        int ns = 0, nt = 0;
        for (auto x : s)
            if (!in(x, t)) so[static_cast<std::size_t>(ns++)] = x;
        for (auto x : t)
            if (!in(x, s)) to[static_cast<std::size_t>(nt++)] = x;
        return segment_meets_triangle(V[so[0]], V[so[1]], V[t[0]], V[t[1]], V[t[2]]) ||
               segment_meets_triangle(V[to[0]], V[to[1]], V[s[0]], V[s[1]], V[s[2]]);
    }
    // shared edge (a, b): a fold iff the opposite corners are coplanar on the same side
    std::uint32_t a = 0, b = 0, c = 0, d = 0;
    int k = 0;
    for (auto x : s) {
        if (in(x, t)) (k++ == 0 ? a : b) = x;
        else c = x;
    }
    for (auto x : t)
        if (!in(x, s)) d = x;
    if (orient(V[a], V[b], V[c], V[d]) != 0) return false;
    const int axis = dominant_axis(V[a], V[b], V[c]);
    const p2 A = drop(V[a], axis), B = drop(V[b], axis);
    return sgn(cross2(A, B, drop(V[c], axis))) * sgn(cross2(A, B, drop(V[d], axis))) > 0;
}

}  // namespace detail::selfx

/// Counts the improperly intersecting face pairs of m (see the file comment) and names the
/// smallest; `pairs` (optional) receives every pair (f < g), sorted. Throws invalid_input for
/// non-finite vertices or faces indexing missing vertices.
[[nodiscard]] inline self_intersection_report find_self_intersections(const triangle_mesh& m,
                                                                      std::vector<std::array<std::uint32_t, 2>>* pairs = nullptr) {
    if (pairs) pairs->clear();
    validate(m, "self-intersection input mesh");
    self_intersection_report out;
    const std::size_t F = m.faces.size();
    if (F < 2) return out;
    std::vector<box3> fb(F);
    std::vector<double> sides;
    sides.reserve(F);
    box3 all;
    for (std::size_t f = 0; f < F; ++f) {
        for (auto v : m.faces[f]) fb[f].extend(m.vertices[v]);
        all.extend(fb[f]);
        const vec3 s = fb[f].size();
        sides.push_back(std::max({s.x, s.y, s.z}));
    }
    std::nth_element(sides.begin(), sides.begin() + static_cast<std::ptrdiff_t>(F / 2), sides.end());
    const vec3 ext = all.size();
    double cell = std::max(2.0 * sides[F / 2], 1e-12 * std::max({ext.x, ext.y, ext.z, 1.0}));
    // at most about 8 F cells
    while ((std::floor(ext.x / cell) + 1) * (std::floor(ext.y / cell) + 1) * (std::floor(ext.z / cell) + 1) > 8.0 * static_cast<double>(F) + 64)
        cell *= 1.5;
    const auto dims = ivec3(glm::floor(ext / cell)) + 1;
    const auto cell_of = [&](const vec3& p) {
        return glm::clamp(ivec3(glm::floor((p - all.lo) / cell)), ivec3(0), dims - 1);
    };
    const auto index = [&](ivec3 c) { return (static_cast<std::size_t>(c.z) * static_cast<std::size_t>(dims.y) + static_cast<std::size_t>(c.y)) * static_cast<std::size_t>(dims.x) + static_cast<std::size_t>(c.x); };
    // counting sort of (cell, face) entries
    const std::size_t cells = static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z);
    std::vector<std::uint32_t> start(cells + 1, 0);
    const auto for_cells = [&](std::size_t f, auto&& fn) {
        const ivec3 lo = cell_of(fb[f].lo), hi = cell_of(fb[f].hi);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) fn(index({x, y, z}));
    };
    for (std::size_t f = 0; f < F; ++f)
        if (m.faces[f][0] != m.faces[f][1] && m.faces[f][1] != m.faces[f][2] && m.faces[f][0] != m.faces[f][2])
            for_cells(f, [&](std::size_t c) { ++start[c + 1]; });
    for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
    std::vector<std::uint32_t> entry(start[cells]), fill(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < F; ++f)
        if (m.faces[f][0] != m.faces[f][1] && m.faces[f][1] != m.faces[f][2] && m.faces[f][0] != m.faces[f][2])
            for_cells(f, [&](std::size_t c) { entry[fill[c]++] = static_cast<std::uint32_t>(f); });

    struct partial {
        std::size_t pairs = 0;
        std::array<std::uint32_t, 2> first{UINT32_MAX, UINT32_MAX};
        std::vector<std::array<std::uint32_t, 2>> list;  // filled only when asked for
    };
    // the integer grid of the predicates: coordinates in [0, 2^30] (see the file comment)
    const double grid = std::ldexp(1.0, 30) / std::max({ext.x, ext.y, ext.z, 1e-300});
    std::vector<detail::selfx::ipoint> V(m.vertices.size());
    for (std::size_t v = 0; v < V.size(); ++v)
        V[v] = detail::selfx::ipoint(glm::round((m.vertices[v] - all.lo) * grid));
    partial total = parallel_reduce(
        std::size_t{0}, cells, partial{},
        [&](std::size_t c) {
            partial p;
            for (std::uint32_t i = start[c]; i < start[c + 1]; ++i)
                for (std::uint32_t j = i + 1; j < start[c + 1]; ++j) {
                    std::uint32_t f = entry[i], g = entry[j];
                    if (f > g) std::swap(f, g);
                    if (!fb[f].intersects(fb[g])) continue;
                    // count the pair only in the cell of the lowest corner of the boxes' overlap
                    if (index(cell_of(glm::max(fb[f].lo, fb[g].lo))) != c) continue;
                    if (!detail::selfx::faces_intersect(V, m.faces[f], m.faces[g])) continue;
                    ++p.pairs;
                    p.first = std::min(p.first, std::array<std::uint32_t, 2>{f, g});
                    if (pairs) p.list.push_back({f, g});
                }
            return p;
        },
        [](partial a, const partial& b) {
            a.pairs += b.pairs;
            a.first = std::min(a.first, b.first);
            a.list.insert(a.list.end(), b.list.begin(), b.list.end());
            return a;
        },
        {.grain = 256});
    out.pairs = total.pairs;
    if (total.pairs) out.first = total.first;
    if (pairs) {
        *pairs = total.list;
        std::sort(pairs->begin(), pairs->end());
    }
    return out;
}

}  // namespace fabsynth
