// SPDX-License-Identifier: MIT
#pragma once
/// @file reconstruct.hpp  Reconstruction of a filigree on a base surface
/// (filigree-synthesis.md §6.1 baking, §6.2 printable mesh): the strips of every instance, drawn in
/// its own local parameterization, baked into the faces of the base mesh (surface/bake.hpp's
/// bake_per_face: per face the union of every instance's strips there, clipped to the face,
/// triangulated and lifted), then thickened into a watertight solid (surface/offset.hpp).
///
/// Bridges: bridge_contours gives the strip that joins a piece cut off from the rest (structure.hpp
/// keeps one piece and bridges the others to it, as the planar path does).
///
/// Usage:
///   auto r  = fabsynth::filigree::synthesize_on_surface(classes, weights, region, field, opt);
///   fabsynth::filigree::surface_space s(classes, r.instances, field, region);
///   fabsynth::triangle_mesh mb = fabsynth::filigree::bake_pattern(s, r.skeletons);     // M_b
///   fabsynth::triangle_mesh solid = fabsynth::thicken_surface(mb, 1.0, {.cell = 0.25});
///
/// An instance's strips (reconstruct.hpp's strip_outline of its skeleton in its map) reach the
/// faces of its map that are in the region; there they are clipped to each face's (u, v) triangle
/// in the map and carried to the face's own frame by the affine map between the two triangles, so
/// strips of different instances meet in the face frames, where they are united. Parts of strips
/// outside the region are dropped (the 2D path clips the strips to the domain the same way).
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/filigree/reconstruct.hpp"
#include "fabsynth/filigree/surface/space.hpp"
#include "fabsynth/filigree/surface/synthesis.hpp"
#include "fabsynth/surface/bake.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/graph/skeleton_graph.hpp"

namespace fabsynth::filigree {

/// Planar `strips` (polygons in the (u, v) of patch P, mm) per face of P that is in `region`,
/// clipped to the face's (u, v) triangle and carried to the face's own frame (face_frame) by the
/// affine map between the two triangles (see the file comment).
[[nodiscard]] inline std::vector<face_contours> patch_contours(const local_patch& P, const triangle_mesh& m, const surface_region& region,
                                                               const std::vector<polygon_with_holes>& strips) {
    std::vector<face_contours> out;
    if (strips.empty()) return out;
    box2 reach = bounding_box(strips);
    const box2 sb = reach;
    for (const vec2& q : P.uv) reach.extend(q);
    const clip_grid grid = clip_grid::for_bounds(reach);
    for (std::size_t t = 0; t < P.faces.size(); ++t) {
        const std::uint32_t f = P.faces[t];
        if (!region.contains(f)) continue;
        const vec2 a = P.uv[P.corners[t][0]], b = P.uv[P.corners[t][1]], c = P.uv[P.corners[t][2]];
        box2 tb;
        tb.extend(a).extend(b).extend(c);
        if (!tb.intersects(sb) || !(std::abs(orient2d(a, b, c)) > 0)) continue;
        const ring2 tri = orient2d(a, b, c) > 0 ? ring2{a, b, c} : ring2{a, c, b};
        std::vector<polygon_with_holes> piece = polygon_intersection({polygon_with_holes{tri, {}}}, strips, grid);
        if (piece.empty()) continue;
        const face_frame fr = face_frame::of(m, f);
        const auto& fc = m.faces[f];
        const vec2 A = fr.to_2d(m.vertices[fc[0]]), B = fr.to_2d(m.vertices[fc[1]]), C = fr.to_2d(m.vertices[fc[2]]);
        auto carry = [&](ring2& r) {
            for (vec2& q : r) {
                const vec3 l = barycentric(q, a, b, c);
                q = l.x * A + l.y * B + l.z * C;
            }
        };
        for (polygon_with_holes& p : piece) {
            carry(p.outer);
            for (ring2& h : p.holes) carry(h);
        }
        out.push_back({f, std::move(piece)});
    }
    return out;
}

/// Instance i's strips per face of its map, in face frames (see the file comment).
/// @param sk  instance i's skeleton (skeleton_on_surface(s, i))
[[nodiscard]] inline std::vector<face_contours> instance_contours(const surface_space& s, std::size_t i, const surface_skeleton& sk,
                                                                  double arc_tolerance = 0.01) {
    graph::skeleton_graph<vec2> g;
    for (std::size_t v = 0; v < sk.picture.size(); ++v) g.add_vertex(sk.picture[v], sk.widths[v]);
    for (const skeleton_edge& e : sk.edges) g.add_edge(e[0], e[1]);
    const std::vector<polygon_with_holes> strips = strip_outline(std::span(&g, 1), arc_tolerance);
    if (strips.empty()) return {};
    return patch_contours(s.view(i).patch(), s.patcher().mesh(), s.region(), strips);
}

/// A bridge strip on the surface, per face in face frames: `width` mm wide with round ends, along
/// the geodesic from `a` toward `b` (the radial line to b in the exponential map at a, so its length
/// is the geodesic distance the map measures), clipped to the region. Empty when b lies farther than
/// `max_length` mm from a along the surface, or where the map does not reach (a fold, a hole).
[[nodiscard]] inline std::vector<face_contours> bridge_contours(const surface_patcher& sp, const surface_region& region, const surface_point& a,
                                                                const surface_point& b, double width, double max_length) {
    const triangle_mesh& m = sp.mesh();
    const vec3 n = sp.face_normal(a.face);
    if (n == vec3(0.0)) return {};
    vec3 dir = sp.position(b) - sp.position(a);
    dir -= glm::dot(dir, n) * n;
    if (!(glm::length(dir) > 1e-6 * width)) dir = m.vertices[m.faces[a.face][1]] - m.vertices[m.faces[a.face][0]];  // any tangent
    const local_patch P = sp.patch(a, dir, max_length + width);
    const std::optional<vec2> to = P.uv_of(b);
    if (!to || glm::length(*to) > max_length) return {};
    // a contact at a point (a hinge) still gets a round joint of the strip width
    const vec2 end = glm::length(*to) > 1e-3 * width ? *to : vec2(1e-3 * width, 0);
    return patch_contours(P, m, region, stroke_outline({{vec2(0, 0), end}}, 0.5 * width));
}

/// The baked mesh M_b of the pattern (see the file comment). skeletons: one per instance of s
/// (synthesize_on_surface's result.skeletons with s built from its instances).
[[nodiscard]] inline triangle_mesh bake_pattern(const surface_space& s, std::span<const surface_skeleton> skeletons, double arc_tolerance = 0.01) {
    std::vector<std::vector<face_contours>> parts(s.size());
    parallel_for(0, s.size(), [&](std::size_t i) { parts[i] = instance_contours(s, i, skeletons[i], arc_tolerance); });
    std::vector<face_contours> all;
    for (auto& p : parts) all.insert(all.end(), std::make_move_iterator(p.begin()), std::make_move_iterator(p.end()));
    return bake_per_face(s.patcher().mesh(), all);
}

}  // namespace fabsynth::filigree
