// SPDX-License-Identifier: MIT
#pragma once
/// @file topology_cut.hpp  The topology cut (filigree-synthesis.md §4.5) of a pattern on a
/// surface: topology_cut.hpp's four phases with every skeleton kept in its own local
/// parameterization (topology_cut_in_frames).
///
/// Usage:
///   std::vector<surface_skeleton> sk = ...;            // skeleton_on_surface(s, i) per instance
///   auto report = fabsynth::filigree::topology_cut_on_surface(s, sk, {});
///
/// How: instance b's skeleton enters instance a's frame by the rigid motion that takes b's placed
/// skeleton in b's own picture onto b's placed skeleton in a's picture (both are the element
/// placed rigidly, so a least-squares fit is exact up to rounding). The connected pairs are those
/// of the pattern graph (surface_space::connectivity, i < j, found in i's picture), each cut in
/// the picture of its lower id; strips of a < b touch when they touch in a's picture, for every b
/// that a's picture holds. So the connectivity that the cut keeps is the pattern's over the whole
/// surface, while every geometric test runs in one local picture. Split vertices are located on
/// the surface through their instance's own map; one that falls where the map has no face (a
/// hole of the region or a left-out fold) loses its edges (counted).
#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/filigree/surface/space.hpp"
#include "fabsynth/filigree/synthesis.hpp"
#include "fabsynth/filigree/topology_cut.hpp"
#include "fabsynth/geometry/rigid_motion.hpp"

namespace fabsynth::filigree {

/// One instance's skeleton on the surface.
struct surface_skeleton {
    std::vector<surface_point> vertices;  ///< where each skeleton vertex lies (absent ones: face = UINT32_MAX)
    std::vector<double> widths;           ///< strip width per vertex (mm)
    std::vector<skeleton_edge> edges;     ///< edges with both ends on the surface
    std::vector<vec2> picture;            ///< the vertices in the instance's own map (mm)
};

/// What topology_cut_on_surface did: the cut's counts, and the split vertices that could not be
/// located on the surface (their edges were dropped).
struct surface_cut_report {
    topology_cut_report cut;
    std::size_t vertices_off_surface = 0;
};

/// The topology cut of the skeletons of s's instances, in place (see the file comment).
/// @param s          the pattern space the skeletons come from (same instances)
/// @param skeletons  one per instance of s (skeleton_on_surface); edited: split vertices appended,
///                   cut edges removed
/// @param opt        thresholds and weights of §4.5 (mm)
/// Throws invalid_input when the skeleton count is not s.size(), and as topology_cut.
inline surface_cut_report topology_cut_on_surface(const surface_space& s, std::vector<surface_skeleton>& skeletons,
                                                  const topology_cut_options& opt = {}) {
    if (skeletons.size() != s.size())
        throw invalid_input("topology_cut_on_surface: " + std::to_string(skeletons.size()) + " skeletons for " + std::to_string(s.size()) +
                            " instances");
    const std::size_t n = s.size();
    std::vector<surface_space::view_type> views(n);
    parallel_for(0, n, [&](std::size_t i) { views[i] = s.view(i); });
    // poses[a]: (b, where b's own frame lies in a's) for every other instance b of a's picture
    std::vector<std::vector<std::pair<std::uint32_t, rigid_motion2>>> poses(n);
    parallel_for(0, n, [&](std::size_t a) {
        const auto& v = views[a];
        for (std::size_t k = 0; k < v.state().size(); ++k) {
            const std::uint32_t b = v.global(k);
            if (b == a) continue;
            poses[a].emplace_back(b, fit_rigid_motion(skeletons[b].picture, v.state().geometry()[k].vertices));
        }
    });
    instance_frames frames;
    frames.pose = [&](std::uint32_t a, std::uint32_t b) -> std::optional<rigid_motion2> {
        const auto& list = poses[a];
        const auto it = std::lower_bound(list.begin(), list.end(), b, [](const auto& e, std::uint32_t x) { return e.first < x; });
        if (it == list.end() || it->first != b) return std::nullopt;
        return it->second;
    };
    frames.neighbours = [&](std::uint32_t a) {
        std::vector<std::uint32_t> out;
        for (const auto& [b, m] : poses[a]) out.push_back(b);
        return out;
    };

    std::vector<graph::skeleton_graph<vec2>> graphs(n);
    for (std::size_t i = 0; i < n; ++i) {
        const surface_skeleton& sk = skeletons[i];
        for (std::size_t v = 0; v < sk.picture.size(); ++v) graphs[i].add_vertex(sk.picture[v], sk.widths[v]);
        for (const skeleton_edge& e : sk.edges) graphs[i].add_edge(e[0], e[1]);
    }
    const auto pairs = connected_pairs(s);

    surface_cut_report report;
    report.cut = topology_cut_in_frames(graphs, pairs, frames, opt);

    for (std::size_t i = 0; i < n; ++i) {
        const auto& g = graphs[i];
        surface_skeleton& sk = skeletons[i];
        for (std::size_t v = sk.picture.size(); v < g.num_vertices(); ++v) {  // split vertices, on edges of i
            const vec2 q = g.position(static_cast<graph::vertex_id>(v));
            const auto at = views[i].patch().locate(q);
            const bool on = at && s.region().contains(at->face);
            sk.vertices.push_back(on ? *at : surface_point{UINT32_MAX, {0, 0, 0}});
            sk.picture.push_back(q);
            sk.widths.push_back(g.width(static_cast<graph::vertex_id>(v)));
            report.vertices_off_surface += !on;
        }
        sk.edges.clear();
        for (graph::edge_id e = 0; e < g.edge_slots(); ++e) {
            if (!g.edge_alive(e)) continue;
            const auto [a, b] = g.endpoints(e);
            if (sk.vertices[a].face != UINT32_MAX && sk.vertices[b].face != UINT32_MAX) sk.edges.push_back({a, b});
        }
    }
    return report;
}

}  // namespace fabsynth::filigree
