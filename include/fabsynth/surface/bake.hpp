// SPDX-License-Identifier: MIT
#pragma once
/// @file bake.hpp  Pattern baking (filigree-synthesis.md §6.1, Fig. 11): the part of a triangle
/// mesh covered by planar contours given in a 2D chart of it. For every face of the chart, the
/// 2D boolean of its (u, v) triangle with the contours (Clipper, one integer grid for the whole
/// chart), a constrained triangulation of the result (geometry/triangulate.hpp's ear clipping,
/// which keeps every boundary vertex), and the sub-triangles lifted back onto the face by their
/// barycentric coordinates. The result is the baked mesh M_b, the input of the stress analysis and
/// of the printable solid (surface/offset.hpp).
///
/// Usage:
///   // a flat mesh: its own x, y are the chart
///   std::vector<fabsynth::vec2> uv;  for (auto v : mesh.vertices) uv.push_back({v.x, v.y});
///   fabsynth::triangle_mesh mb = fabsynth::bake(mesh, uv, all_faces, contours);
///   // a surface patch: fabsynth::local_patch p = patcher.patch(...); uv per patch vertex
///
/// Chart: `uv` gives one (u, v) per mesh vertex (mm; only the vertices of `faces` are read), and a
/// face's (u, v) triangle must not be degenerate; faces whose (u, v) triangle is clockwise are
/// taken as they are (the orientation of the lifted triangles follows the 3D face). Vertices are
/// welded where their (u, v) agree after the grid's rounding, so sub-triangles of neighbouring
/// faces share the points where a contour crosses their common edge; welding uses the grid's
/// integer coordinates, so a point is one vertex whatever face computed it.
///
/// bake() ear-clips T ∩ C (a constrained triangulation with the same vertices and boundary, not
/// Delaunay); bake_per_face, the path of filigrees on surfaces, flips it to the constrained
/// Delaunay triangulation the paper asks for (Fig. 11c, geometry/cdt.hpp).
///
/// Errors: invalid_input naming the input for a uv count that is not the vertex count, a face out
/// of range, a non-finite (u, v).
///
/// bake_per_face: the same for contours that come from many charts (filigree elements on a curved
/// surface, each in its own local parameterization): per face, contours in the face's own frame
/// (face_frame: origin at corner 0, x along edge 0-1, y in the face's plane, mm, isometric), united
/// per face (nonzero), clipped to the face, triangulated (ear clipping flipped to the constrained
/// Delaunay triangulation; a face whose ear clipping has a flat triangle keeps it) and lifted. Points on a mesh edge computed
/// by its two faces are merged when they lie within `weld` mm along the edge (a tolerance rather
/// than a rounding grid, so that two nearly equal points never straddle a cell border), points at a
/// corner become one vertex; the per-face booleans run on a fixed grid of 2^-24 mm (face frames
/// are within 2^26 mm of their origin for any mesh below 60 km); triangles flatter than 1e-10
/// (doubled area over the squared longest edge) are left out; the result shares vertices across faces wherever the contours cross
/// an edge at one place.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/cdt.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/triangulate.hpp"

namespace fabsynth {

/// The baked mesh (see the file comment): faces of `m` listed in `faces`, charted by `uv` (one per
/// vertex of m), intersected with `contours` (polygons with holes in the chart, mm).
[[nodiscard]] inline triangle_mesh bake(const triangle_mesh& m, std::span<const vec2> uv, std::span<const std::uint32_t> faces,
                                        const std::vector<polygon_with_holes>& contours) {
    if (uv.size() != m.num_vertices())
        throw invalid_input("bake: " + std::to_string(uv.size()) + " chart points for " + std::to_string(m.num_vertices()) + " vertices");
    triangle_mesh out;
    if (contours.empty() || faces.empty()) return out;
    box2 all = bounding_box(contours);
    for (const std::uint32_t f : faces) {
        if (f >= m.num_faces()) throw invalid_input("bake: face " + std::to_string(f) + " out of range for " + std::to_string(m.num_faces()));
        for (const std::uint32_t v : m.faces[f]) {
            if (!all_finite(uv[v])) throw invalid_input("bake: the chart point of vertex " + std::to_string(v) + " is not finite");
            all.extend(uv[v]);
        }
    }
    const clip_grid grid = clip_grid::for_bounds(all);
    std::vector<box2> contour_box;
    for (const polygon_with_holes& p : contours) contour_box.push_back(bounding_box(p.outer));
    std::map<std::pair<long long, long long>, std::uint32_t> welded;  // grid point -> vertex of out
    for (const std::uint32_t f : faces) {
        const auto& c = m.faces[f];
        const vec2 a = uv[c[0]], b = uv[c[1]], d = uv[c[2]];
        const double area2 = orient2d(a, b, d);
        if (!(std::abs(area2) > 0)) continue;  // a degenerate chart triangle covers nothing
        box2 tb;
        tb.extend(a).extend(b).extend(d);
        std::vector<polygon_with_holes> near;
        for (std::size_t k = 0; k < contours.size(); ++k)
            if (contour_box[k].intersects(tb)) near.push_back(contours[k]);
        if (near.empty()) continue;
        const std::vector<polygon_with_holes> piece = polygon_intersection({polygon_with_holes{ring2{a, b, d}, {}}}, near, grid);
        if (piece.empty()) continue;
        const planar_triangulation t = triangulate(piece);
        std::vector<std::uint32_t> id(t.vertices.size());
        for (std::size_t k = 0; k < t.vertices.size(); ++k) {
            const vec2 q = t.vertices[k];
            const ClipperLib::IntPoint g = grid.to_int(q);
            const auto [it, fresh] = welded.try_emplace({static_cast<long long>(g.X), static_cast<long long>(g.Y)}, static_cast<std::uint32_t>(out.vertices.size()));
            if (fresh) {  // lift by the barycentric coordinates of q in the chart triangle
                const vec3 l = barycentric(q, a, b, d);
                out.vertices.push_back(l.x * m.vertices[c[0]] + l.y * m.vertices[c[1]] + l.z * m.vertices[c[2]]);
            }
            id[k] = it->second;
        }
        for (const auto& tri : t.triangles) {  // counter-clockwise in (u, v): keep the face's own orientation
            std::array<std::uint32_t, 3> o{id[tri[0]], id[tri[1]], id[tri[2]]};
            if (o[0] == o[1] || o[1] == o[2] || o[0] == o[2]) continue;  // collapsed by the weld
            if (area2 < 0) std::swap(o[1], o[2]);
            out.faces.push_back(o);
        }
    }
    return out;
}

/// The isometric 2D frame of a face (see bake_per_face).
struct face_frame {
    vec3 origin, ex, ey;
    [[nodiscard]] static face_frame of(const triangle_mesh& m, std::uint32_t f) {
        const auto& c = m.faces[f];
        const vec3 p0 = m.vertices[c[0]], e1 = m.vertices[c[1]] - p0, e2 = m.vertices[c[2]] - p0;
        const vec3 n = glm::cross(e1, e2);
        const double l1 = glm::length(e1), ln = glm::length(n);
        if (!(l1 > 0 && ln > 0)) return {p0, {0, 0, 0}, {0, 0, 0}};
        const vec3 ex = e1 / l1;
        return {p0, ex, glm::cross(n / ln, ex)};
    }
    [[nodiscard]] vec2 to_2d(const vec3& x) const { return {glm::dot(x - origin, ex), glm::dot(x - origin, ey)}; }
    [[nodiscard]] vec3 to_3d(vec2 q) const { return origin + q.x * ex + q.y * ey; }
    [[nodiscard]] bool degenerate() const { return glm::dot(ex, ex) == 0; }
};

/// Contours on one face, in its face_frame (mm).
struct face_contours {
    std::uint32_t face = 0;
    std::vector<polygon_with_holes> polygons;
};

namespace detail::bake {

using edge_key = std::pair<std::uint32_t, std::uint32_t>;  // mesh vertex ids, lower first

// Where a point of a face piece lies: a corner of the face (mesh vertex), on one of its edges (at
// t from the edge's lower vertex id), or inside.
struct place {
    int kind = 0;  // 0 inside, 1 on an edge, 2 a corner
    std::uint32_t vertex = 0;
    edge_key edge{};
    double t = 0;
};

// One face's pieces (its frame) with every ring vertex placed.
struct face_piece {
    std::uint32_t face = 0;
    face_frame frame;
    std::array<vec2, 3> corners;
    std::vector<polygon_with_holes> polys;
    std::vector<std::vector<place>> places;  // per ring (outer, then holes, polygon by polygon)
    planar_triangulation triangles;          // of polys (every ring vertex kept, in ring order)
};

[[nodiscard]] inline place locate_on_face(const triangle_mesh& m, std::uint32_t f, const std::array<vec2, 3>& t2, vec2 q, double weld) {
    const auto& c = m.faces[f];
    const vec3 l = barycentric(q, t2[0], t2[1], t2[2]);
    const std::array<double, 3> lam{l.x, l.y, l.z};
    const double area2 = std::abs(orient2d(t2[0], t2[1], t2[2]));
    std::array<bool, 3> near{};
    int zeros = 0;
    for (int k = 0; k < 3; ++k) {  // distance to the edge opposite corner k: lam[k] times the corner's height
        const double h = area2 / std::max(glm::distance(t2[static_cast<std::size_t>((k + 1) % 3)], t2[static_cast<std::size_t>((k + 2) % 3)]), 1e-300);
        near[static_cast<std::size_t>(k)] = std::abs(lam[static_cast<std::size_t>(k)]) * h <= weld;
        zeros += near[static_cast<std::size_t>(k)];
    }
    place p;
    if (zeros >= 2) {
        for (std::size_t k = 0; k < 3; ++k)
            if (!near[k]) p.kind = 2, p.vertex = c[k];
        if (p.kind != 2) p.kind = 2, p.vertex = c[0];  // a face smaller than the weld
        return p;
    }
    if (zeros == 1) {
        std::size_t k = 0;
        while (!near[k]) ++k;
        const std::uint32_t a = c[(k + 1) % 3], b = c[(k + 2) % 3];
        const double tb = lam[(k + 2) % 3] / (lam[(k + 1) % 3] + lam[(k + 2) % 3]);  // from a to b
        p.kind = 1;
        p.edge = std::minmax(a, b);
        p.t = std::clamp(a < b ? tb : 1 - tb, 0.0, 1.0);
    }
    return p;
}

// The constrained Delaunay triangulation of an ear clipping over the same vertex list (vertices
// the CDT merges, rings touching at a point, are given by the first of them); the ear clipping
// itself when it has a flat triangle (Clipper's grid can leave collinear ring points).
[[nodiscard]] inline planar_triangulation delaunay_of(const planar_triangulation& ears) {
    std::vector<std::uint32_t> vertex_of;
    planar_triangulation d;
    try {
        d = constrained_delaunay(ears, &vertex_of);
    } catch (const solver_error&) {
        return ears;
    }
    std::vector<std::uint32_t> first(d.vertices.size(), UINT32_MAX);
    for (std::uint32_t v = 0; v < vertex_of.size(); ++v)
        if (first[vertex_of[v]] == UINT32_MAX) first[vertex_of[v]] = v;
    planar_triangulation out;
    out.vertices = ears.vertices;
    for (const auto& t : d.triangles) out.triangles.push_back({first[t[0]], first[t[1]], first[t[2]]});
    return out;
}

// The t of a point placed on, or at a corner of, edge e (nothing if it is not on e).
[[nodiscard]] inline std::optional<double> t_on(const place& p, const edge_key& e) {
    if (p.kind == 1 && p.edge == e) return p.t;
    if (p.kind == 2 && p.vertex == e.first) return 0.0;
    if (p.kind == 2 && p.vertex == e.second) return 1.0;
    return std::nullopt;
}

}  // namespace detail::bake

/// The baked mesh of contours given per face (see the file comment); entries of one face are
/// united. `weld`: mm along an edge within which points of its two faces are one vertex.
/// Conforming: a triangle side along a mesh edge is split at every point the other face put on
/// that edge, so the two sides share their edges (no T-junctions).
[[nodiscard]] inline triangle_mesh bake_per_face(const triangle_mesh& m, std::span<const face_contours> per_face, double weld = 1e-6) {
    namespace db = detail::bake;
    std::map<std::uint32_t, std::vector<polygon_with_holes>> by_face;
    for (const face_contours& fc : per_face) {
        if (fc.face >= m.num_faces()) throw invalid_input("bake: face " + std::to_string(fc.face) + " out of range for " + std::to_string(m.num_faces()));
        auto& dst = by_face[fc.face];
        dst.insert(dst.end(), fc.polygons.begin(), fc.polygons.end());
    }
    // 1. per face: the union clipped to the face, ring vertices placed; edge points gathered.
    std::vector<db::face_piece> pieces;
    std::map<db::edge_key, std::vector<double>> edge_ts;
    for (const auto& [f, polys] : by_face) {
        db::face_piece fp;
        fp.face = f, fp.frame = face_frame::of(m, f);
        if (fp.frame.degenerate()) continue;
        const auto& c = m.faces[f];
        fp.corners = {fp.frame.to_2d(m.vertices[c[0]]), fp.frame.to_2d(m.vertices[c[1]]), fp.frame.to_2d(m.vertices[c[2]])};
        // A fixed grid of 2^-24 mm (6e-8 mm, below the weld tolerance): Clipper's output then has no
        // triangle too thin for orient2d in doubles (a grid fitted to a 1 mm face would be 1e-15 mm,
        // and its nearly collinear output vertices stop the ear clipper).
        clip_grid grid;
        grid.scale = std::ldexp(1.0, 24);
        // Each polygon oriented (outer counter-clockwise, holes clockwise) before the nonzero
        // union: a caller's chart may be mirrored against the face (a fold of a local
        // parameterization), and one mirrored ring would cancel the rings it overlaps.
        std::vector<ring2> rings;
        for (polygon_with_holes p : polys) {
            orient(p);
            rings.push_back(std::move(p.outer));
            rings.insert(rings.end(), std::make_move_iterator(p.holes.begin()), std::make_move_iterator(p.holes.end()));
        }
        const auto united = polygon_union(rings, fill_rule::nonzero, grid);
        // The notches of a grid unit the booleans leave would stop the ear clipper: vertices are
        // merged at the weld distance, then at 100 and 1000 times it; a piece whose rings still
        // touch themselves (a spike against an edge) is opened by 10 and 100 times the weld
        // (offset in, out, clipped to the face again), which removes features thinner than that.
        const ring2 tri{fp.corners[0], fp.corners[1], fp.corners[2]};
        const auto clipped = polygon_intersection({polygon_with_holes{tri, {}}}, united, grid);
        const std::array<double, 5> spacing{weld, 100 * weld, 1000 * weld, 1e4 * weld, 1e5 * weld};
        for (std::size_t attempt = 0; attempt < spacing.size(); ++attempt) {
            if (attempt < 3) fp.polys = merge_close_vertices(clipped, spacing[attempt], grid);
            else {
                const double d = spacing[attempt];
                fp.polys = merge_close_vertices(
                    polygon_intersection({polygon_with_holes{tri, {}}}, polygon_offset(polygon_offset(clipped, -d, 0.1 * d), d, 0.1 * d), grid), weld, grid);
            }
            try {
                fp.triangles = db::delaunay_of(triangulate(fp.polys));
                break;
            } catch (const solver_error& e) {
                if (attempt + 1 == spacing.size()) throw solver_error("bake: face " + std::to_string(f) + ": " + e.what());
            }
        }
        if (fp.polys.empty()) continue;
        for (const auto& p : fp.polys)
            for (std::size_t r = 0; r <= p.holes.size(); ++r) {
                const ring2& ring = r == 0 ? p.outer : p.holes[r - 1];
                auto& pl = fp.places.emplace_back();
                for (const vec2& q : ring) {
                    pl.push_back(db::locate_on_face(m, f, fp.corners, q, weld));
                    if (pl.back().kind == 1) edge_ts[pl.back().edge].push_back(pl.back().t);
                }
            }
        pieces.push_back(std::move(fp));
    }
    // 2. per mesh edge: its points clustered within `weld` along it, one vertex each.
    triangle_mesh out;
    std::map<db::edge_key, std::vector<std::pair<double, std::uint32_t>>> edge_vertices;  // t, output vertex
    for (auto& [e, ts] : edge_ts) {
        std::sort(ts.begin(), ts.end());
        const double len = glm::distance(m.vertices[e.first], m.vertices[e.second]);
        auto& ev = edge_vertices[e];
        for (const double t : ts) {
            if (!ev.empty() && (t - ev.back().first) * len <= weld) continue;
            ev.emplace_back(t, static_cast<std::uint32_t>(out.vertices.size()));
            out.vertices.push_back((1 - t) * m.vertices[e.first] + t * m.vertices[e.second]);
        }
    }
    auto edge_vertex = [&](const db::edge_key& e, double t) {  // the cluster of t
        const auto& ev = edge_vertices.at(e);
        auto it = std::lower_bound(ev.begin(), ev.end(), std::pair{t, 0u}, [](const auto& a, const auto& b) { return a.first < b.first; });
        if (it == ev.end() || (it != ev.begin() && t - std::prev(it)->first < it->first - t)) --it;
        return *it;
    };
    std::map<std::uint32_t, std::uint32_t> corner_id;
    auto corner_vertex = [&](std::uint32_t v) {
        const auto [it, fresh] = corner_id.try_emplace(v, static_cast<std::uint32_t>(out.vertices.size()));
        if (fresh) out.vertices.push_back(m.vertices[v]);
        return it->second;
    };
    // 3. per face: ear clipping of the rings where Clipper put them, each ring point lifted to its
    //    shared vertex (placed[v]: where output vertex v lies), then every triangle side along a mesh edge split
    //    at the edge's points between its ends, so both faces of an edge share their sides.
    std::vector<db::place> placed(out.vertices.size());
    for (const auto& [e, ev] : edge_vertices)
        for (const auto& [t, v] : ev) placed[v] = db::place{1, 0, e, t};
    auto note = [&](std::uint32_t v, const db::place& p) {
        if (placed.size() <= v) placed.resize(v + 1);
        placed[v] = p;
    };
    for (db::face_piece& fp : pieces) {
        std::vector<std::uint32_t> ids;  // output vertex per ring point, in triangulation input order
        std::size_t ring_index = 0;
        for (const auto& p : fp.polys)
            for (std::size_t r = 0; r <= p.holes.size(); ++r, ++ring_index) {
                const ring2& ring = r == 0 ? p.outer : p.holes[r - 1];
                const auto& pl = fp.places[ring_index];
                for (std::size_t k = 0; k < ring.size(); ++k) {
                    const db::place& a = pl[k];
                    std::uint32_t id = 0;
                    if (a.kind == 2) {
                        id = corner_vertex(a.vertex);
                        note(id, a);
                    } else if (a.kind == 1) {
                        id = edge_vertex(a.edge, a.t).second;
                    } else {
                        id = static_cast<std::uint32_t>(out.vertices.size()), out.vertices.push_back(fp.frame.to_3d(ring[k]));
                        note(id, a);
                    }
                    ids.push_back(id);
                }
            }
        const planar_triangulation& t = fp.triangles;
        if (t.vertices.size() != ids.size()) throw solver_error("bake: the triangulation changed the vertex count");
        std::vector<std::array<std::uint32_t, 3>> work;
        for (const auto& tri : t.triangles) work.push_back({ids[tri[0]], ids[tri[1]], ids[tri[2]]});
        while (!work.empty()) {
            const std::array<std::uint32_t, 3> o = work.back();
            work.pop_back();
            if (o[0] == o[1] || o[1] == o[2] || o[0] == o[2]) continue;
            bool split = false;
            for (int k = 0; k < 3 && !split; ++k) {  // side (u, v) opposite w
                const std::uint32_t u = o[static_cast<std::size_t>(k)], v = o[static_cast<std::size_t>((k + 1) % 3)], w = o[static_cast<std::size_t>((k + 2) % 3)];
                const db::place& pu = placed[u];
                const db::place& pv = placed[v];
                db::edge_key e{};
                if (pu.kind == 1) e = pu.edge;
                else if (pv.kind == 1) e = pv.edge;
                else if (pu.kind == 2 && pv.kind == 2) e = std::minmax(pu.vertex, pv.vertex);
                if (e == db::edge_key{} || !edge_vertices.count(e)) continue;
                const auto tu = db::t_on(pu, e), tv = db::t_on(pv, e);
                if (!tu || !tv) continue;
                std::vector<std::uint32_t> between;
                for (const auto& [tx, x] : edge_vertices.at(e))
                    if (tx > std::min(*tu, *tv) && tx < std::max(*tu, *tv) && x != u && x != v) between.push_back(x);
                if (between.empty()) continue;
                if (*tu > *tv) std::reverse(between.begin(), between.end());
                std::uint32_t prev = u;
                for (const std::uint32_t x : between) work.push_back({prev, x, w}), prev = x;
                work.push_back({prev, v, w});
                split = true;
            }
            if (split) continue;
            const vec3 a = out.vertices[o[0]], b = out.vertices[o[1]], c = out.vertices[o[2]];
            const double l2 = std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a), glm::dot(c - b, c - b)});
            if (!(glm::length(glm::cross(b - a, c - a)) > 1e-10 * l2)) continue;  // flat: no area, no stiffness
            out.faces.push_back(o);
        }
    }
    // interior points were added for every ring vertex; drop the unused ones
    std::vector<std::uint32_t> used(out.vertices.size(), UINT32_MAX);
    triangle_mesh compact;
    for (auto f : out.faces) {
        for (auto& v : f) {
            if (used[v] == UINT32_MAX) used[v] = static_cast<std::uint32_t>(compact.vertices.size()), compact.vertices.push_back(out.vertices[v]);
            v = used[v];
        }
        compact.faces.push_back(f);
    }
    return compact;
}

}  // namespace fabsynth
