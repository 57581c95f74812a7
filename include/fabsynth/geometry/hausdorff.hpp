// SPDX-License-Identifier: MIT
#pragma once
/// @file hausdorff.hpp  Hausdorff distance between triangle meshes with a certified upper bound:
/// how far a simplified, smoothed or otherwise rebuilt surface strays from the one it replaces.
///
/// Usage:
///   auto h = fabsynth::hausdorff_distance(raw, simplified, {.precision = 0.01});
///   // every point of each surface lies within h.upper mm of the other; some point is h.lower away
///
/// Method. d(p) = distance from p to the other surface is 1-Lipschitz, and every point of a
/// triangle with longest edge L lies within L / sqrt(3) of one of its corners (for barycentric
/// weights w, min_i |p - v_i|^2 <= sum_i w_i |p - v_i|^2 = sum_{i<j} w_i w_j |v_i - v_j|^2 <= L^2 / 3).
/// So sup over a triangle of d <= max over its corners of d + L / sqrt(3). Each triangle is split in
/// four at its edge midpoints until that bound is within `precision` of the corner maximum, or is
/// at most `stop_below` (a check against a tolerance needs to know no more than that). The result
/// is an interval [lower, upper] holding the true distance: lower is a distance attained at a
/// sample point, upper the largest bound. Samples per triangle grow as (L / precision)^2, or
/// (L / stop_below)^2 where the surfaces are close: a certificate costs about area / stop_below^2
/// queries, so checking a fine tolerance on a large surface is the expensive case.
///
/// Cost: one closest-point query (AABB tree, geometry/distance.hpp) per vertex and per split
/// midpoint; parallel over faces, and the result does not depend on the thread count.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth {

/// Options of the Hausdorff bound, mm.
struct hausdorff_options {
    double precision = 0.01;  ///< > 0: upper - lower <= precision unless the bound is below stop_below
    double stop_below = 0.0;  ///< >= 0: a triangle whose bound is below this is not refined further
    /// A triangle with a corner farther than this is not refined further: checking against a
    /// tolerance, one such corner already decides (then upper is only a bound, not within precision)
    double abort_above = std::numeric_limits<double>::infinity();
};

/// A Hausdorff distance known to lie in [lower, upper], mm.
struct hausdorff_interval {
    double lower = 0.0;
    double upper = 0.0;
};

namespace detail::hd {

struct tri_bound {
    double lower = 0.0, upper = 0.0;
};

inline tri_bound refine(const mesh_distance& to, const vec3 (&p)[3], const double (&d)[3], const hausdorff_options& o, int depth) {
    const double L = std::sqrt(std::max({glm::dot(p[1] - p[0], p[1] - p[0]), glm::dot(p[2] - p[1], p[2] - p[1]),
                                         glm::dot(p[0] - p[2], p[0] - p[2])}));
    const double corner = std::max({d[0], d[1], d[2]});
    const double bound = corner + L / std::sqrt(3.0);
    // 40 halvings take any edge below 1e-12 of itself: a guard, never reached for precision > 0
    if (bound - corner <= o.precision || bound <= o.stop_below || corner > o.abort_above || depth >= 40) return {corner, bound};
    const vec3 m[3] = {(p[0] + p[1]) * 0.5, (p[1] + p[2]) * 0.5, (p[2] + p[0]) * 0.5};
    double dm[3];
    for (int i = 0; i < 3; ++i) {
        // the Lipschitz bound from an end of the edge limits the search
        const double hint = std::min(d[i], d[(i + 1) % 3]) + 0.5 * glm::length(p[(i + 1) % 3] - p[i]);
        dm[i] = std::sqrt(to.closest(m[i], hint * (1 + 1e-9) + 1e-12).dist2);
        if (!std::isfinite(dm[i])) dm[i] = std::sqrt(to.closest(m[i]).dist2);
    }
    tri_bound out;
    const auto child = [&](const vec3& a, const vec3& b, const vec3& c, double da, double db, double dc) {
        const vec3 q[3] = {a, b, c};
        const double dq[3] = {da, db, dc};
        const tri_bound r = refine(to, q, dq, o, depth + 1);
        out.lower = std::max(out.lower, r.lower);
        out.upper = std::max(out.upper, r.upper);
    };
    child(p[0], m[0], m[2], d[0], dm[0], dm[2]);
    child(m[0], p[1], m[1], dm[0], d[1], dm[1]);
    child(m[2], m[1], p[2], dm[2], dm[1], d[2]);
    child(m[0], m[1], m[2], dm[0], dm[1], dm[2]);
    return out;
}

}  // namespace detail::hd

/// One-sided Hausdorff distance sup_{p in a} dist(p, to.mesh()), as an interval (see the file
/// comment). Throws invalid_input for a non-positive precision, a negative stop_below or an
/// invalid mesh.
[[nodiscard]] inline hausdorff_interval one_sided_hausdorff(const triangle_mesh& a, const mesh_distance& to, const hausdorff_options& o = {}) {
    if (!(std::isfinite(o.precision) && o.precision > 0)) throw invalid_input("hausdorff: precision must be finite and > 0 mm");
    if (!(std::isfinite(o.stop_below) && o.stop_below >= 0)) throw invalid_input("hausdorff: stop_below must be finite and >= 0 mm");
    if (!(o.abort_above >= 0)) throw invalid_input("hausdorff: abort_above must be >= 0 mm");
    validate(a, "hausdorff input mesh");
    std::vector<double> dv(a.vertices.size(), 0.0);
    std::vector<std::uint8_t> used(a.vertices.size(), 0);
    for (const auto& t : a.faces)
        for (auto v : t) used[v] = 1;
    parallel_for(
        0, a.vertices.size(), [&](std::size_t v) { dv[v] = used[v] ? std::sqrt(to.closest(a.vertices[v]).dist2) : 0.0; },
        {.grain = 1024});
    const auto r = parallel_reduce(
        std::size_t{0}, a.faces.size(), detail::hd::tri_bound{},
        [&](std::size_t f) {
            const auto& t = a.faces[f];
            const vec3 p[3] = {a.vertices[t[0]], a.vertices[t[1]], a.vertices[t[2]]};
            const double d[3] = {dv[t[0]], dv[t[1]], dv[t[2]]};
            return detail::hd::refine(to, p, d, o, 0);
        },
        [](detail::hd::tri_bound x, const detail::hd::tri_bound& y) {
            return detail::hd::tri_bound{std::max(x.lower, y.lower), std::max(x.upper, y.upper)};
        },
        {.grain = 512});
    return {r.lower, r.upper};
}

/// Two-sided (symmetric) Hausdorff distance between the surfaces of a and b, as an interval.
[[nodiscard]] inline hausdorff_interval hausdorff_distance(const triangle_mesh& a, const triangle_mesh& b, const hausdorff_options& o = {}) {
    const mesh_distance da(a), db(b);
    const hausdorff_interval ab = one_sided_hausdorff(a, db, o), ba = one_sided_hausdorff(b, da, o);
    return {std::max(ab.lower, ba.lower), std::max(ab.upper, ba.upper)};
}

}  // namespace fabsynth
