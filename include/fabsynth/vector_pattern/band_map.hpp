// SPDX-License-Identifier: MIT
#pragma once
/// @file band_map.hpp  Maps a pattern synthesized in a curve's band coordinates onto the curve
/// (Zhou et al. 2014, §3.5, §6.1: synthesis runs in the (u, v) parameter domain of the curve; the
/// result is mapped by (u, v) -> C(u) + v n(u), geometry/curve.hpp).
///
/// A straight edge in (u, v) maps to a curved arc; map_to_curve densifies every ring edge so that
/// the mapped polyline stays within `chord_tolerance` of the mapped arc: the edge is first cut at
/// every polyline vertex of the curve it crosses (the map is only piecewise smooth there), then
/// each piece is halved recursively while its mapped midpoint is farther than the tolerance from
/// the chord. Closed curves are glued at the seam: the pattern's pieces cut at u = 0 and u = L map
/// onto the same segments (planar_curve evaluates u = L exactly as u = 0) and are merged by a
/// polygon union (geometry/clip.hpp), so a shape crossing the seam comes out as one polygon.
///
/// Usage:
///   auto curve = fabsynth::planar_curve::circle(40.0);
///   auto shapes = fabsynth::vector_pattern::map_to_curve(result.polygons, curve, {.chord_tolerance = 0.005});
///
/// Errors (invalid_input): non-finite points, u outside [0, L], a band (max |v| of the pattern)
/// that would fold or overlap itself (planar_curve::check_band), a bad tolerance.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/curve.hpp"
#include "fabsynth/geometry/extrude.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/segment.hpp"

namespace fabsynth::vector_pattern {

/// Options of map_to_curve.
struct band_map_options {
    double chord_tolerance = 0.01;  ///< max distance between a mapped edge's polyline and the true mapped arc, mm (> 0)
    int max_depth = 20;             ///< recursion bound of the halving (at most 2^max_depth pieces per curve segment)
};

namespace detail {
// Appends the mapped points of (u, v) edge p0 -> p1 for parameters in (t0, t1], halving while
// the mapped midpoint deviates from the chord by more than the tolerance.
inline void densify(const planar_curve& c, vec2 p0, vec2 p1, double t0, double t1, vec2 q0, vec2 q1, double tol,
                    int depth, ring2& out) {
    const double tm = 0.5 * (t0 + t1);
    const vec2 pm = p0 + tm * (p1 - p0);
    const vec2 qm = c.band_point(pm.x, pm.y);
    if (depth > 0 && segment_distance(qm, q0, q1) > tol) {
        densify(c, p0, p1, t0, tm, q0, qm, tol, depth - 1, out);
        densify(c, p0, p1, tm, t1, qm, q1, tol, depth - 1, out);
    } else {
        out.push_back(q1);
    }
}
}  // namespace detail

/// Maps one ring from band coordinates to the plane with edge densification (no validation).
[[nodiscard]] inline ring2 map_ring(const ring2& r, const planar_curve& c, const band_map_options& opt = {}) {
    ring2 out;
    const auto& arcs = c.vertex_arc_lengths();
    for (std::size_t i = 0; i < r.size(); ++i) {
        const vec2 p0 = r[i], p1 = r[(i + 1) % r.size()];
        // parameters where the edge crosses a curve vertex (map kinks), then the end
        std::vector<double> ts{0.0};
        if (!c.is_circle() && p0.x != p1.x) {
            const double lo = std::min(p0.x, p1.x), hi = std::max(p0.x, p1.x);
            std::vector<double> cut;
            for (auto it = std::upper_bound(arcs.begin(), arcs.end(), lo); it != arcs.end() && *it < hi; ++it)
                cut.push_back((*it - p0.x) / (p1.x - p0.x));
            if (p0.x > p1.x) std::reverse(cut.begin(), cut.end());
            ts.insert(ts.end(), cut.begin(), cut.end());
        }
        ts.push_back(1.0);
        vec2 q0 = c.band_point(p0.x, p0.y);
        out.push_back(q0);
        for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
            const vec2 pe = p0 + ts[k + 1] * (p1 - p0);
            const vec2 q1 = k + 2 == ts.size() ? c.band_point(p1.x, p1.y) : c.band_point(pe.x, pe.y);
            detail::densify(c, p0, p1, ts[k], ts[k + 1], q0, q1, opt.chord_tolerance, opt.max_depth, out);
            q0 = q1;
        }
        out.pop_back();  // the edge's end is the next edge's start
    }
    return out;
}

/// Maps band-coordinate polygons (u in [0, L] along the curve, v across, as synthesized) onto
/// the curve; closed curves are glued at the seam by a union. Outer rings positive, holes negative.
[[nodiscard]] inline std::vector<polygon_with_holes> map_to_curve(const std::vector<polygon_with_holes>& polys,
                                                                  const planar_curve& c, const band_map_options& opt = {}) {
    require_positive(opt.chord_tolerance, "map_to_curve: chord_tolerance");
    if (opt.max_depth < 0 || opt.max_depth > 40) throw invalid_input("map_to_curve: max_depth must be in [0, 40]");
    const double vmax = fabsynth::detail::band::check_band_polygons(polys, c.length(), "map_to_curve");
    c.check_band(vmax);
    std::vector<polygon_with_holes> out;
    out.reserve(polys.size());
    for (const polygon_with_holes& p : polys) {
        polygon_with_holes m{map_ring(p.outer, c, opt), {}};
        for (const ring2& h : p.holes) m.holes.push_back(map_ring(h, c, opt));
        orient(m);
        out.push_back(std::move(m));
    }
    if (c.closed() && !out.empty()) {
        // Glue the seam: the cut edges at u = 0 and u = L coincide exactly after mapping.
        std::vector<ring2> rings = to_rings(out);
        out = polygon_boolean(clip_op::union_, rings, fill_rule::nonzero, {}, fill_rule::nonzero, std::nullopt);
    }
    return out;
}

}  // namespace fabsynth::vector_pattern
