// SPDX-License-Identifier: MIT
#pragma once
/// @file thin_features.hpp  "Enlarging small features" (structurally-sound-patterns.md §6.2.1): a
/// geodesic skeleton of the solid pattern, pruned, dilated by the minimal printable radius within
/// the shell and united with the pattern.
///
/// Usage:
///   auto added = fabsynth::surface_pattern::enlarge_thin_features(g_surface, solid, 0.4);   // solid updated
///
/// Method, on the 26-neighbour graph G_surface of the shell voxels (mm weights):
///  1. depth: d(v) = geodesic distance, inside the solid voxels, to the nearest boundary voxel (a
///     solid voxel with an empty shell neighbour), by one multi-source Dijkstra (graph/);
///  2. skeleton: the solid voxels where the depth stops growing at unit rate, i.e. no solid neighbour
///     w has d(w) >= d(v) + 0.5 w(v, w): the ridges and local maxima of d. This replaces the
///     paper's watershed of the graph with connected maxima (Haumont et al. 2003): both keep the
///     voxels farthest from the boundary across each feature; ours needs no region merging;
///  3. pruning: skeleton voxels with at most one skeleton neighbour are removed repeatedly, for as
///     many rounds as the minimal radius spans voxels, so spurs created by boundary noise (shorter
///     than the radius) disappear while the axis of each feature stays; small loops are left, as
///     their dilation is inside the pattern anyway;
///  4. dilation: every shell voxel within min_radius_mm (geodesic in G_surface) of the skeleton
///     becomes solid. Where a feature is already wider than the radius nothing changes.
/// Voxels known to be printable (optional `printable` flags: the reinforcement bridges of §5.2, laid
/// as their voxel path dilated by at least this radius, i.e. already a skeleton dilated by it) are
/// left out of the skeleton. The depth test cannot see that: a bridge two or three voxels wide on a
/// staircase path has no voxel without an empty 26-neighbour, so all of it would read as skeleton
/// and be widened by the radius once more (on the bunny with hooks at 256^3 that added about 6 600
/// voxels to 15 000 bridge voxels).
/// Deterministic (graph/ Dijkstra tie rules, index-order passes).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/graph/csr_graph.hpp"
#include "fabsynth/graph/shortest_paths.hpp"

namespace fabsynth::surface_pattern {

/// What enlarge_thin_features did.
struct thin_feature_report {
    std::size_t skeleton_voxels = 0;  ///< after pruning
    std::size_t added_voxels = 0;     ///< shell voxels made solid (state 4)
};

/// See the file comment. `g` is G_surface (vertex = shell voxel), `solid` one 0/1 flag per vertex
/// (updated), `spacing_mm` the voxel size (for the pruning rounds). `added` (optional, same size)
/// gets 1 where a voxel was added; `printable` (optional, same size) flags voxels kept out of the
/// skeleton (see the file comment). Throws invalid_input for sizes that do not match or a radius
/// that is not finite and >= 0 (0 changes nothing).
inline thin_feature_report enlarge_thin_features(const graph::csr_graph<>& g, std::vector<std::uint8_t>& solid, double min_radius_mm,
                                                 double spacing_mm, std::vector<std::uint8_t>* added = nullptr,
                                                 const std::vector<std::uint8_t>* printable = nullptr) {
    const std::size_t n = g.num_vertices();
    if (solid.size() != n) throw invalid_input("enlarge_thin_features: one flag per shell voxel is needed");
    if (printable && printable->size() != n) throw invalid_input("enlarge_thin_features: one printable flag per shell voxel is needed");
    if (!(std::isfinite(min_radius_mm) && min_radius_mm >= 0)) throw invalid_input("enlarge_thin_features: radius must be finite and >= 0");
    if (!(spacing_mm > 0)) throw invalid_input("enlarge_thin_features: spacing must be > 0");
    if (added) added->assign(n, 0);
    thin_feature_report rep;
    if (min_radius_mm == 0) return rep;
    // 1. depth inside the solid
    std::vector<graph::vertex_id> boundary;
    for (std::size_t v = 0; v < n; ++v) {
        if (!solid[v]) continue;
        for (graph::vertex_id w : g.neighbours(static_cast<graph::vertex_id>(v)))
            if (!solid[w]) {
                boundary.push_back(static_cast<graph::vertex_id>(v));
                break;
            }
    }
    if (boundary.empty()) return rep;  // no solid voxel, or the whole shell is solid
    const graph::shortest_path_forest depth = graph::dijkstra_forest(g, boundary, solid);
    // 2. ridges of the depth
    std::vector<std::uint8_t> skeleton(n, 0);
    for (std::size_t v = 0; v < n; ++v) {
        if (!solid[v] || (printable && (*printable)[v])) continue;
        bool ridge = true;
        const auto vid = static_cast<graph::vertex_id>(v);
        for (graph::arc_id e = g.edge_begin(vid); e < g.edge_end(vid); ++e) {
            const graph::vertex_id w = g.target(e);
            if (solid[w] && depth.distance[w] >= depth.distance[v] + 0.5 * g.weight(e)) {
                ridge = false;
                break;
            }
        }
        skeleton[v] = ridge ? 1 : 0;
    }
    // 3. prune spurs shorter than the radius
    const int rounds = static_cast<int>(std::ceil(min_radius_mm / spacing_mm));
    for (int r = 0; r < rounds; ++r) {
        std::vector<graph::vertex_id> ends;
        for (std::size_t v = 0; v < n; ++v) {
            if (!skeleton[v]) continue;
            int k = 0;
            for (graph::vertex_id w : g.neighbours(static_cast<graph::vertex_id>(v))) k += skeleton[w];
            if (k <= 1) ends.push_back(static_cast<graph::vertex_id>(v));
        }
        if (ends.empty()) break;
        for (graph::vertex_id v : ends) skeleton[v] = 0;
    }
    std::vector<graph::vertex_id> axis;
    for (std::size_t v = 0; v < n; ++v)
        if (skeleton[v]) axis.push_back(static_cast<graph::vertex_id>(v));
    rep.skeleton_voxels = axis.size();
    if (axis.empty()) return rep;
    // 4. dilation along the surface
    const graph::shortest_path_forest near = graph::dijkstra_forest(g, axis);
    for (std::size_t v = 0; v < n; ++v)
        if (!solid[v] && near.distance[v] <= min_radius_mm) {
            solid[v] = 1;
            ++rep.added_voxels;
            if (added) (*added)[v] = 1;
        }
    return rep;
}

}  // namespace fabsynth::surface_pattern
