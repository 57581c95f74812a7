// SPDX-License-Identifier: MIT
#pragma once
/// @file extrude.hpp  Closed, outward-oriented triangle meshes from planar triangulations: straight
/// extrusion, and the extrusion of a band pattern along a curve computed in the curve's parameter
/// domain (Zhou et al. 2014, §6.3 "Generating the final mesh").
///
/// extrude(t, thickness): the triangles become the top (z = thickness) and, reversed, the bottom
/// (z = 0); every boundary edge of the triangulation (a directed edge whose reverse is not used)
/// gets a wall of two triangles. The result is watertight (every edge in exactly two faces,
/// traversed in opposite directions) when the triangulation is edge-conforming, and its normals
/// point outwards when the triangles are counter-clockwise; volume = area * thickness.
///
/// extrude_along_curve(polys, curve, opt), the paper's §6.3: the pattern's polygons are
/// triangulated in (u, v) (geometry/triangulate.hpp), the triangles cut by the lines u = k max_du
/// (conforming), and only then are the vertices mapped by
/// the band map (u, v) -> C(u) + v n(u) (geometry/curve.hpp). Tessellating in the parameter domain
/// keeps the triangulation valid where the mapped outline is tightly curved. For closed curves the
/// seam is welded: the vertices of the cut at u = L are identified with those of the cut at u = 0
/// (the cuts are first made conforming by inserting each side's seam vertices into the other
/// side's seam edges), so the seam edges become interior edges and the mesh stays watertight
/// (the paper's "circular band" for closed curves).
///
/// extrude_along_space_curve(polys, curve, opt): the same along a curve in space
/// (geometry/space_curve.hpp), the thickness along the frame's binormal.
///
/// weld_to_float(mesh) merges vertices that coincide in single precision (what binary STL keeps).
///
/// Usage:
///   auto t = fabsynth::triangulate(polys);
///   fabsynth::triangle_mesh slab = fabsynth::extrude(t, 2.0);
///   fabsynth::triangle_mesh band = fabsynth::extrude_along_curve(band_polys, curve, {.thickness = 2.0});
///
/// Errors: invalid_input for a thickness that is not finite and > 0, a triangulation that uses a
/// directed edge twice (overlapping or badly oriented triangles), pattern vertices outside
/// u in [0, L], a band that folds (planar_curve::check_band), a closed pattern whose two cuts do
/// not match, and non-finite coordinates.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/compiler.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/curve.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/segment.hpp"
#include "fabsynth/geometry/space_curve.hpp"
#include "fabsynth/geometry/triangulate.hpp"

namespace fabsynth {

/// Extrudes triangles (indices into t.vertices, counter-clockwise) to a closed slab between
/// z = 0 and z = thickness. Unreferenced vertices are dropped. O(F log F).
[[nodiscard]] inline triangle_mesh extrude(const planar_triangulation& t, double thickness) {
    require_positive(thickness, "extrude: thickness");
    std::vector<std::uint32_t> remap(t.vertices.size(), std::numeric_limits<std::uint32_t>::max());
    std::vector<vec2> used;
    for (const auto& tri : t.triangles)
        for (std::uint32_t v : tri) {
            if (v >= t.vertices.size()) throw invalid_input("extrude: triangle uses missing vertex " + std::to_string(v));
            if (remap[v] == std::numeric_limits<std::uint32_t>::max()) {
                if (!all_finite(t.vertices[v])) throw invalid_input("extrude: vertex " + std::to_string(v) + " is not finite");
                remap[v] = static_cast<std::uint32_t>(used.size());
                used.push_back(t.vertices[v]);
            }
        }
    const std::uint32_t n = static_cast<std::uint32_t>(used.size());
    triangle_mesh m;
    m.vertices.reserve(2 * used.size());
    for (const vec2& p : used) m.vertices.push_back({p.x, p.y, 0.0});
    for (const vec2& p : used) m.vertices.push_back({p.x, p.y, thickness});
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& tri : t.triangles) {
        const std::uint32_t a = remap[tri[0]], b = remap[tri[1]], c = remap[tri[2]];
        if (a == b || b == c || a == c) throw invalid_input("extrude: a triangle repeats a vertex");
        for (auto e : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
            if (++directed[e] > 1)
                throw invalid_input("extrude: the directed edge " + std::to_string(e.first) + "-" + std::to_string(e.second) +
                                    " is used twice (overlapping or inconsistently oriented triangles)");
        m.faces.push_back({a + n, b + n, c + n});  // top, normal +z
        m.faces.push_back({a, c, b});              // bottom, normal -z
    }
    // Walls on boundary edges a->b (interior on the left): outward = right of a->b.
    for (const auto& [e, k] : directed) {
        if (directed.count({e.second, e.first})) continue;
        const std::uint32_t a = e.first, b = e.second;
        m.faces.push_back({a, b, b + n});
        m.faces.push_back({a, b + n, a + n});
    }
    return m;
}

/// Cuts every triangle by the vertical lines x = k * max_dx (k integer) so that no triangle spans
/// more than max_dx along x. Conforming: the crossing of an edge with a line is computed once per
/// edge and shared by both triangles using it, so an edge-conforming triangulation stays
/// edge-conforming. Each triangle's part between two consecutive lines is a convex polygon (at most
/// 5 vertices) split by a fan. Costs O(triangles + crossings): unlike midpoint subdivision, only u
/// is refined (v needs nothing: the band map is affine along v).
inline void refine_x_extent(planar_triangulation& t, double max_dx) {
    require_positive(max_dx, "refine: max_dx");
    using edge = std::pair<std::uint32_t, std::uint32_t>;
    std::map<edge, std::vector<std::uint32_t>> crossings;  // canonical edge (lo id, hi id) -> vertices, in id order
    // Lines X_k = k * max_dx; k is found by comparing with X_k itself (not floor(x / max_dx), whose
    // rounding can disagree with k * max_dx for x on a line).
    auto first_line_above = [max_dx](double x) {
        double k = std::floor(x / max_dx) - 1.0;
        while (k * max_dx <= x) k += 1.0;
        return k;
    };
    auto slab_of = [&](double x) { return first_line_above(x) - 1.0; };  // X_k <= x < X_k+1
    auto crossings_of = [&](std::uint32_t a, std::uint32_t b) -> const std::vector<std::uint32_t>& {
        const edge key = a < b ? edge{a, b} : edge{b, a};
        auto it = crossings.find(key);
        if (it != crossings.end()) return it->second;
        std::vector<std::uint32_t> ids;
        const vec2 p = t.vertices[key.first], q = t.vertices[key.second];
        const double lo = std::min(p.x, q.x), hi = std::max(p.x, q.x);
        // lines strictly between the endpoints, ordered from p to q
        std::vector<double> xs;
        for (double k = first_line_above(lo); k * max_dx < hi; k += 1.0) xs.push_back(k * max_dx);
        if (p.x > q.x) std::reverse(xs.begin(), xs.end());
        for (double x : xs) {
            const double s = (x - p.x) / (q.x - p.x);
            ids.push_back(static_cast<std::uint32_t>(t.vertices.size()));
            t.vertices.push_back({x, p.y + s * (q.y - p.y)});
        }
        return crossings.emplace(key, std::move(ids)).first->second;
    };
    std::vector<std::array<std::uint32_t, 3>> out;
    out.reserve(t.triangles.size());
    std::vector<std::uint32_t> ring, piece;
    for (const auto& tri : t.triangles) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (std::uint32_t v : tri) lo = std::min(lo, t.vertices[v].x), hi = std::max(hi, t.vertices[v].x);
        if (hi <= (slab_of(lo) + 1.0) * max_dx) {
            out.push_back(tri);
            continue;
        }
        // boundary of the triangle with every crossing, counter-clockwise
        ring.clear();
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
            ring.push_back(a);
            const auto& c = crossings_of(a, b);
            if (a < b) ring.insert(ring.end(), c.begin(), c.end());
            else ring.insert(ring.end(), c.rbegin(), c.rend());
        }
        // the part in each slab [X_k, X_k+1]: the boundary points inside it, in boundary order
        for (double k = slab_of(lo); k * max_dx < hi; k += 1.0) {
            const double x0 = k * max_dx, x1 = (k + 1.0) * max_dx;
            piece.clear();
            for (std::uint32_t v : ring)
                if (t.vertices[v].x >= x0 && t.vertices[v].x <= x1) piece.push_back(v);
            // Every fan triangle is kept, even a flat one (a sliver whose rounded crossings are
            // collinear): dropping it would open the mesh; the fan uses each piece edge once.
            for (std::size_t i = 1; i + 1 < piece.size(); ++i) out.push_back({piece[0], piece[i], piece[i + 1]});
        }
    }
    t.triangles = std::move(out);
}

namespace detail::weld {
using float3 = std::array<float, 3>;

[[nodiscard]] inline float3 rounded(const vec3& p) { return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}; }

// The faces' edges that are not shared by exactly two faces traversing them in opposite
// directions (boundary, non-manifold or inconsistently oriented), as vertex pairs.
[[nodiscard]] inline std::vector<std::pair<std::uint32_t, std::uint32_t>> bad_edges(const std::vector<std::array<std::uint32_t, 3>>& faces) {
    struct half {
        std::uint64_t key;
        std::uint32_t from;
        bool operator<(const half& o) const noexcept { return key != o.key ? key < o.key : from < o.from; }
    };
    std::vector<half> he;
    he.reserve(3 * faces.size());
    for (const auto& f : faces)
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t a = f[static_cast<std::size_t>(i)], b = f[static_cast<std::size_t>((i + 1) % 3)];
            he.push_back({(static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b), a});
        }
    std::sort(he.begin(), he.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> bad;
    for (std::size_t i = 0; i < he.size();) {
        std::size_t j = i;
        while (j < he.size() && he[j].key == he[i].key) ++j;
        if (j - i != 2 || he[i].from == he[i + 1].from)
            bad.push_back({static_cast<std::uint32_t>(he[i].key >> 32), static_cast<std::uint32_t>(he[i].key & 0xffffffffu)});
        i = j;
    }
    return bad;
}

// The free float position nearest to p: p rounded, else the rounded position moved by up to
// `reach` float steps per coordinate, nearest to p first.
[[nodiscard]] inline float3 free_float_position(const vec3& p, const std::map<float3, std::uint32_t>& used) {
    const float3 r = rounded(p);
    for (int reach = 1;; ++reach) {
        float3 best{};
        double best_d = std::numeric_limits<double>::infinity();
        for (int dx = -reach; dx <= reach; ++dx)
            for (int dy = -reach; dy <= reach; ++dy)
                for (int dz = -reach; dz <= reach; ++dz) {
                    float3 c = r;
                    const int d[3] = {dx, dy, dz};
                    for (int a = 0; a < 3; ++a)
                        for (int s = 0; s < std::abs(d[a]); ++s)
                            c[static_cast<std::size_t>(a)] = std::nextafter(c[static_cast<std::size_t>(a)], d[a] > 0 ? std::numeric_limits<float>::infinity()
                                                                                                                 : -std::numeric_limits<float>::infinity());
                    if (used.count(c)) continue;
                    const vec3 q{c[0], c[1], c[2]};
                    const double dist = glm::dot(q - p, q - p);
                    if (dist < best_d) best_d = dist, best = c;
                }
        if (std::isfinite(best_d)) return best;
    }
}
}  // namespace detail::weld

/// Rounds every vertex to single precision (what binary STL stores) and merges vertices that
/// become equal, without changing the mesh's topology where that would open or pinch it.
///
/// Vertices that round to the same float position form a cluster. A cluster whose members are
/// joined by edges among themselves (short edges of sliver triangles next to a cut line, a few
/// 1e-7 mm long) is merged: its zero-length edges collapse and the faces that become degenerate
/// (a repeated vertex) are dropped, as written STL would collapse them. A collapse can still break
/// the surface (two of the cluster's neighbours joined twice: the link condition), and a cluster
/// whose members share no edge would pinch two sheets together. So, when the indexed mesh is
/// watertight (every edge in two faces, opposite directions), the merge is checked: every cluster
/// at an edge that is no longer shared by exactly two opposite faces is kept apart instead, its
/// members moved to distinct free float positions nearest to them (at most a few float steps,
/// about 1e-7 of the coordinates), and the check repeats. Un-merging every cluster gives back the
/// input's connectivity, so the result is watertight whenever the indexed input is, with every
/// vertex a float. A mesh that is not watertight as indexed is welded by position alone (every
/// cluster merged), which may be what closes it. Vertex order: first use in index order.
FABSYNTH_NO_SLP_VECTORIZE inline void weld_to_float(triangle_mesh& m) {  // compiler.hpp: GCC 12 miscompiles it otherwise
    using detail::weld::float3;
    const std::size_t n = m.vertices.size();
    std::map<float3, std::uint32_t> index;  // rounded position -> cluster
    std::vector<std::uint32_t> cluster(n);
    std::vector<float3> key;
    std::vector<std::uint32_t> members;
    for (std::size_t i = 0; i < n; ++i) {
        const float3 k = detail::weld::rounded(m.vertices[i]);
        const auto [it, fresh] = index.emplace(k, static_cast<std::uint32_t>(key.size()));
        if (fresh) key.push_back(k), members.push_back(0);
        cluster[i] = it->second;
        ++members[it->second];
    }
    const std::size_t nc = key.size();
    // merge[c]: cluster c (more than one vertex) is merged into one vertex
    std::vector<char> merge(nc, 0);
    const bool checked = is_watertight(m);
    if (!checked) {
        for (std::size_t c = 0; c < nc; ++c) merge[c] = members[c] > 1;
    } else if (nc < n) {
        // only clusters connected through their own edges
        union_find uf(static_cast<std::uint32_t>(n));
        for (const auto& f : m.faces)
            for (int e = 0; e < 3; ++e) {
                const std::uint32_t a = f[static_cast<std::size_t>(e)], b = f[static_cast<std::size_t>((e + 1) % 3)];
                if (cluster[a] == cluster[b]) uf.unite(a, b);
            }
        std::vector<std::uint32_t> root(nc, std::numeric_limits<std::uint32_t>::max());
        for (std::size_t c = 0; c < nc; ++c) merge[c] = members[c] > 1;
        for (std::uint32_t i = 0; i < n; ++i) {
            std::uint32_t& r = root[cluster[i]];
            if (r == std::numeric_limits<std::uint32_t>::max()) r = uf.find(i);
            else if (r != uf.find(i)) merge[cluster[i]] = 0;
        }
    }
    std::vector<std::uint32_t> remap(n);
    std::vector<std::uint32_t> owner;  // cluster of each output vertex
    std::vector<std::array<std::uint32_t, 3>> faces;
    for (;;) {
        owner.clear();
        std::vector<std::uint32_t> first(nc, std::numeric_limits<std::uint32_t>::max());
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t c = cluster[i];
            if (merge[c] && first[c] != std::numeric_limits<std::uint32_t>::max()) {
                remap[i] = first[c];
                continue;
            }
            remap[i] = first[c] = static_cast<std::uint32_t>(owner.size());
            owner.push_back(c);
        }
        faces.clear();
        faces.reserve(m.faces.size());
        for (auto f : m.faces) {
            for (std::uint32_t& v : f) v = remap[v];
            if (f[0] != f[1] && f[1] != f[2] && f[0] != f[2]) faces.push_back(f);
        }
        if (!checked) break;
        bool changed = false;
        for (const auto& [a, b] : detail::weld::bad_edges(faces))
            for (std::uint32_t v : {a, b})
                if (merge[owner[v]]) merge[owner[v]] = 0, changed = true;
        if (!changed) break;  // nothing merged is at fault (a watertight input cannot get here)
    }
    // positions: a cluster's float position for its first output vertex, the nearest free float
    // positions for the other members of a cluster kept apart
    std::vector<vec3> verts(owner.size());
    std::vector<char> placed(nc, 0);
    std::vector<char> done(owner.size(), 0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t v = remap[i], c = cluster[i];
        if (done[v]) continue;
        done[v] = 1;
        float3 k = key[c];
        if (placed[c]) {
            k = detail::weld::free_float_position(m.vertices[i], index);
            index.emplace(k, c);
        }
        placed[c] = 1;
        verts[v] = {k[0], k[1], k[2]};
    }
    m.vertices = std::move(verts);
    m.faces = std::move(faces);
}

/// Where two rings of a set of polygons come within `tolerance` of each other: two rings, or two
/// edges of one ring that are not neighbours, touching or crossing (a figure-eight, two shapes
/// meeting at a corner, a hole touching its outline). Extruded, such a contact is a vertical edge
/// or wall shared by both sides: a solid that is not a 2-manifold there, in any precision.
struct ring_contact {
    vec2 at;                      ///< a point of the contact (on the first edge)
    std::size_t polygon_a = 0;    ///< the polygons (indices into the set) of the two edges
    std::size_t polygon_b = 0;
};

/// The first contact closer than `tolerance` (>= 0) between edges of `polys` that do not share a
/// ring vertex, or none. Edges are bucketed on a uniform grid, so the cost is about linear in the
/// number of edges for outlines of even edge lengths.
[[nodiscard]] inline std::optional<ring_contact> find_ring_contact(const std::vector<polygon_with_holes>& polys, double tolerance) {
    struct edge {
        vec2 a, b;
        std::uint32_t ring, i, n;  // ring id, index in the ring, ring size
        std::size_t polygon;
    };
    std::vector<edge> edges;
    box2 bounds;
    std::uint32_t ring_id = 0;
    for (std::size_t k = 0; k < polys.size(); ++k) {
        auto add = [&](const ring2& r) {
            const auto n = static_cast<std::uint32_t>(r.size());
            for (std::uint32_t i = 0; i < n; ++i) {
                edges.push_back({r[i], r[(i + 1) % n], ring_id, i, n, k});
                bounds.extend(r[i]);
            }
            ++ring_id;
        };
        add(polys[k].outer);
        for (const ring2& h : polys[k].holes) add(h);
    }
    if (edges.empty()) return std::nullopt;
    double mean = 0.0;
    for (const edge& e : edges) mean += glm::length(e.b - e.a);
    mean /= static_cast<double>(edges.size());
    const vec2 size = bounds.size();
    const double cell = std::max({mean, tolerance, 1e-6 * std::max(size.x, size.y), std::numeric_limits<double>::min()});
    const int nx = std::clamp(static_cast<int>(size.x / cell) + 1, 1, 4096), ny = std::clamp(static_cast<int>(size.y / cell) + 1, 1, 4096);
    const double cx = std::max(size.x / nx, std::numeric_limits<double>::min()), cy = std::max(size.y / ny, std::numeric_limits<double>::min());
    std::vector<std::vector<std::uint32_t>> grid(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
    auto cell_of = [&](double v, double lo, double c, int n) { return std::clamp(static_cast<int>(std::floor((v - lo) / c)), 0, n - 1); };
    for (std::uint32_t k = 0; k < edges.size(); ++k) {
        const edge& e = edges[k];
        const int x0 = cell_of(std::min(e.a.x, e.b.x) - tolerance, bounds.lo.x, cx, nx), x1 = cell_of(std::max(e.a.x, e.b.x) + tolerance, bounds.lo.x, cx, nx);
        const int y0 = cell_of(std::min(e.a.y, e.b.y) - tolerance, bounds.lo.y, cy, ny), y1 = cell_of(std::max(e.a.y, e.b.y) + tolerance, bounds.lo.y, cy, ny);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) grid[static_cast<std::size_t>(y) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(x)].push_back(k);
    }
    auto orient2 = [](vec2 a, vec2 b, vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); };
    // distance between two segments and a point of the first near the second
    auto contact = [&](const edge& e, const edge& f, vec2& at) {
        const double d1 = orient2(e.a, e.b, f.a), d2 = orient2(e.a, e.b, f.b), d3 = orient2(f.a, f.b, e.a), d4 = orient2(f.a, f.b, e.b);
        if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
            at = e.a + (d3 / (d3 - d4)) * (e.b - e.a);
            return 0.0;
        }
        double best = segment_distance(e.a, f.a, f.b);
        at = e.a;
        if (const double d = segment_distance(e.b, f.a, f.b); d < best) best = d, at = e.b;
        if (const double d = segment_distance(f.a, e.a, e.b); d < best) best = d, at = f.a;
        if (const double d = segment_distance(f.b, e.a, e.b); d < best) best = d, at = f.b;
        return best;
    };
    for (const auto& bucket : grid)
        for (std::size_t p = 0; p < bucket.size(); ++p)
            for (std::size_t q = p + 1; q < bucket.size(); ++q) {
                const edge &e = edges[bucket[p]], &f = edges[bucket[q]];
                if (e.ring == f.ring && (e.n <= 3 || (e.i + 1) % e.n == f.i || (f.i + 1) % f.n == e.i)) continue;  // neighbours share a vertex
                vec2 at;
                if (contact(e, f, at) <= tolerance) return ring_contact{at, e.polygon, f.polygon};
            }
    return std::nullopt;
}

/// Options of extrude_along_curve.
struct curve_extrude_options {
    double thickness = 1.0;        ///< slab thickness, mm (> 0)
    double chord_tolerance = 0.01; ///< max distance of a mapped triangle edge from the true mapped curve, mm (> 0)
    double max_du = 0.0;           ///< max u-extent of a triangle edge before mapping; 0 = from chord_tolerance
};

namespace detail::band {
/// Validates band-coordinate polygons for a curve of length L; returns max |v|.
inline double check_band_polygons(const std::vector<polygon_with_holes>& polys, double length, const char* what) {
    const double tol = 1e-9 * length;
    double vmax = 0.0;
    for (std::size_t i = 0; i < polys.size(); ++i) {
        auto check = [&](const ring2& r) {
            for (const vec2& p : r) {
                if (!all_finite(p)) throw invalid_input(std::string(what) + ": polygon " + std::to_string(i) + " has a non-finite point");
                if (p.x < -tol || p.x > length + tol)
                    throw invalid_input(std::string(what) + ": polygon " + std::to_string(i) + " has u = " + std::to_string(p.x) +
                                        " outside the curve's [0, " + std::to_string(length) + "]");
                vmax = std::max(vmax, std::abs(p.y));
            }
        };
        check(polys[i].outer);
        for (const ring2& h : polys[i].holes) check(h);
    }
    return vmax;
}

/// Seam conformity for closed curves: snaps u within tol of 0 or L onto 0 or L and inserts into
/// every edge lying on a seam side the v values of the other side's seam vertices.
inline std::vector<polygon_with_holes> conform_seam(std::vector<polygon_with_holes> polys, double length) {
    const double tol = 1e-9 * length;
    std::vector<double> at0, atL;
    auto snap = [&](ring2& r) {
        for (vec2& p : r) {
            if (std::abs(p.x) <= tol) p.x = 0.0, at0.push_back(p.y);
            else if (std::abs(p.x - length) <= tol) p.x = length, atL.push_back(p.y);
        }
    };
    for (auto& p : polys) {
        snap(p.outer);
        for (ring2& h : p.holes) snap(h);
    }
    std::sort(at0.begin(), at0.end());
    std::sort(atL.begin(), atL.end());
    auto insert = [&](ring2& r) {
        ring2 out;
        for (std::size_t i = 0; i < r.size(); ++i) {
            const vec2 a = r[i], b = r[(i + 1) % r.size()];
            out.push_back(a);
            if (a.x != b.x || (a.x != 0.0 && a.x != length)) continue;
            const auto& other = a.x == 0.0 ? atL : at0;
            const double lo = std::min(a.y, b.y), hi = std::max(a.y, b.y);
            std::vector<double> vs;
            for (auto it = std::upper_bound(other.begin(), other.end(), lo); it != other.end() && *it < hi; ++it)
                if (vs.empty() || *it != vs.back()) vs.push_back(*it);
            if (a.y > b.y) std::reverse(vs.begin(), vs.end());
            for (double v : vs) out.push_back({a.x, v});
        }
        r = std::move(out);
    };
    for (auto& p : polys) {
        insert(p.outer);
        for (ring2& h : p.holes) insert(h);
    }
    return polys;
}
}  // namespace detail::band

/// The u-extent below which mapped triangle edges stay within chord_tolerance of the mapped curve
/// (sagitta r (1 - cos(du / 2r)) ~ du^2 / 8r at radius of curvature r, scaled by r / (r + vmax) for
/// the outer side of the band); +inf for a straight curve. Curve: planar_curve or space_curve.
template <class Curve>
[[nodiscard]] double max_du_for_tolerance(const Curve& c, double chord_tolerance, double vmax) {
    require_positive(chord_tolerance, "curve band: chord_tolerance");
    const double r = c.min_radius_of_curvature();
    if (!std::isfinite(r)) return std::numeric_limits<double>::infinity();
    return std::sqrt(8.0 * chord_tolerance * r) * r / (r + vmax);
}

namespace detail::band {
/// The pattern's triangulation in the parameter domain (u, v) of a curve of length L: triangulated,
/// cut by the lines u = k du (du finite), and for closed curves with the cut at u = L welded onto
/// the cut at u = 0 (refinement never splits seam edges: their u-extent is 0).
inline planar_triangulation parameter_triangulation(const std::vector<polygon_with_holes>& band_polys, double L, bool closed, double du,
                                                    double vmax) {
    const std::vector<polygon_with_holes> polys = closed ? conform_seam(band_polys, L) : band_polys;
    planar_triangulation t = triangulate(polys);
    if (std::isfinite(du)) refine_x_extent(t, du);
    if (closed) {
        std::vector<std::pair<double, std::uint32_t>> at0;
        for (std::uint32_t i = 0; i < t.vertices.size(); ++i)
            if (t.vertices[i].x == 0.0) at0.push_back({t.vertices[i].y, i});
        std::sort(at0.begin(), at0.end());
        std::vector<std::uint32_t> target(t.vertices.size());
        for (std::uint32_t i = 0; i < t.vertices.size(); ++i) target[i] = i;
        const double vtol = 1e-9 * std::max(L, vmax);
        // Only vertices of edges lying on the cut need a partner: a shape may also touch the line
        // u = L at a single vertex (its material ends there), which glues to nothing at u = 0.
        std::vector<char> on_seam_edge(t.vertices.size(), 0);
        for (const auto& tri : t.triangles)
            for (int e = 0; e < 3; ++e) {
                const std::uint32_t a = tri[e], b = tri[(e + 1) % 3];
                if (t.vertices[a].x == L && t.vertices[b].x == L) on_seam_edge[a] = on_seam_edge[b] = 1;
            }
        for (std::uint32_t i = 0; i < t.vertices.size(); ++i) {
            if (t.vertices[i].x != L || !on_seam_edge[i]) continue;
            const double v = t.vertices[i].y;
            auto it = std::lower_bound(at0.begin(), at0.end(), std::pair{v - vtol, std::uint32_t{0}});
            if (it == at0.end() || it->first > v + vtol)
                throw invalid_input("extrude_along_curve: closed pattern: the cut at u = L has a vertex at v = " + std::to_string(v) +
                                    " with no partner in the cut at u = 0 (the two cuts must match)");
            target[i] = it->second;
        }
        for (auto& tri : t.triangles)
            for (std::uint32_t& v : tri) v = target[v];
    }
    return t;
}
}  // namespace detail::band

/// Triangulates band-coordinate polygons (u along the curve in [0, L], v across) in the parameter
/// domain, refines, welds the seam of closed curves, maps by the band map and extrudes (§6.3).
[[nodiscard]] inline triangle_mesh extrude_along_curve(const std::vector<polygon_with_holes>& band_polys,
                                                       const planar_curve& curve, const curve_extrude_options& opt = {}) {
    require_positive(opt.thickness, "extrude_along_curve: thickness");
    require_positive(opt.chord_tolerance, "extrude_along_curve: chord_tolerance");
    if (!(opt.max_du >= 0.0) || !std::isfinite(opt.max_du)) throw invalid_input("extrude_along_curve: max_du must be finite and >= 0");
    const double L = curve.length();
    const double vmax = detail::band::check_band_polygons(band_polys, L, "extrude_along_curve");
    curve.check_band(vmax);
    const double du = opt.max_du > 0.0 ? opt.max_du : max_du_for_tolerance(curve, opt.chord_tolerance, vmax);
    planar_triangulation t = detail::band::parameter_triangulation(band_polys, L, curve.closed(), du, vmax);
    for (vec2& p : t.vertices) p = curve.band_point(p.x, p.y);
    return extrude(t, opt.thickness);
}

/// As extrude_along_curve, along a curve in space (geometry/space_curve.hpp): the slab is built in
/// the parameter domain (u, v, w in [0, thickness]) and every vertex mapped by
/// C(u) + v n(u) + w b(u), so the thickness runs along the frame's third axis. The map keeps
/// orientation (t, n, b right-handed), so the slab stays closed and outward. On a curve in the
/// plane z = c with up = z and no twist this is extrude_along_curve's mesh, moved to z = c.
/// Also throws invalid_input when distant parts of the band meet (space_curve::find_self_contact
/// with the polygons' half-height and the thickness): the slab would cross itself.
[[nodiscard]] inline triangle_mesh extrude_along_space_curve(const std::vector<polygon_with_holes>& band_polys, const space_curve& curve,
                                                             const curve_extrude_options& opt = {}) {
    require_positive(opt.thickness, "extrude_along_space_curve: thickness");
    require_positive(opt.chord_tolerance, "extrude_along_space_curve: chord_tolerance");
    if (!(opt.max_du >= 0.0) || !std::isfinite(opt.max_du))
        throw invalid_input("extrude_along_space_curve: max_du must be finite and >= 0");
    const double L = curve.length();
    const double vmax = detail::band::check_band_polygons(band_polys, L, "extrude_along_space_curve");
    curve.check_band(vmax);
    if (const auto c = curve.find_self_contact(vmax, opt.thickness))
        throw invalid_input("extrude_along_space_curve: the band meets itself: its cross-sections at u = " + std::to_string(c->u1) + " and " +
                            std::to_string(c->u2) + " mm along the curve come within " + std::to_string(c->distance) + " mm (parts closer than " +
                            std::to_string(c->clearance) + " mm count as touching)");
    const double du = opt.max_du > 0.0 ? opt.max_du : max_du_for_tolerance(curve, opt.chord_tolerance, vmax);
    const planar_triangulation t = detail::band::parameter_triangulation(band_polys, L, curve.closed(), du, vmax);
    triangle_mesh m = extrude(t, opt.thickness);
    for (vec3& p : m.vertices) p = curve.band_point(p.x, p.y, p.z);
    return m;
}

}  // namespace fabsynth
