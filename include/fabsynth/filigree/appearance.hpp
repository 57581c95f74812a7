// SPDX-License-Identifier: MIT
#pragma once
/// @file appearance.hpp  How a synthesized filigree reads (filigree-synthesis.md §3.4): the paper
/// wants neighbouring elements joined by tangent contacts or by partial overlaps of matching
/// shapes (Fig. 4), never by strips that cut across each other. measure_appearance counts, on the
/// final skeletons (after the topology cut):
///  - transversal crossings: points where a strip of one instance crosses a strip of another at
///    more than `min_crossing_angle_deg` (folded into [0, 90] degrees) and *both* strips go on past
///    the point, each by at least the strip width there along its own skeleton (a strip that ends
///    on another one, the T-junction the topology cut leaves, is a contact, not a crossing; a
///    crossing at a small angle is a near-tangent contact). Hits of the same two instances within
///    one strip width of a counted crossing are the same crossing.
///  - the overlap area fraction: the area covered by the strips of two or more instances over the
///    area covered by any strip (rasterized at a quarter of the narrowest strip width, at most
///    about 16 M pixels), inside the region;
///  - free ends: valence-1 skeleton vertices whose strip end touches no strip of another instance
///    (distance > half the sum of the two widths), inside the region.
/// Everything is counted inside `inside(point)` (the domain: what the clipped print keeps).
///
/// Usage:
///   auto a = fabsynth::filigree::measure_appearance(result.skeletons, [&](vec2 p) { return domain.contains(p); });
///   a.crossings_per_instance;  a.overlap_area_fraction;  a.free_ends;
///
/// The paper reports no such figures; they are what the issue tracker measured by eye and by an
/// independent raster skeleton of the SVGs, made part of every result so a change can be judged.
/// Deterministic; O(sum over instance pairs with meeting boxes of their edge pairs in common grid
/// cells) for the crossings, O(ends x edges near them) for the free ends, O(pixels) for the area.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/filigree/reconstruct.hpp"
#include "fabsynth/filigree/topology_cut.hpp"
#include "fabsynth/geometry/raster.hpp"
#include "fabsynth/geometry/segment.hpp"
#include "fabsynth/graph/shortest_paths.hpp"
#include "fabsynth/graph/skeleton_graph.hpp"

namespace fabsynth::filigree {

struct appearance_options {
    double min_crossing_angle_deg = 30.0;  ///< crossings at a smaller angle are near-tangent contacts
};

/// What measure_appearance counts (see the file comment).
struct appearance_report {
    std::size_t instances = 0;              ///< skeletons with at least one live edge
    std::size_t transversal_crossings = 0;
    double crossings_per_instance = 0.0;    ///< transversal_crossings / instances (0 without instances)
    double overlap_area_fraction = 0.0;     ///< area under >= 2 instances / area under >= 1, in [0, 1]
    std::size_t free_ends = 0;
    std::vector<vec2> crossing_points;      ///< where the transversal crossings are (mm), in instance-pair order
};

namespace detail::appearance {

using skeleton = graph::skeleton_graph<vec2>;

// Per vertex: the distance along the live edges of g to the nearest valence-1 vertex (+inf if none).
[[nodiscard]] inline std::vector<double> distance_to_ends(const skeleton& g) {
    std::vector<graph::vertex_id> ends;
    for (graph::vertex_id v = 0; v < g.num_vertices(); ++v)
        if (g.valence(v) == 1) ends.push_back(v);
    if (ends.empty()) return std::vector<double>(g.num_vertices(), std::numeric_limits<double>::infinity());
    return graph::dijkstra_forest(g.to_csr(), ends).distance;
}

// Distance along g from the point at parameter t of edge e to the nearest end.
[[nodiscard]] inline double end_distance_at(const skeleton& g, const std::vector<double>& d, graph::edge_id e, double t) {
    const auto [u, v] = g.endpoints(e);
    const double l = g.length(e);
    return std::min(d[u] + t * l, d[v] + (1 - t) * l);
}

[[nodiscard]] inline double width_at(const skeleton& g, graph::edge_id e, double t) {
    const auto [u, v] = g.endpoints(e);
    return g.width(u) + t * (g.width(v) - g.width(u));
}

[[nodiscard]] inline box2 live_box(const skeleton& g) {
    box2 b;
    for (graph::edge_id e = 0; e < g.edge_slots(); ++e)
        if (g.edge_alive(e)) {
            const auto [u, v] = g.endpoints(e);
            b.extend(g.position(u)).extend(g.position(v));
        }
    return b;
}

}  // namespace detail::appearance

/// Measures the appearance of the skeletons (world mm, one per instance, widths = strip widths)
/// restricted to `inside` (a callable bool(vec2), e.g. the domain's contains). See the file comment.
template <class Inside>
[[nodiscard]] appearance_report measure_appearance(std::span<const graph::skeleton_graph<vec2>> skeletons, Inside&& inside,
                                                   const appearance_options& opt = {}) {
    namespace da = detail::appearance;
    namespace dt = detail::topocut;
    if (!(opt.min_crossing_angle_deg >= 0 && opt.min_crossing_angle_deg <= 90))
        throw invalid_input("measure_appearance: min_crossing_angle_deg must be in [0, 90]");
    appearance_report r;
    const std::size_t n = skeletons.size();
    std::vector<box2> boxes(n);
    std::vector<std::vector<double>> to_end(n);
    double min_width = std::numeric_limits<double>::infinity(), max_width = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const auto& g = skeletons[i];
        if (g.num_edges() == 0) continue;
        ++r.instances;
        boxes[i] = da::live_box(g);
        to_end[i] = da::distance_to_ends(g);
        for (graph::edge_id e = 0; e < g.edge_slots(); ++e)
            if (g.edge_alive(e)) {
                const auto [u, v] = g.endpoints(e);
                for (const double w : {g.width(u), g.width(v)})
                    if (w > 0) min_width = std::min(min_width, w), max_width = std::max(max_width, w);
            }
    }
    if (r.instances == 0) return r;
    const double cos_min = std::cos(opt.min_crossing_angle_deg * std::numbers::pi / 180.0);

    // Transversal crossings.
    for (std::size_t a = 0; a < n; ++a) {
        if (skeletons[a].num_edges() == 0) continue;
        for (std::size_t b = a + 1; b < n; ++b) {
            if (skeletons[b].num_edges() == 0 || !boxes[a].intersects(boxes[b])) continue;
            const auto& P = skeletons[a];
            const auto& Q = skeletons[b];
            std::vector<vec2> counted;
            for (const dt::crossing_hit& h : dt::find_crossing_hits(P, Q)) {
                if (!inside(h.point)) continue;
                const auto [p0, p1] = P.endpoints(h.edge_p);
                const auto [q0, q1] = Q.endpoints(h.edge_q);
                const vec2 dp = P.position(p1) - P.position(p0), dq = Q.position(q1) - Q.position(q0);
                const double lp = glm::length(dp), lq = glm::length(dq);
                if (!(lp > 0 && lq > 0)) continue;
                if (std::abs(glm::dot(dp, dq)) / (lp * lq) > cos_min) continue;  // near-tangent
                const double w = std::max(da::width_at(P, h.edge_p, h.t_p), da::width_at(Q, h.edge_q, h.t_q));
                if (da::end_distance_at(P, to_end[a], h.edge_p, h.t_p) < w || da::end_distance_at(Q, to_end[b], h.edge_q, h.t_q) < w)
                    continue;  // one strip ends on the other: a contact
                if (std::any_of(counted.begin(), counted.end(), [&](vec2 c) { return glm::distance(c, h.point) < w; })) continue;
                counted.push_back(h.point);
            }
            r.transversal_crossings += counted.size();
            r.crossing_points.insert(r.crossing_points.end(), counted.begin(), counted.end());
        }
    }
    r.crossings_per_instance = static_cast<double>(r.transversal_crossings) / static_cast<double>(r.instances);

    // Free ends.
    for (std::size_t a = 0; a < n; ++a) {
        const auto& P = skeletons[a];
        for (graph::vertex_id v = 0; v < P.num_vertices(); ++v) {
            if (P.valence(v) != 1 || !inside(P.position(v))) continue;
            const vec2 p = P.position(v);
            const double wp = P.width(v);
            bool touches = false;
            for (std::size_t b = 0; b < n && !touches; ++b) {
                if (b == a || skeletons[b].num_edges() == 0 || !boxes[b].inflated(0.5 * (wp + max_width)).contains(p)) continue;
                const auto& Q = skeletons[b];
                for (graph::edge_id e = 0; e < Q.edge_slots() && !touches; ++e) {
                    if (!Q.edge_alive(e)) continue;
                    const auto [u, w] = Q.endpoints(e);
                    const double t = segment_closest_parameter(p, Q.position(u), Q.position(w));
                    const double reach = 0.5 * (wp + da::width_at(Q, e, t));
                    const vec2 d = p - (Q.position(u) + t * (Q.position(w) - Q.position(u)));
                    touches = glm::dot(d, d) <= reach * reach;
                }
            }
            if (!touches) ++r.free_ends;
        }
    }

    // Overlap area: per pixel, the number of instances whose strips cover its centre.
    if (!(min_width > 0 && std::isfinite(min_width))) return r;
    box2 all;
    for (std::size_t i = 0; i < n; ++i)
        if (skeletons[i].num_edges() > 0) all.extend(boxes[i].inflated(max_width));
    double px = 0.25 * min_width;
    const vec2 size = all.size();
    while ((size.x / px) * (size.y / px) > 16.0e6) px *= 1.5;
    const raster_grid grid{all.lo, px, static_cast<int>(std::ceil(size.x / px)), static_cast<int>(std::ceil(size.y / px))};
    std::vector<std::uint16_t> count(static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height), 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (skeletons[i].num_edges() == 0) continue;
        polygon_rasterizer raster;
        for (const auto& p : strip_outline(skeletons.subspan(i, 1))) raster.add_polygon(p);
        raster.for_each_run(grid, [&](int j, int i0, int i1) {
            for (int c = i0; c < i1; ++c) {
                auto& k = count[static_cast<std::size_t>(j) * static_cast<std::size_t>(grid.width) + static_cast<std::size_t>(c)];
                if (k < UINT16_MAX) ++k;
            }
        });
    }
    std::size_t any = 0, several = 0;
    for (int j = 0; j < grid.height; ++j)
        for (int c = 0; c < grid.width; ++c) {
            const std::uint16_t k = count[static_cast<std::size_t>(j) * static_cast<std::size_t>(grid.width) + static_cast<std::size_t>(c)];
            if (k == 0 || !inside(grid.origin + px * vec2(c + 0.5, j + 0.5))) continue;
            ++any;
            several += k >= 2;
        }
    r.overlap_area_fraction = any ? static_cast<double>(several) / static_cast<double>(any) : 0.0;
    return r;
}

}  // namespace fabsynth::filigree
