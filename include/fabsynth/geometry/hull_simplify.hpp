// SPDX-License-Identifier: MIT
#pragma once
/// @file hull_simplify.hpp  Convex hull of a point set and Douglas-Peucker simplification of a
/// polyline: thin wrappers around Boost.Geometry (header-only, Boost licence), so that the library
/// has one implementation of each (filigree-synthesis.md §3.3: skeletons approximated by polylines
/// to a user accuracy; §4.2: covering regions as convex hulls).
///
/// Usage:
///   fabsynth::ring2 h = fabsynth::convex_hull(points);              // counter-clockwise, y up
///   std::vector<fabsynth::vec2> s = fabsynth::simplify_polyline(line, 0.05);
///
/// convex_hull returns the hull's corners without repeating the first one, counter-clockwise
/// (positive signed_area), collinear points dropped; fewer than 3 distinct non-collinear points give
/// the distinct extreme points (0, 1 or 2 of them). simplify_polyline keeps both end points and
/// every kept point is a point of the input; no input point is farther than `tolerance` from the
/// result (Douglas & Peucker 1973). Throws invalid_input for non-finite points or a negative or
/// non-finite tolerance.
#include <boost/geometry/strategies/strategies.hpp>
#include <boost/geometry/algorithms/convex_hull.hpp>
#include <boost/geometry/algorithms/simplify.hpp>
#include <boost/geometry/geometries/linestring.hpp>
#include <boost/geometry/geometries/multi_point.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth {

namespace detail::hull {
using bg_point = boost::geometry::model::d2::point_xy<double>;
inline void require_finite(std::span<const vec2> points, const char* what) {
    for (const vec2& p : points)
        if (!all_finite(p)) throw invalid_input(std::string(what) + ": a point is not finite");
}
}  // namespace detail::hull

/// Convex hull of `points` (any order, duplicates allowed), counter-clockwise, first point not
/// repeated (see the file comment).
[[nodiscard]] inline ring2 convex_hull(std::span<const vec2> points) {
    namespace bg = boost::geometry;
    detail::hull::require_finite(points, "convex_hull");
    bg::model::multi_point<detail::hull::bg_point> mp;
    for (const vec2& p : points) mp.emplace_back(p.x, p.y);
    bg::model::polygon<detail::hull::bg_point, false, false> hull;  // counter-clockwise, open
    if (!mp.empty()) bg::convex_hull(mp, hull);
    ring2 out;
    for (const auto& q : hull.outer()) out.emplace_back(q.x(), q.y());
    while (out.size() > 1 && out.front() == out.back()) out.pop_back();
    if (out.size() >= 3 && signed_area(out) < 0) std::reverse(out.begin(), out.end());
    return out;
}

/// Douglas-Peucker simplification of an open polyline to `tolerance` (same units as the points).
[[nodiscard]] inline std::vector<vec2> simplify_polyline(std::span<const vec2> line, double tolerance) {
    namespace bg = boost::geometry;
    detail::hull::require_finite(line, "simplify_polyline");
    if (!(std::isfinite(tolerance) && tolerance >= 0)) throw invalid_input("simplify_polyline: tolerance must be finite and >= 0");
    if (line.size() <= 2 || tolerance == 0) return {line.begin(), line.end()};
    bg::model::linestring<detail::hull::bg_point> in, out;
    for (const vec2& p : line) in.emplace_back(p.x, p.y);
    bg::simplify(in, out, tolerance);
    std::vector<vec2> r;
    for (const auto& q : out) r.emplace_back(q.x(), q.y());
    return r;
}

}  // namespace fabsynth
