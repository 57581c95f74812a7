// SPDX-License-Identifier: MIT
#pragma once
/// @file curve_region.hpp  The faces of a triangle mesh that a closed curve drawn on it encloses
/// (a user region given by its outline, as in filigree-synthesis.md §7.2's regions).
///
/// Usage:
///   std::vector<vec3> outline = ...;                               // closed: the last point joins the first
///   auto faces = fabsynth::faces_inside_curve(mesh, outline, 1.0);  // points within 1 mm of the mesh; increasing face ids
///
/// How: every curve point is projected onto the mesh (closest point); each segment between two
/// consecutive projections is bisected, its midpoints projected in turn, until the faces of
/// neighbouring samples share a vertex, so the traced faces form an unbroken band along the curve.
/// The other faces fall into edge-connected sides (two faces are joined when they share an edge;
/// across a vertex where two traced faces meet, every path of shared edges runs through a traced
/// face, so a band closed in this sense separates). Among the sides that touch the band, the one
/// with the largest area is the outside (on a closed surface a closed curve bounds two sides: the
/// smaller one is taken to be the one meant); the region is the band plus the other sides. Its
/// border therefore follows the curve to within one face.
///
/// Errors (invalid_input, naming what was wrong): fewer than 3 points, a non-finite point, a point
/// farther than `max_offset` from the mesh, a segment over a gap of the mesh (no unbroken band
/// within 2^-30 of its length), a curve that does not separate the surface.
#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth {

namespace detail::curve_region {

[[nodiscard]] inline bool share_a_vertex(const triangle_mesh& m, std::uint32_t f, std::uint32_t g) {
    for (const std::uint32_t a : m.faces[f])
        for (const std::uint32_t b : m.faces[g])
            if (a == b) return true;
    return false;
}

// Marks the faces under segment [a, b] (a and b on the mesh, in faces fa and fb): bisects until
// neighbouring samples lie in faces that share a vertex.
inline void trace_segment(const mesh_distance& md, const triangle_mesh& m, vec3 a, std::uint32_t fa, vec3 b, std::uint32_t fb, int depth,
                          std::size_t segment, std::vector<std::uint8_t>& band) {
    band[fa] = band[fb] = 1;
    if (fa == fb || share_a_vertex(m, fa, fb)) return;
    if (depth == 30)
        throw invalid_input("curve region: segment " + std::to_string(segment) +
                            " of the curve crosses a gap of the mesh (a hole or a border): it cannot be traced on the surface");
    const mesh_closest mid = md.closest(0.5 * (a + b));
    trace_segment(md, m, a, fa, mid.point, mid.face, depth + 1, segment, band);
    trace_segment(md, m, mid.point, mid.face, b, fb, depth + 1, segment, band);
}

// Phase 1: the band of faces under the closed curve.
[[nodiscard]] inline std::vector<std::uint8_t> traced_band(const triangle_mesh& m, std::span<const vec3> curve, double max_offset) {
    const mesh_distance md(m);
    std::vector<mesh_closest> on(curve.size());
    for (std::size_t k = 0; k < curve.size(); ++k) {
        if (!all_finite(curve[k])) throw invalid_input("curve region: point " + std::to_string(k) + " is not finite");
        on[k] = md.closest(curve[k], max_offset);
        if (!on[k].found())
            throw invalid_input("curve region: point " + std::to_string(k) + " lies farther than " + std::to_string(max_offset) + " mm from the mesh");
    }
    std::vector<std::uint8_t> band(m.faces.size(), 0);
    for (std::size_t k = 0; k < curve.size(); ++k) {
        const mesh_closest &a = on[k], &b = on[(k + 1) % curve.size()];
        trace_segment(md, m, a.point, a.face, b.point, b.face, 0, k, band);
    }
    return band;
}

// Phase 2: edge-connected sides of the faces outside the band; side id per face (UINT32_MAX on
// the band).
[[nodiscard]] inline std::vector<std::uint32_t> sides(const triangle_mesh& m, const std::vector<std::uint8_t>& band) {
    union_find uf(m.faces.size());
    std::unordered_map<std::uint64_t, std::uint32_t> first;  // undirected edge -> a face off the band using it
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
        if (band[f]) continue;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = m.faces[f][k], b = m.faces[f][(k + 1) % 3];
            const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
            const auto [it, fresh] = first.try_emplace(key, f);
            if (!fresh) uf.unite(it->second, f);
        }
    }
    std::vector<std::uint32_t> side(m.faces.size(), UINT32_MAX);
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        if (!band[f]) side[f] = static_cast<std::uint32_t>(uf.find(f));
    return side;
}

}  // namespace detail::curve_region

/// The faces enclosed by a closed curve on m (see the file comment), increasing ids.
/// @param m           triangle mesh (mm), vertices shared between faces
/// @param curve       closed polyline on or near the surface (mm; the last point joins the first)
/// @param max_offset  largest accepted distance of a curve point from the mesh (mm)
[[nodiscard]] inline std::vector<std::uint32_t> faces_inside_curve(const triangle_mesh& m, std::span<const vec3> curve, double max_offset) {
    namespace cr = detail::curve_region;
    if (curve.size() < 3) throw invalid_input("curve region: a closed curve needs at least 3 points, got " + std::to_string(curve.size()));
    if (!(max_offset >= 0)) throw invalid_input("curve region: the largest distance from the mesh must be >= 0");
    const std::vector<std::uint8_t> band = cr::traced_band(m, curve, max_offset);
    const std::vector<std::uint32_t> side = cr::sides(m, band);

    std::vector<std::uint8_t> on_band_vertex(m.vertices.size(), 0);
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        if (band[f])
            for (const std::uint32_t v : m.faces[f]) on_band_vertex[v] = 1;
    std::unordered_map<std::uint32_t, double> area;  // the sides that touch the band, by root face
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        if (!band[f] && (on_band_vertex[m.faces[f][0]] || on_band_vertex[m.faces[f][1]] || on_band_vertex[m.faces[f][2]])) area[side[f]] = 0;
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        if (const auto it = band[f] ? area.end() : area.find(side[f]); it != area.end()) it->second += 0.5 * glm::length(face_normal_area2(m, f));
    if (area.size() < 2) throw invalid_input("curve region: the curve does not separate the surface (it encloses no part of it)");
    std::uint32_t outside = UINT32_MAX;  // the largest side; ties: the lowest root face
    double largest = -1.0;
    for (const auto& [root, a] : area)
        if (a > largest || (a == largest && root < outside)) outside = root, largest = a;

    std::vector<std::uint32_t> faces;
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        if (band[f] || (area.count(side[f]) && side[f] != outside)) faces.push_back(f);
    return faces;
}

}  // namespace fabsynth
