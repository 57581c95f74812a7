// SPDX-License-Identifier: MIT
#pragma once
/// @file connection.hpp  SMOOTHCONNECTION of Algorithm 1 for a pattern (filigree-synthesis.md
/// §4.3.2): an instance is deformed (ffd.hpp: bicubic Bezier FFD, eqs. 10-14; contact.hpp: where to touch) into tangent
/// contact with one neighbour where the two skeletons cross twice close together or pass at a
/// narrow gap (Fig. 6), keeping its contacts with its other neighbours fixed.
///
/// Usage:
///   placement_options po;
///   po.smooth_connection = fabsynth::filigree::make_smooth_connection(0.15);
///   auto fixed_up = fabsynth::filigree::reconnect(state, i, moved, j, keep, 2.4, 0.15);  // boosting, §4.4
///
/// Per call (one instance i): neighbours j in id order; the fixed control points are, for every
/// other neighbour k, the vertex of i nearest to k's skeleton when it is within one strip width
/// (the paper's "intersections with other neighbouring elements that do not need to be changed"),
/// at most `max_fixed` of them (the FFD has 16 control points). The first deformation whose
/// distortion is below sigma_d (Table 1: 0.13-0.17), that keeps every neighbour of i and does not
/// raise i's matching energy, is returned; without one, a tangent contact with the domain boundary
/// is tried the same way (boundary_contact, §7.2). Contact thresholds scale with the strip width w: two
/// crossings closer than 3 w, a gap narrower than 1.5 w. The energy condition is added here (the
/// paper accepts on distortion alone): placement keeps the pattern matching energy from rising, so a
/// deformation that raised it would only be undone.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "fabsynth/core/box.hpp"

#include "fabsynth/filigree/contact.hpp"
#include "fabsynth/filigree/placement.hpp"

namespace fabsynth::filigree {

namespace detail::connection {

// Vertex of `p` nearest to any of `q`, with its distance.
[[nodiscard]] inline std::pair<std::uint32_t, double> nearest_vertex(std::span<const vec2> p, std::span<const vec2> q) {
    std::pair<std::uint32_t, double> best{0, std::numeric_limits<double>::infinity()};
    for (std::uint32_t a = 0; a < p.size(); ++a)
        for (const vec2& b : q) {
            const double d = glm::distance(p[a], b);
            if (d < best.second) best = {a, d};
        }
    return best;
}

// The fixed control points of a deformation of i (§4.3.2: "intersection points with other
// neighbouring elements that do not need to be changed"): per neighbour k in `keep` other than
// `except`, the vertex of g nearest to k's skeleton when it is within `reach`; at most max_fixed.
[[nodiscard]] inline std::vector<std::uint32_t> fixed_contacts(const pattern_state& s, const placed& g, std::span<const std::uint32_t> keep,
                                                               std::size_t except, double reach, std::size_t max_fixed) {
    std::vector<std::uint32_t> fixed;
    for (const std::uint32_t k : keep) {
        if (k == except || fixed.size() >= max_fixed) continue;
        const auto [v, d] = nearest_vertex(g.vertices, s.geometry()[k].vertices);
        if (d <= reach) fixed.push_back(v);
    }
    return fixed;
}

}  // namespace detail::connection

/// Boundary-aware synthesis (§7.2: "encourage pattern elements next to the domain boundary to have
/// tangential contact with boundary curves ... by applying ... limited deformation"): instance i
/// deformed into tangent contact with the domain boundary, its contacts with its neighbours fixed;
/// returned if the distortion is below sigma_d, every neighbour is kept and the local energy (whose
/// Theta term scores the alignment with the boundary) is at most `before`.
[[nodiscard]] inline std::optional<instance> boundary_contact(const pattern_state& s, std::size_t i, std::span<const std::uint32_t> nbrs,
                                                             const contact_options& copt, double sigma_d, double before) {
    const instance& cur = s.instances()[i];
    const element& e = s.classes()[cur.cls];
    const placed& g = s.geometry()[i];
    const box2 near = g.box.inflated(copt.max_gap + copt.max_intersection_gap);
    if (std::none_of(s.boundary_samples().begin(), s.boundary_samples().end(), [&](vec2 q) { return near.contains(q); }))
        return std::nullopt;  // far from the domain boundary
    const std::vector<std::uint32_t> fixed = detail::connection::fixed_contacts(s, g, nbrs, SIZE_MAX, e.median_width(), 12);
    std::optional<ffd_result> r;
    try {
        r = smooth_connection(g.vertices, e.edges, s.boundary_positions(), s.boundary_edges(), fixed, copt, {}, sigma_d);
    } catch (const solver_error&) {
        return std::nullopt;
    }
    if (!r) return std::nullopt;
    instance out = cur;
    for (std::size_t v = 0; v < out.shape.size(); ++v) out.shape[v] = to_local(cur, r->positions[v]);
    const placed ng = place(e, out);
    const std::vector<std::uint32_t> now = s.neighbours_of(ng, i);
    if (!std::includes(now.begin(), now.end(), nbrs.begin(), nbrs.end()) || s.local_energy(ng, now) > before) return std::nullopt;
    return out;
}

/// The smooth-connection hook of place_optimize (see the file comment).
[[nodiscard]] inline smooth_connection_fn make_smooth_connection(double sigma_d, std::size_t max_fixed = 12) {
    require_positive(sigma_d, "smooth connection: sigma_d");
    return [sigma_d, max_fixed](const pattern_state& s, std::size_t i) -> std::optional<instance> {
        namespace dc = detail::connection;
        const instance& cur = s.instances()[i];
        const element& e = s.classes()[cur.cls];
        const placed& g = s.geometry()[i];
        const std::vector<std::uint32_t> nbrs = s.neighbours_of(g, i);
        const double w = e.median_width();
        contact_options copt;
        copt.max_intersection_gap = 3 * w;
        copt.max_gap = 1.5 * w;
        const double before = s.local_energy(g, nbrs);
        for (const std::uint32_t j : nbrs) {
            const std::vector<std::uint32_t> fixed = dc::fixed_contacts(s, g, nbrs, j, w, max_fixed);
            const element& ej = s.classes()[s.instances()[j].cls];
            std::optional<ffd_result> r;
            try {
                r = smooth_connection(g.vertices, e.edges, s.geometry()[j].vertices, ej.edges, fixed, copt, {}, sigma_d);
            } catch (const solver_error&) {  // constraints the 4 x 4 patch cannot meet: no deformation
                continue;
            }
            if (!r) continue;
            instance out = cur;
            for (std::size_t v = 0; v < out.shape.size(); ++v) out.shape[v] = to_local(cur, r->positions[v]);
            const placed ng = place(e, out);
            const std::vector<std::uint32_t> now = s.neighbours_of(ng, i);
            if (!std::includes(now.begin(), now.end(), nbrs.begin(), nbrs.end())) continue;
            if (s.local_energy(ng, now) > before) continue;
            return out;
        }
        return boundary_contact(s, i, nbrs, copt, sigma_d, before);
    };
}

/// Reconnection by deformation (§4.4, learning phase: "we will enhance the connectivity by forcing
/// some nearby pairs of elements to be connected to each other using non-rigid deformation"):
/// instance i, about to be placed as `cand`, deformed (the narrow-gap case of Fig. 6, gaps up to
/// `max_gap` mm) into tangent contact with instance j of the current state, its contacts with its
/// neighbours `keep` (at cand) fixed. Returned if the distortion is below sigma_d and the deformed
/// instance reaches into j's covering region (overlapping(), the pattern's connectivity) while
/// keeping every instance of `keep` as a neighbour; nothing otherwise.
[[nodiscard]] inline std::optional<instance> reconnect(const pattern_state& s, std::size_t i, const instance& cand, std::uint32_t j,
                                                      std::span<const std::uint32_t> keep, double max_gap, double sigma_d) {
    require_positive(sigma_d, "reconnect: sigma_d");
    require_positive(max_gap, "reconnect: max_gap");
    const element& e = s.classes()[cand.cls];
    const placed g = place(e, cand);
    const placed& gj = s.geometry()[j];
    if (!g.box.inflated(max_gap).intersects(gj.box)) return std::nullopt;
    const std::vector<std::uint32_t> fixed = detail::connection::fixed_contacts(s, g, keep, j, e.median_width(), 12);
    contact_options copt;
    copt.max_gap = max_gap;
    copt.max_intersection_gap = 3 * e.median_width();
    std::optional<ffd_result> r;
    try {
        r = smooth_connection(g.vertices, e.edges, gj.vertices, s.classes()[s.instances()[j].cls].edges, fixed, copt, {}, sigma_d);
    } catch (const solver_error&) {  // constraints the 4 x 4 patch cannot meet
        return std::nullopt;
    }
    if (!r) return std::nullopt;
    instance out = cand;
    for (std::size_t v = 0; v < out.shape.size(); ++v) out.shape[v] = to_local(cand, r->positions[v]);
    const placed ng = place(e, out);
    if (!overlapping(ng, gj)) return std::nullopt;
    const std::vector<std::uint32_t> now = s.neighbours_of(ng, i);
    if (!std::includes(now.begin(), now.end(), keep.begin(), keep.end())) return std::nullopt;
    return out;
}

}  // namespace fabsynth::filigree
