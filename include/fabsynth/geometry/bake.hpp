// SPDX-License-Identifier: MIT
#pragma once
/// @file bake.hpp  Pattern baking (filigree-synthesis.md §6.1, Fig. 11): the part of a triangle
/// mesh covered by planar contours given in a 2D chart of it. For every face of the chart, the
/// 2D boolean of its (u, v) triangle with the contours (Clipper, one integer grid for the whole
/// chart), a constrained triangulation of the result (geometry/triangulate.hpp's ear clipping,
/// which keeps every boundary vertex), and the sub-triangles lifted back onto the face by their
/// barycentric coordinates. The result is the baked mesh M_b, the input of the stress analysis and
/// of the printable solid (geometry/surface_offset.hpp).
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
/// The paper triangulates T ∩ C by a constrained Delaunay triangulation; ear clipping gives a
/// constrained triangulation with the same vertices and boundary, not Delaunay (the FEM path
/// refines its own mesh, filigree/reconstruct.hpp).
///
/// Errors: invalid_input naming the input for a uv count that is not the vertex count, a face out
/// of range, a non-finite (u, v).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
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

}  // namespace fabsynth
