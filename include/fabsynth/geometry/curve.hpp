// SPDX-License-Identifier: MIT
#pragma once
/// @file curve.hpp  Planar curves parametrised by arc length, and the band map around them
/// (Zhou et al. 2014, "Topology-constrained synthesis of vector patterns", §3.5 and §6.1: patterns
/// are synthesized in the (u, v) parameter domain of a curve C and mapped by (u, v) -> C(u) + v n(u)).
///
/// A planar_curve is either a polyline (open or closed) or an exact circle. Arc length s runs over
/// [0, length()]; closed curves wrap (s and s + length() are the same point, and s = length() is
/// evaluated exactly as s = 0, so a pattern cut at u = 0 and u = L glues without a crack).
///
/// Normal convention: n = the unit tangent turned by +90 degrees, n = (-t.y, t.x). In SVG user
/// space (y down) a curve drawn left to right has n pointing down the screen, the same direction as
/// an exemplar's +y, so patterns are mapped without mirroring; the map (u, v) -> C(u) + v n(u)
/// preserves orientation (det[t n] = +1), so rings with positive signed area stay positive.
/// circle(R) is traversed so that n points outwards: band_point(u, v) is at radius R + v and angle
/// -u / R (counter-clockwise on an SVG screen).
///
/// Polyline band map (why not the plain unit normal): at a polyline vertex the segment normals
/// jump. The map instead uses the mitre vector m_i = (n_a + n_b) / (1 + n_a . n_b) at vertex i
/// (n_a, n_b the normals of the segments meeting there; m_i . n_a = m_i . n_b = 1) and interpolates
/// it linearly along each segment: band_point(u, v) = C(u) + v m(u). Then every line v = const is
/// the mitred parallel polyline: on each segment it lies at distance exactly |v| from the
/// segment's line, and consecutive pieces meet at the mitre points (no gap or overlap at vertices,
/// band height exactly H), and the map is injective on a segment's band iff the offset segment keeps positive length:
/// len + v (m1 - m0) . t > 0. The largest half-height allowed by that, min over segments of
/// len / |(m1 - m0) . t|, is the polyline's discrete radius of curvature (it tends to the true
/// radius for a finely sampled smooth curve: R cos(alpha/2) for a regular polygon inscribed in a
/// circle of radius R with turning angle alpha). normal(s) is the unit vector along m(s).
///
/// Usage:
///   auto c = fabsynth::planar_curve::circle(20.0);                 // closed, length 2 pi 20
///   auto d = fabsynth::planar_curve::polyline(points, /*closed=*/false);
///   auto e = fabsynth::curve_from_svg(fabsynth::io::read_svg("curve.svg", 0.001));
///   c.check_band(5.0);                       // throws invalid_input if |v| <= 5 would fold
///   vec2 p = c.band_point(u, v);             // C(u) + v n(u)
///
/// Errors (invalid_input, naming the problem): fewer than 2 distinct points, zero length, a
/// non-finite coordinate or radius, a polyline turning back on itself by 180 degrees, and in
/// check_band a half-height >= the smallest radius of curvature or a band that self-overlaps.
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth {

namespace detail::curve {
/// True iff two of the given polylines (open or closed) cross or touch, or one touches itself,
/// other than at the shared vertex of consecutive edges.
///
/// Candidate pairs come from detail::any_segment_pair's grid (polygon.hpp).
inline bool any_contact(const std::vector<std::vector<vec2>>& lines, const std::vector<bool>& closed) {
    struct edge {
        std::size_t line, index;
        vec2 a, b;
    };
    std::vector<edge> edges;
    for (std::size_t l = 0; l < lines.size(); ++l) {
        const auto& p = lines[l];
        if (p.size() < 2) continue;
        const std::size_t n = p.size(), m = closed[l] ? n : n - 1;
        for (std::size_t i = 0; i < m; ++i) edges.push_back({l, i, p[i], p[(i + 1) % n]});
    }
    if (edges.size() < 2) return false;
    auto contact = [&](const edge& E, const edge& F) {
        if (E.line == F.line) {
            const std::size_t n = lines[E.line].size();
            const std::size_t d = E.index > F.index ? E.index - F.index : F.index - E.index;
            if (d == 0) return false;
            const bool adjacent = d == 1 || (closed[E.line] && d == n - 1);
            if (adjacent) {
                // consecutive edges share one vertex; they only fail if they fold onto each other
                const vec2 s = (E.b == F.a) ? E.b : E.a;
                const vec2 pe = (E.b == F.a) ? E.a : E.b, pf = (E.b == F.a) ? F.b : F.a;
                return orient2d(pe, s, pf) == 0.0 && glm::dot(pe - s, pf - s) > 0.0;
            }
        }
        return fabsynth::detail::segments_intersect(E.a, E.b, F.a, F.b);
    };

    std::vector<std::pair<vec2, vec2>> segs;
    segs.reserve(edges.size());
    for (const edge& e : edges) segs.emplace_back(e.a, e.b);
    return fabsynth::detail::any_segment_pair(segs, [&](std::size_t i, std::size_t j) { return contact(edges[i], edges[j]); });
}

/// The vertices of a polyline as the curves keep them: every point finite, consecutive duplicates
/// dropped (and, closed, a repeated first point at the end), at least 2 distinct points (3 when
/// closed). `what` names the curve in errors (invalid_input).
template <class V>
[[nodiscard]] std::vector<V> polyline_vertices(std::vector<V> points, bool closed, const std::string& what) {
    for (std::size_t i = 0; i < points.size(); ++i)
        if (!all_finite(points[i])) throw invalid_input(what + ": point " + std::to_string(i) + " is not finite");
    std::vector<V> p;
    for (const V& q : points)
        if (p.empty() || q != p.back()) p.push_back(q);
    if (closed)
        while (p.size() > 1 && p.back() == p.front()) p.pop_back();
    if (p.size() < 2 || (closed && p.size() < 3))
        throw invalid_input(what + ": needs at least " + std::string(closed ? "3" : "2") + " distinct points, got " + std::to_string(p.size()));
    return p;
}

/// Arc length s wrapped to [0, L) on a closed curve, clamped to [0, L] on an open one.
[[nodiscard]] inline double wrap_arc_length(double s, double length, bool closed) noexcept {
    if (!closed) return std::clamp(s, 0.0, length);
    if (s >= 0.0 && s < length) return s;
    double w = std::fmod(s, length);
    if (w < 0.0) w += length;
    return w >= length ? 0.0 : w;
}
/// The segment of a polyline holding arc length u: the last k with arc[k] <= u, at most the last
/// segment (arc: the vertex arc lengths, one more than the segments).
[[nodiscard]] inline std::size_t segment_at(const std::vector<double>& arc, double u) noexcept {
    const auto it = std::upper_bound(arc.begin(), arc.end(), u);
    const std::size_t k = it == arc.begin() ? 0 : static_cast<std::size_t>(it - arc.begin()) - 1;
    return std::min(k, arc.size() - 2);
}
/// Where u lies along segment k, in [0, 1].
[[nodiscard]] inline double fraction_in_segment(const std::vector<double>& arc, std::size_t k, double u) noexcept {
    return std::clamp((u - arc[k]) / (arc[k + 1] - arc[k]), 0.0, 1.0);
}
/// A mitred polyline band's discrete radius of curvature (curve.hpp's file comment): the smallest
/// len / |(m_1 - m_0) . t| over the segments, +inf if none shrinks; `tangent(k)` is segment k's
/// unit tangent, mitre one vector per vertex (wrapping on closed curves).
template <class Mitres, class Tangent>
[[nodiscard]] double mitred_radius_of_curvature(const std::vector<double>& arc, const Mitres& mitre, Tangent&& tangent, double* at_arc_length) {
    double best = std::numeric_limits<double>::infinity(), where = 0.0;
    const std::size_t n = mitre.size(), segs = arc.size() - 1;
    for (std::size_t k = 0; k < segs; ++k) {
        const double len = arc[k + 1] - arc[k];
        const double shrink = std::abs(glm::dot(mitre[(k + 1) % n] - mitre[k], tangent(k)));
        if (shrink > 0.0 && len / shrink < best) best = len / shrink, where = arc[k];
    }
    if (at_arc_length) *at_arc_length = where;
    return best;
}
}  // namespace detail::curve

/// A planar curve with arc-length parametrisation: a polyline (open or closed) or an exact circle.
class planar_curve {
public:
    /// Polyline through `points` (closed: the last point connects back to the first; a repeated
    /// first point at the end is dropped). Consecutive duplicate points are dropped. Throws
    /// invalid_input for non-finite points, fewer than 2 distinct points (3 when closed), or a
    /// vertex where the polyline turns back by 180 degrees.
    [[nodiscard]] static planar_curve polyline(std::vector<vec2> points, bool closed) {
        std::vector<vec2> p = detail::curve::polyline_vertices(std::move(points), closed, "curve");
        planar_curve c;
        c.closed_ = closed;
        c.points_ = std::move(p);
        const std::size_t n = c.points_.size(), segs = closed ? n : n - 1;
        c.arc_.assign(segs + 1, 0.0);
        std::vector<vec2> seg_normal(segs);
        for (std::size_t i = 0; i < segs; ++i) {
            const vec2 d = c.points_[(i + 1) % n] - c.points_[i];
            const double len = glm::length(d);
            if (!(len > 0.0) || !std::isfinite(len)) throw invalid_input("curve: segment " + std::to_string(i) + " has no length");
            c.arc_[i + 1] = c.arc_[i] + len;
            seg_normal[i] = vec2(-d.y, d.x) / len;
        }
        c.length_ = c.arc_.back();
        if (!(c.length_ > 0.0) || !std::isfinite(c.length_)) throw invalid_input("curve: zero or non-finite length");
        // Mitre vectors m_i with m_i . n = 1 for both adjacent segment normals (see the file comment).
        c.mitre_.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const bool has_prev = closed || i > 0, has_next = closed || i + 1 < n;
            if (!has_prev) { c.mitre_[i] = seg_normal[0]; continue; }
            if (!has_next) { c.mitre_[i] = seg_normal[segs - 1]; continue; }
            const vec2 na = seg_normal[(i + segs - 1) % segs], nb = seg_normal[i % segs];
            const double d = 1.0 + glm::dot(na, nb);
            if (!(d > 1e-12))
                throw invalid_input("curve: the polyline turns back on itself at vertex " + std::to_string(i) +
                                    " (arc length " + std::to_string(c.arc_[i]) + ")");
            c.mitre_[i] = (na + nb) / d;
        }
        return c;
    }

    /// Straight segment from `start` in direction `direction` (normalised) of the given length.
    [[nodiscard]] static planar_curve line(double length, vec2 start = {0, 0}, vec2 direction = {1, 0}) {
        require_positive(length, "curve: line length");
        if (!all_finite(start) || !all_finite(direction) || !(glm::length(direction) > 0.0))
            throw invalid_input("curve: line start and direction must be finite, direction non-zero");
        const vec2 d = glm::normalize(direction);
        return polyline({start, start + length * d}, false);
    }

    /// Closed circle of the given radius around `center`, exact (not a polygon), starting at
    /// center + (R, 0) and traversed so that the normal points outwards (see the file comment).
    [[nodiscard]] static planar_curve circle(double radius, vec2 center = {0, 0}) {
        require_positive(radius, "curve: circle radius");
        if (!all_finite(center)) throw invalid_input("curve: circle center must be finite");
        planar_curve c;
        c.closed_ = true;
        c.is_circle_ = true;
        c.radius_ = radius;
        c.center_ = center;
        c.length_ = 2.0 * std::numbers::pi * radius;
        if (!std::isfinite(c.length_)) throw invalid_input("curve: circle radius too large");
        return c;
    }

    [[nodiscard]] double length() const noexcept { return length_; }
    [[nodiscard]] bool closed() const noexcept { return closed_; }
    [[nodiscard]] bool is_circle() const noexcept { return is_circle_; }
    /// Polyline vertices (empty for a circle).
    [[nodiscard]] const std::vector<vec2>& vertices() const noexcept { return points_; }
    /// Arc length of every polyline vertex (size vertices()+1 when closed: the last is length()).
    [[nodiscard]] const std::vector<double>& vertex_arc_lengths() const noexcept { return arc_; }

    /// Point at arc length s (clamped to [0, L] on open curves, wrapped on closed ones).
    [[nodiscard]] vec2 point(double s) const { return band_point(s, 0.0); }

    /// Unit tangent at arc length s (for a polyline: of the segment containing s).
    [[nodiscard]] vec2 tangent(double s) const {
        if (is_circle_) {
            const double a = wrap(s) / radius_;
            return {-std::sin(a), -std::cos(a)};
        }
        const std::size_t k = segment_of(wrap(s));
        return glm::normalize(points_[(k + 1) % points_.size()] - points_[k]);
    }

    /// Unit normal at arc length s: (-t.y, t.x) on a circle; the direction of the interpolated
    /// mitre vector on a polyline (continuous along the curve).
    [[nodiscard]] vec2 normal(double s) const {
        if (is_circle_) {
            const double a = wrap(s) / radius_;
            return {std::cos(a), -std::sin(a)};
        }
        return glm::normalize(offset_direction(s));
    }

    /// The vector v is multiplied by in the band map: the unit normal on a circle, the linearly
    /// interpolated mitre vector on a polyline (length >= 1; its component along each adjacent
    /// segment normal is 1).
    [[nodiscard]] vec2 offset_direction(double s) const {
        if (is_circle_) return normal(s);
        const double u = wrap(s);
        const std::size_t k = segment_of(u);
        const double a = segment_fraction(k, u);
        return (1.0 - a) * mitre_[k] + a * mitre_[(k + 1) % points_.size()];
    }

    /// The band map (u, v) -> C(u) + v n(u) (§3.5). u is wrapped on closed curves (u = L gives
    /// exactly the point of u = 0) and clamped to [0, L] on open ones.
    [[nodiscard]] vec2 band_point(double u, double v) const {
        u = wrap(u);
        if (is_circle_) {
            const double a = u / radius_, r = radius_ + v;
            return center_ + r * vec2(std::cos(a), -std::sin(a));
        }
        const std::size_t k = segment_of(u);
        const std::size_t k1 = (k + 1) % points_.size();
        const double a = segment_fraction(k, u);
        const vec2 p = a == 0.0 ? points_[k] : points_[k] + a * (points_[k1] - points_[k]);
        return p + v * ((1.0 - a) * mitre_[k] + a * mitre_[k1]);
    }

    /// The largest half-height h for which the band |v| < h does not fold locally: the radius R for
    /// a circle, the discrete radius of curvature for a polyline (see the file comment); +inf for a
    /// straight polyline.
    [[nodiscard]] double min_radius_of_curvature(double* at_arc_length = nullptr) const {
        if (is_circle_) {
            if (at_arc_length) *at_arc_length = 0.0;
            return radius_;
        }
        const std::size_t n = points_.size();
        return detail::curve::mitred_radius_of_curvature(
            arc_, mitre_, [&](std::size_t k) { return (points_[(k + 1) % n] - points_[k]) / (arc_[k + 1] - arc_[k]); }, at_arc_length);
    }

    /// Throws invalid_input unless the band map is injective on u in [0, L], |v| <= half_height:
    /// half_height must be below min_radius_of_curvature() and the band must not overlap itself
    /// (its boundary curves must not touch or cross; for closed curves also the two sides).
    void check_band(double half_height) const {
        if (!(half_height >= 0.0) || !std::isfinite(half_height))
            throw invalid_input("curve band: half-height must be finite and >= 0, got " + std::to_string(half_height));
        double where = 0.0;
        const double r = min_radius_of_curvature(&where);
        if (!(half_height < r))
            throw invalid_input("curve band: half-height " + std::to_string(half_height) +
                                " is not below the curve's smallest radius of curvature " + std::to_string(r) +
                                " (at arc length " + std::to_string(where) + "); the band map would fold: lower the band height below " +
                                std::to_string(2 * r) + " or smooth the curve there");
        if (is_circle_) return;
        const std::size_t n = points_.size();
        std::vector<vec2> plus(n), minus(n);
        for (std::size_t i = 0; i < n; ++i) plus[i] = points_[i] + half_height * mitre_[i], minus[i] = points_[i] - half_height * mitre_[i];
        bool overlap = false;
        if (closed_) {
            overlap = detail::curve::any_contact({points_}, {true}) ||
                      (half_height > 0.0 && detail::curve::any_contact({plus, minus}, {true, true}));
        } else if (half_height > 0.0) {
            std::vector<vec2> outline = plus;
            outline.insert(outline.end(), minus.rbegin(), minus.rend());
            overlap = detail::curve::any_contact({outline}, {true});
        } else {
            overlap = detail::curve::any_contact({points_}, {false});
        }
        if (overlap)
            throw invalid_input("curve band: the band of half-height " + std::to_string(half_height) +
                                " overlaps itself (the curve comes closer to itself than the band height)");
    }

    /// Bounding box of the band u in [0, L], |v| <= half_height (conservative for circles).
    [[nodiscard]] box2 band_bounds(double half_height) const {
        box2 b;
        if (is_circle_) {
            const double r = radius_ + std::abs(half_height);
            return box2(center_ - vec2(r), center_ + vec2(r));
        }
        for (std::size_t i = 0; i < points_.size(); ++i)
            b.extend(points_[i] + half_height * mitre_[i]), b.extend(points_[i] - half_height * mitre_[i]);
        return b;
    }

    /// Arc length wrapped to [0, L) on closed curves, clamped to [0, L] on open ones.
    [[nodiscard]] double wrap(double s) const noexcept { return detail::curve::wrap_arc_length(s, length_, closed_); }

private:
    [[nodiscard]] std::size_t segment_of(double u) const noexcept { return detail::curve::segment_at(arc_, u); }
    [[nodiscard]] double segment_fraction(std::size_t k, double u) const noexcept { return detail::curve::fraction_in_segment(arc_, k, u); }

    bool closed_ = false;
    bool is_circle_ = false;
    double length_ = 0.0;
    double radius_ = 0.0;
    vec2 center_{0, 0};
    std::vector<vec2> points_;  // polyline vertices
    std::vector<double> arc_;   // arc length at each vertex (+ the closing vertex when closed)
    std::vector<vec2> mitre_;   // mitre vector per vertex
};

/// What curve_from_svg reads: `shapes`, each with `subpaths` and `closed` (io::svg_document
/// satisfies it; a template so that geometry/ does not depend on io/).
template <class Doc>
concept svg_like_curve_document = requires(const Doc& d) {
    d.shapes.size();
    d.shapes[0].subpaths;
    d.shapes[0].closed;
};

/// The curve of the first subpath (with at least 2 points) of the first shape of an SVG document
/// (paths, polylines, lines, circles, ...). The document's curves must already be flattened finely
/// enough (read it with a small tolerance, e.g. 1e-3 of its size). force_closed closes an open
/// subpath. Throws invalid_input if the document has no such subpath, and as planar_curve::polyline.
template <svg_like_curve_document Doc>
[[nodiscard]] planar_curve curve_from_svg(const Doc& doc, bool force_closed = false) {
    for (const auto& s : doc.shapes)
        for (std::size_t i = 0; i < s.subpaths.size(); ++i)
            if (s.subpaths[i].size() >= 2)
                return planar_curve::polyline(std::vector<vec2>(s.subpaths[i].begin(), s.subpaths[i].end()),
                                              force_closed || s.closed[i]);
    throw invalid_input("curve: the SVG document has no path or shape with at least 2 points");
}

}  // namespace fabsynth
