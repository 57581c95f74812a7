// SPDX-License-Identifier: MIT
#pragma once
/// @file reconstruct.hpp  Reconstruction of a filigree on a base surface
/// (filigree-synthesis.md §6.1 baking, §6.2 printable mesh): the strips of every instance, drawn in
/// its own local parameterization, baked into the faces of the base mesh (surface/bake.hpp's
/// bake_per_face: per face the union of every instance's strips there, clipped to the face,
/// triangulated and lifted), then thickened into a watertight solid (surface/offset.hpp).
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

/// Instance i's strips per face of its map, in face frames (see the file comment).
/// @param sk  instance i's skeleton (skeleton_on_surface(s, i))
[[nodiscard]] inline std::vector<face_contours> instance_contours(const surface_space& s, std::size_t i, const surface_skeleton& sk,
                                                                  double arc_tolerance = 0.01) {
    graph::skeleton_graph<vec2> g;
    for (std::size_t v = 0; v < sk.picture.size(); ++v) g.add_vertex(sk.picture[v], sk.widths[v]);
    for (const skeleton_edge& e : sk.edges) g.add_edge(e[0], e[1]);
    const std::vector<polygon_with_holes> strips = strip_outline(std::span(&g, 1), arc_tolerance);
    std::vector<face_contours> out;
    if (strips.empty()) return out;
    const auto v = s.view(i);
    const local_patch& P = v.patch();
    const triangle_mesh& m = s.patcher().mesh();
    box2 reach = bounding_box(strips);
    const box2 sb = reach;
    for (const vec2& q : P.uv) reach.extend(q);
    const clip_grid grid = clip_grid::for_bounds(reach);
    for (std::size_t t = 0; t < P.faces.size(); ++t) {
        const std::uint32_t f = P.faces[t];
        if (!s.region().contains(f)) continue;
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
