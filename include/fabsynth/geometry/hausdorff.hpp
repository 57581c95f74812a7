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
/// So sup over a triangle of d <= max over its corners of d + L / sqrt(3). Each triangle is
/// bisected at the midpoint of its longest edge until that bound is within `precision` of the
/// corner maximum, or is at most `stop_below` (a check against a tolerance needs to know no more than that). The result
/// is an interval [lower, upper] holding the true distance: lower is a distance attained at a
/// sample point, upper the largest bound. A triangle whose corners project into one face of the
/// other surface is bounded at once by their distances to that face's plane (projection is affine
/// and the face convex), so coinciding flat stretches cost nothing. Elsewhere samples grow as area / precision^2 (area / stop_below^2
/// where the surfaces are close), and only linearly in the length of slivers: checking a fine
/// tolerance on a large surface is the expensive case.
///
/// Cost: one closest-point query (AABB tree, geometry/distance.hpp) per vertex and per split
/// bisection; parallel over faces, and the result does not depend on the thread count.
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

// If the corners' projections onto the plane of face f of `to` all fall in f (closed), so does the
// projection of every point of the triangle (an affine map of a convex set), and the triangle's
// distance to the surface is at most the largest corner distance to that plane: returns it, or inf.
inline double plane_bound(const mesh_distance& to, std::uint32_t f, const vec3 (&p)[3]) {
    const triangle_mesh& m = to.mesh();
    const vec3 a = m.vertices[m.faces[f][0]], b = m.vertices[m.faces[f][1]], c = m.vertices[m.faces[f][2]];
    const vec3 n = glm::cross(b - a, c - a);
    const double n2 = glm::dot(n, n);
    if (!(n2 > 0)) return std::numeric_limits<double>::infinity();
    double worst = 0;
    for (const vec3& x : p) {
        const double h = glm::dot(x - a, n) / n2;
        const vec3 q = x - h * n;
        // barycentric signs of q in abc (sub-areas against the normal)
        if (glm::dot(glm::cross(b - a, q - a), n) < 0 || glm::dot(glm::cross(c - b, q - b), n) < 0 || glm::dot(glm::cross(a - c, q - c), n) < 0)
            return std::numeric_limits<double>::infinity();
        worst = std::max(worst, std::abs(h) * std::sqrt(n2));
    }
    return worst;
}

inline tri_bound refine(const mesh_distance& to, const vec3 (&p)[3], const double (&d)[3], const std::uint32_t (&face)[3],
                        const hausdorff_options& o, int depth) {
    const double corner0 = std::max({d[0], d[1], d[2]});
    // flat stretches: the whole triangle over one face of the other surface is decided at once
    for (int i = 0; i < 3; ++i)
        if (i == 0 || (face[i] != face[0] && (i == 1 || face[i] != face[1]))) {
            const double b = plane_bound(to, face[i], p);
            if (b - corner0 <= o.precision || b <= o.stop_below) return {corner0, std::max(b, corner0)};
        }
    const double e[3] = {glm::dot(p[1] - p[0], p[1] - p[0]), glm::dot(p[2] - p[1], p[2] - p[1]), glm::dot(p[0] - p[2], p[0] - p[2])};
    const int k = e[0] >= e[1] && e[0] >= e[2] ? 0 : (e[1] >= e[2] ? 1 : 2);  // longest edge p[k] p[k+1]
    const double L = std::sqrt(e[k]);
    const double corner = std::max({d[0], d[1], d[2]});
    const double bound = corner + L / std::sqrt(3.0);
    // 200 bisections take any edge far below 1e-12 of itself: a guard, never reached for precision > 0
    if (bound - corner <= o.precision || bound <= o.stop_below || corner > o.abort_above || depth >= 200) return {corner, bound};
    // bisect the longest edge: slivers (long extrusion faces) cost about L / precision samples,
    // not (L / precision)^2 as a split into four would
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    const vec3 m = (p[k] + p[k1]) * 0.5;
    // the Lipschitz bound from an end of the edge limits the search
    const double hint = std::min(d[k], d[k1]) + 0.5 * L;
    mesh_closest cm = to.closest(m, hint * (1 + 1e-9) + 1e-12);
    if (!cm.found()) cm = to.closest(m);
    const double dm = std::sqrt(cm.dist2);
    const vec3 qa[3] = {p[k], m, p[k2]}, qb[3] = {m, p[k1], p[k2]};
    const double da[3] = {d[k], dm, d[k2]}, db[3] = {dm, d[k1], d[k2]};
    const std::uint32_t fa[3] = {face[k], cm.face, face[k2]}, fb[3] = {cm.face, face[k1], face[k2]};
    const tri_bound ra = refine(to, qa, da, fa, o, depth + 1), rb = refine(to, qb, db, fb, o, depth + 1);
    return {std::max(ra.lower, rb.lower), std::max(ra.upper, rb.upper)};
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
    std::vector<std::uint32_t> fv(a.vertices.size(), 0);
    std::vector<std::uint8_t> used(a.vertices.size(), 0);
    for (const auto& t : a.faces)
        for (auto v : t) used[v] = 1;
    parallel_for(
        0, a.vertices.size(),
        [&](std::size_t v) {
            if (!used[v]) return;
            const mesh_closest c = to.closest(a.vertices[v]);
            dv[v] = std::sqrt(c.dist2), fv[v] = c.face;
        },
        {.grain = 1024});
    const auto r = parallel_reduce(
        std::size_t{0}, a.faces.size(), detail::hd::tri_bound{},
        [&](std::size_t f) {
            const auto& t = a.faces[f];
            const vec3 p[3] = {a.vertices[t[0]], a.vertices[t[1]], a.vertices[t[2]]};
            const double d[3] = {dv[t[0]], dv[t[1]], dv[t[2]]};
            const std::uint32_t face[3] = {fv[t[0]], fv[t[1]], fv[t[2]]};
            return detail::hd::refine(to, p, d, face, o, 0);
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
