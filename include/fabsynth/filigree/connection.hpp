// SPDX-License-Identifier: MIT
#pragma once
/// @file connection.hpp  SMOOTHCONNECTION of Algorithm 1 for a pattern (filigree-synthesis.md
/// §4.3.2): an instance is deformed (deformation.hpp: bicubic Bezier FFD, eqs. 10-14) into tangent
/// contact with one neighbour where the two skeletons cross twice close together or pass at a
/// narrow gap (Fig. 6), keeping its contacts with its other neighbours fixed.
///
/// Usage:
///   placement_options po;
///   po.smooth_connection = fabsynth::filigree::make_smooth_connection(0.15);
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
#include <limits>
#include <optional>
#include <vector>

#include "fabsynth/core/box.hpp"

#include "fabsynth/filigree/deformation.hpp"
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
    const box2& b = g.box;
    const box2& d = s.domain().bounds;
    const double reach = copt.max_gap + copt.max_intersection_gap;
    if (b.lo.x - d.lo.x > reach && b.lo.y - d.lo.y > reach && d.hi.x - b.hi.x > reach && d.hi.y - b.hi.y > reach && s.domain().region.size() == 1 &&
        s.domain().region[0].holes.empty())
        return std::nullopt;  // far from the outer boundary of a domain without holes
    std::vector<std::uint32_t> fixed;
    for (const std::uint32_t k : nbrs) {
        if (fixed.size() >= 12) break;
        const auto [v, dist] = detail::connection::nearest_vertex(g.vertices, s.geometry()[k].vertices);
        if (dist <= e.median_width()) fixed.push_back(v);
    }
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
            std::vector<std::uint32_t> fixed;
            for (const std::uint32_t k : nbrs) {
                if (k == j || fixed.size() >= max_fixed) continue;
                const auto [v, d] = dc::nearest_vertex(g.vertices, s.geometry()[k].vertices);
                if (d <= w) fixed.push_back(v);
            }
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

}  // namespace fabsynth::filigree
