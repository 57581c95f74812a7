// SPDX-License-Identifier: MIT
#pragma once
/// @file space_curve.hpp  Curves in space parametrised by arc length, with a frame per point
/// (tangent t, normal n, binormal b) and the band map around them: (u, v, w) -> C(u) + v n(u) +
/// w b(u), the generalisation of planar_curve's (u, v) -> C(u) + v n(u) (curve.hpp) to the bands
/// of Zhou et al. 2014 §6.3 along 3D curves.
///
/// Frames. The normal is carried along the polyline without spinning about the tangent: across a
/// vertex it turns by the smallest rotation taking the incoming tangent to the outgoing one (the
/// rotation-minimising frame of a polyline; Wang, Jüttler, Zheng & Liu 2008, "Computation of
/// rotation minimizing frames", show the double-reflection method converges to it for sampled
/// smooth curves). The first normal is `up` x t_0 (normalised; for a curve in the plane z = c and
/// up = z this is planar_curve's n = (-t.y, t.x), so a planar curve gives the planar band map).
/// On top of that the user's twist turns the frame about the tangent by an angle growing linearly
/// with arc length, twist_degrees over the whole curve. A closed curve must come back to its own
/// frame: the transport's holonomy (the angle the carried normal is off after one loop) is taken
/// out linearly along the curve, and twist_degrees must be a multiple of 360.
/// with_up_directions() replaces the transport by given directions, one per vertex (a curve on a
/// surface keeps its band in the surface's tangent plane: the binormal follows the surface normal).
///
/// Band map. As for planar polylines (curve.hpp's file comment): at vertex i the two adjacent
/// segment normals n_a, n_b (twisted alike) give the mitre vector m_i = (n_a + n_b) / (1 + n_a .
/// n_b), interpolated linearly along each segment; each line v = const is then at distance |v|
/// from the segment's line within the plane of the segment's normals, and a segment's band folds
/// iff len + v (m_1 - m_0) . t <= 0. min_radius_of_curvature() is the smallest len / |(m_1 - m_0)
/// . t|, and check_band(h) requires h below it. The binormal b_i = unit(t_a + t_b) x unit(m_i) is
/// interpolated alike and normalised: the direction of a band's thickness (w).
///
/// Usage:
///   auto c = fabsynth::space_curve::polyline(points, /*closed=*/false, {.twist_degrees = 90});
///   c.check_band(5.0);                        // throws invalid_input if |v| <= 5 would fold
///   vec3 p = c.band_point(u, v, w);           // C(u) + v n(u) + w b(u)
///
/// Errors (invalid_input, naming the problem): a non-finite coordinate or option, fewer than 2
/// distinct points (3 when closed), a polyline turning back on itself by 180 degrees, a closed
/// curve with a twist that is not a multiple of 360 degrees, and in check_band a half-height >=
/// the smallest radius of curvature.
///
/// Self-contact. check_band rules out a fold (neighbouring cross-sections crossing);
/// find_self_contact() looks for the other way a band fails, two distant parts of it meeting (a
/// helix whose turns are closer than the band is high, a curve that crosses itself). The band's
/// solid is swept by the rectangles R(u) = {C(u) + v n + w b : |v| <= h, 0 <= w <= thickness};
/// the boundaries of R(u) are sampled every s (s = min(h, thickness) / 8) at sections every s
/// along the curve, and two samples closer than c = 2.5 s (or the clearance asked for, if larger)
/// from sections more than W = pi (h + thickness) + c apart along the curve are a contact. Every
/// point of the swept boundary lies within 1.12 s of a sample (a section's stretch across the band
/// is below 2 when h is below the radius of curvature), so surfaces that cross are always found;
/// the price is that parts passing within c of each other count as touching (at the scale of a
/// print's smallest gap). Sections within W of each other are neighbours, whose overlap is
/// check_band's business. Cost: the centre line is sampled first, and only sections that can reach
/// a distant one (centre lines within 2 sqrt(h^2 + thickness^2) + c + a coarse step) are sampled
/// finely, at most 4 M samples (beyond that s grows, and c with it). (A piece of the band wholly
/// inside a distant one, which needs 2 h < thickness, is not looked for.)
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/curve.hpp"

namespace fabsynth {

/// Options of space_curve::polyline.
struct space_curve_options {
    double twist_degrees = 0.0;  ///< extra turn of the frame about the tangent over the whole curve (degrees, linear in arc length)
    vec3 up{0.0, 0.0, 1.0};      ///< the first normal is up x t_0 (another axis if up is along t_0)
};

/// The frame at a point of a space curve (unit, right-handed: b = t x n).
struct curve_frame {
    vec3 t{1, 0, 0}, n{0, 1, 0}, b{0, 0, 1};
};

/// Two distant cross-sections of a band that meet (space_curve::find_self_contact).
struct band_self_contact {
    double u1 = 0.0, u2 = 0.0;  ///< their arc lengths along the curve (mm), u1 < u2
    double distance = 0.0;      ///< the distance between the two nearest samples found (mm)
    double clearance = 0.0;     ///< the distance below which samples count as touching (mm)
    vec3 at{0.0};               ///< the midpoint of those samples (mm)
};

/// A polyline in space with arc-length parametrisation and rotation-minimising frames (see the
/// file comment).
class space_curve {
public:
    /// Polyline through `points` (closed: the last point connects back to the first; a repeated
    /// first point at the end and consecutive duplicates are dropped). Throws invalid_input as
    /// listed in the file comment.
    [[nodiscard]] static space_curve polyline(std::vector<vec3> points, bool closed, const space_curve_options& opt = {}) {
        if (!std::isfinite(opt.twist_degrees)) throw invalid_input("space curve: twist must be finite");
        if (!all_finite(opt.up)) throw invalid_input("space curve: up vector is not finite");
        space_curve c = with_vertices(std::move(points), closed);
        if (closed && std::abs(std::remainder(opt.twist_degrees, 360.0)) > 1e-9)
            throw invalid_input("space curve: a closed curve's twist must be a multiple of 360 degrees (its frame must come back), got " +
                                std::to_string(opt.twist_degrees));
        const std::vector<vec3>& t = c.tangent_;
        const std::size_t segs = t.size();
        // rotation-minimising segment normals (no twist yet)
        std::vector<vec3> nu(segs);
        nu[0] = first_normal(t[0], opt.up);
        for (std::size_t k = 1; k < segs; ++k) nu[k] = carry(nu[k - 1], t[k - 1], t[k], k);
        double extra = std::numbers::pi / 180.0 * opt.twist_degrees;  // total turn about the tangent
        if (closed) {
            // the normal carried across the closing vertex back onto segment 0, against nu[0]
            const vec3 back = carry(nu[segs - 1], t[segs - 1], t[0], 0);
            extra -= std::atan2(glm::dot(glm::cross(nu[0], back), t[0]), glm::dot(nu[0], back));  // remove the holonomy
        }
        // twist angle at arc length s: extra * s / L; segment k's normal where it meets vertex i
        c.build_mitres([&](std::size_t k, std::size_t i) {
            const double s = c.arc_[closed && i == 0 && k + 1 == segs ? segs : i];
            const double a = extra * s / c.length_;
            return std::cos(a) * nu[k] + std::sin(a) * glm::cross(t[k], nu[k]);
        });
        return c;
    }

    /// Polyline through `points` whose binormal (the band's thickness direction w) follows the
    /// given unit `up` directions, one per point (a surface normal for a curve on a surface,
    /// surface/curve.hpp): segment k's normal at vertex i is up_i x t_k normalised, so
    /// the band (v) lies in the plane normal to up_i. Point preprocessing and errors as polyline();
    /// also invalid_input if the counts differ or an up direction is not finite, zero or along a
    /// tangent at its vertex. No twist is added.
    [[nodiscard]] static space_curve with_up_directions(std::vector<vec3> points, const std::vector<vec3>& up, bool closed) {
        if (up.size() != points.size())
            throw invalid_input("space curve: " + std::to_string(up.size()) + " up directions for " + std::to_string(points.size()) + " points");
        std::vector<vec3> kept_up;  // the directions of the points polyline() keeps
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (!all_finite(up[i]) || !(glm::length(up[i]) > 0.0)) throw invalid_input("space curve: up direction " + std::to_string(i) + " is not finite and non-zero");
            if (i == 0 || points[i] != points[i - 1]) kept_up.push_back(glm::normalize(up[i]));
        }
        space_curve c = with_vertices(std::move(points), closed);
        kept_up.resize(c.points_.size());
        c.build_mitres([&](std::size_t k, std::size_t i) {
            const vec3 n = glm::cross(kept_up[i], c.tangent_[k]);
            if (!(glm::length(n) > 1e-9))
                throw invalid_input("space curve: the up direction at vertex " + std::to_string(i) + " is along the curve's tangent");
            return glm::normalize(n);
        });
        return c;
    }

    [[nodiscard]] double length() const noexcept { return length_; }
    [[nodiscard]] bool closed() const noexcept { return closed_; }
    [[nodiscard]] const std::vector<vec3>& vertices() const noexcept { return points_; }
    /// Arc length of every vertex (size vertices()+1 when closed: the last is length()).
    [[nodiscard]] const std::vector<double>& vertex_arc_lengths() const noexcept { return arc_; }

    /// Point at arc length s (clamped to [0, L] on open curves, wrapped on closed ones).
    [[nodiscard]] vec3 point(double s) const { return band_point(s, 0.0, 0.0); }

    /// The frame at arc length s: the segment's tangent, the unit interpolated mitre vector made
    /// orthogonal to it, and b = t x n.
    [[nodiscard]] curve_frame frame(double s) const {
        const double u = wrap(s);
        const std::size_t k = segment_of(u);
        curve_frame f;
        f.t = tangent_[k];
        const vec3 m = offset_direction(u);
        f.n = glm::normalize(m - glm::dot(m, f.t) * f.t);
        f.b = glm::cross(f.t, f.n);
        return f;
    }

    /// The vector v is multiplied by in the band map: the linearly interpolated mitre vector.
    [[nodiscard]] vec3 offset_direction(double s) const {
        const double u = wrap(s);
        const std::size_t k = segment_of(u);
        const double a = segment_fraction(k, u);
        return (1.0 - a) * mitre_[k] + a * mitre_[(k + 1) % points_.size()];
    }

    /// The unit direction w is multiplied by: the vertex binormals interpolated and normalised.
    [[nodiscard]] vec3 thickness_direction(double s) const {
        const double u = wrap(s);
        const std::size_t k = segment_of(u);
        const double a = segment_fraction(k, u);
        return glm::normalize((1.0 - a) * binormal_[k] + a * binormal_[(k + 1) % points_.size()]);
    }

    /// The band map (u, v, w) -> C(u) + v m(u) + w b(u). u is wrapped on closed curves (u = L
    /// gives exactly the point of u = 0) and clamped to [0, L] on open ones.
    [[nodiscard]] vec3 band_point(double u, double v, double w = 0.0) const {
        u = wrap(u);
        const std::size_t k = segment_of(u);
        const std::size_t k1 = (k + 1) % points_.size();
        const double a = segment_fraction(k, u);
        const vec3 p = a == 0.0 ? points_[k] : points_[k] + a * (points_[k1] - points_[k]);
        vec3 q = p + v * ((1.0 - a) * mitre_[k] + a * mitre_[k1]);
        if (w != 0.0) q += w * glm::normalize((1.0 - a) * binormal_[k] + a * binormal_[k1]);
        return q;
    }

    /// The largest half-height h for which the band |v| < h does not fold (see the file comment);
    /// +inf for a straight, untwisted polyline.
    [[nodiscard]] double min_radius_of_curvature(double* at_arc_length = nullptr) const {
        return detail::curve::mitred_radius_of_curvature(arc_, mitre_, [&](std::size_t k) { return tangent_[k]; }, at_arc_length);
    }

    /// Throws invalid_input unless half_height is finite, >= 0 and below min_radius_of_curvature().
    void check_band(double half_height) const {
        if (!(half_height >= 0.0) || !std::isfinite(half_height))
            throw invalid_input("space curve band: half-height must be finite and >= 0, got " + std::to_string(half_height));
        double where = 0.0;
        const double r = min_radius_of_curvature(&where);
        if (!(half_height < r))
            throw invalid_input("space curve band: half-height " + std::to_string(half_height) +
                                " is not below the curve's smallest radius of curvature " + std::to_string(r) + " (at arc length " +
                                std::to_string(where) + "); the band map would fold: lower the band height below " + std::to_string(2 * r) +
                                ", or smooth the curve or lower the twist there");
    }

    /// The first contact (smallest u1, then u2) between distant parts of the band |v| <= half_height,
    /// 0 <= w <= thickness around this curve (mm; see "Self-contact" in the file comment), or none.
    /// `clearance` (mm, >= 0): parts closer than this count as touching too. Throws invalid_input
    /// for a non-finite or negative half-height or clearance, or a non-positive thickness.
    [[nodiscard]] std::optional<band_self_contact> find_self_contact(double half_height, double thickness, double clearance = 0.0) const {
        if (!(half_height >= 0.0) || !std::isfinite(half_height)) throw invalid_input("space curve band: half-height must be finite and >= 0");
        if (!(thickness > 0.0) || !std::isfinite(thickness)) throw invalid_input("space curve band: thickness must be finite and > 0");
        if (!(clearance >= 0.0) || !std::isfinite(clearance)) throw invalid_input("space curve band: clearance must be finite and >= 0");
        const double h = half_height, t = thickness, L = length_;
        double s = (h > 0.0 ? std::min(h, t) : t) / 8.0;
        const double reach = std::sqrt(h * h + t * t);  // from C(u) to the farthest point of R(u)
        const auto per_section = [&](double step) { return 2.0 * (std::ceil(2.0 * h / step) + std::ceil(t / step) + 2.0); };
        const auto arc_gap = [&](double a, double b) {
            const double d = std::abs(a - b);
            return closed_ ? std::min(d, L - d) : d;
        };
        // 1. candidate sections: centre-line samples every dc; a pair more than W - dc apart along
        //    the curve and within 2 reach + c + dc in space marks both neighbourhoods
        const double dc = std::max(0.5 * reach, s);
        const std::size_t nc = static_cast<std::size_t>(std::ceil(L / dc)) + 1;
        if (nc > 50'000'000) throw invalid_input("space curve band: the curve is too long for the self-contact check");
        std::vector<vec3> centre(nc);
        std::vector<double> centre_u(nc);
        for (std::size_t i = 0; i < nc; ++i) centre_u[i] = std::min(L, static_cast<double>(i) * dc), centre[i] = band_point(centre_u[i], 0.0);
        // visit(i, j) for every pair of points in the same or neighbouring cells of a grid of `cell`
        // whose arc lengths us[i], us[j] may be more than `apart` apart: the points sorted by cell,
        // then each occupied cell against itself and its 13 neighbours that come after it (every
        // neighbouring pair of cells once), skipping pairs of cells whose arc-length ranges are
        // within `apart` of each other (most pairs: a cell holds the samples of nearby sections)
        const auto grid_pairs = [](const std::vector<vec3>& pts, const std::vector<double>& us, double cell, double apart, auto&& visit) {
            using key3 = std::tuple<std::int64_t, std::int64_t, std::int64_t>;
            std::vector<std::pair<key3, std::size_t>> order(pts.size());
            for (std::size_t i = 0; i < pts.size(); ++i)
                order[i] = {key3{static_cast<std::int64_t>(std::floor(pts[i].x / cell)), static_cast<std::int64_t>(std::floor(pts[i].y / cell)),
                                 static_cast<std::int64_t>(std::floor(pts[i].z / cell))},
                            i};
            std::sort(order.begin(), order.end());
            struct occupied {
                key3 key;
                std::size_t first;  // into order (the next cell's first ends it)
                double u0, u1;      // the range of its arc lengths
            };
            std::vector<occupied> cells;
            for (std::size_t i = 0; i < order.size(); ++i) {
                const double u = us[order[i].second];
                if (i == 0 || order[i].first != order[i - 1].first) cells.push_back({order[i].first, i, u, u});
                cells.back().u0 = std::min(cells.back().u0, u), cells.back().u1 = std::max(cells.back().u1, u);
            }
            const std::size_t nc = cells.size();
            cells.push_back({key3{}, order.size(), 0.0, 0.0});
            for (std::size_t ca = 0; ca < nc; ++ca) {
                const auto [ax, ay, az] = cells[ca].key;
                for (std::int64_t dz = -1; dz <= 1; ++dz)
                    for (std::int64_t dy = -1; dy <= 1; ++dy)
                        for (std::int64_t dx = -1; dx <= 1; ++dx) {
                            const key3 kb{ax + dx, ay + dy, az + dz};
                            if (kb < cells[ca].key) continue;  // that pair of cells is visited from the other one
                            const auto it = std::lower_bound(cells.begin(), cells.begin() + static_cast<std::ptrdiff_t>(nc), kb,
                                                             [](const occupied& e, const key3& k) { return e.key < k; });
                            if (it == cells.begin() + static_cast<std::ptrdiff_t>(nc) || it->key != kb) continue;
                            const std::size_t cb = static_cast<std::size_t>(it - cells.begin());
                            // every |u_i - u_j| (an upper bound of the arc gap) within `apart`: no distant pair here
                            if (std::max(cells[ca].u1 - cells[cb].u0, cells[cb].u1 - cells[ca].u0) <= apart) continue;
                            for (std::size_t i = cells[ca].first; i < cells[ca + 1].first; ++i)
                                for (std::size_t j = cb == ca ? i + 1 : cells[cb].first; j < cells[cb + 1].first; ++j)
                                    visit(std::min(order[i].second, order[j].second), std::max(order[i].second, order[j].second));
                        }
            }
        };
        double c = std::max(2.5 * s, clearance);
        const double W = std::numbers::pi * (h + t) + c;
        std::vector<char> marked(nc, 0);
        const double near_c = 2.0 * reach + c + 2.0 * dc;
        grid_pairs(centre, centre_u, near_c, W - 2.0 * dc, [&](std::size_t a, std::size_t b) {
            if (arc_gap(centre_u[a], centre_u[b]) > W - 2.0 * dc && glm::distance(centre[a], centre[b]) <= near_c) marked[a] = marked[b] = 1;
        });
        // 2. the marked neighbourhoods (+- dc), sectioned every s (s grows if they would hold more than 4 M samples)
        std::vector<std::pair<double, double>> spans;
        for (std::size_t i = 0; i < nc; ++i)
            if (marked[i]) {
                const double a = std::max(0.0, (static_cast<double>(i) - 1.0) * dc), b = std::min(L, (static_cast<double>(i) + 1.0) * dc);
                if (!spans.empty() && a <= spans.back().second) spans.back().second = b;
                else spans.emplace_back(a, b);
            }
        if (spans.empty()) return std::nullopt;
        double marked_length = 0.0;
        for (const auto& [a, b] : spans) marked_length += b - a;
        while ((marked_length / s + static_cast<double>(spans.size())) * per_section(s) > 4e6) s *= 1.25;
        c = std::max(2.5 * s, clearance);
        const double W_fine = std::numbers::pi * (h + t) + c;
        std::vector<vec3> pts;
        std::vector<double> at_u;
        const int nv = static_cast<int>(std::ceil(2.0 * h / s)), nw = static_cast<int>(std::ceil(t / s));
        for (const auto& [a, b] : spans) {
            const int nu = std::max(1, static_cast<int>(std::ceil((b - a) / s)));
            for (int k = 0; k <= nu; ++k) {
                const double u = a + (b - a) * k / nu;
                const auto add = [&](double v, double w) {
                    pts.push_back(band_point(u, v, w));
                    at_u.push_back(u);
                };
                for (int i = 0; i <= nv; ++i) {  // the faces w = 0 and w = t
                    const double v = nv ? -h + 2.0 * h * i / nv : 0.0;
                    add(v, 0.0), add(v, t);
                }
                for (int j = 1; j < nw; ++j) add(-h, t * j / nw), add(h, t * j / nw);  // the faces v = -h and v = h
            }
        }
        std::optional<band_self_contact> best;
        grid_pairs(pts, at_u, c, W_fine, [&](std::size_t i, std::size_t j) {
            if (arc_gap(at_u[i], at_u[j]) <= W_fine) return;
            const double d = glm::distance(pts[i], pts[j]);
            if (!(d < c)) return;
            const double u1 = std::min(at_u[i], at_u[j]), u2 = std::max(at_u[i], at_u[j]);
            if (!best || std::tie(u1, u2, d) < std::tie(best->u1, best->u2, best->distance)) best = band_self_contact{u1, u2, d, c, 0.5 * (pts[i] + pts[j])};
        });
        return best;
    }

    /// Arc length wrapped to [0, L) on closed curves, clamped to [0, L] on open ones.
    [[nodiscard]] double wrap(double s) const noexcept { return detail::curve::wrap_arc_length(s, length_, closed_); }

private:
    // The vertices, arc lengths and segment tangents; checks and drops duplicates as polyline().
    [[nodiscard]] static space_curve with_vertices(std::vector<vec3> points, bool closed) {
        std::vector<vec3> p = detail::curve::polyline_vertices(std::move(points), closed, "space curve");
        space_curve c;
        c.closed_ = closed;
        c.points_ = std::move(p);
        const std::size_t n = c.points_.size(), segs = closed ? n : n - 1;
        c.arc_.assign(segs + 1, 0.0);
        c.tangent_.resize(segs);
        for (std::size_t k = 0; k < segs; ++k) {
            const vec3 d = c.points_[(k + 1) % n] - c.points_[k];
            const double len = glm::length(d);
            if (!(len > 0.0) || !std::isfinite(len)) throw invalid_input("space curve: segment " + std::to_string(k) + " has no length");
            c.arc_[k + 1] = c.arc_[k] + len;
            c.tangent_[k] = d / len;
        }
        c.length_ = c.arc_.back();
        return c;
    }
    // Mitre and binormal per vertex from segment_normal(k, i), the unit normal of segment k where
    // it meets vertex i (see the file comment).
    template <class SegmentNormal>
    void build_mitres(SegmentNormal&& segment_normal) {
        const std::vector<vec3>& t = tangent_;
        const std::size_t n = points_.size(), segs = t.size();
        mitre_.resize(n);
        binormal_.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const bool has_prev = closed_ || i > 0, has_next = closed_ || i + 1 < n;
            const std::size_t ka = (i + segs - 1) % segs, kb = i % segs;
            if (!has_prev) {
                mitre_[i] = segment_normal(kb, i);
                binormal_[i] = glm::cross(t[kb], mitre_[i]);
                continue;
            }
            if (!has_next) {
                mitre_[i] = segment_normal(ka, i);
                binormal_[i] = glm::cross(t[ka], mitre_[i]);
                continue;
            }
            const vec3 na = segment_normal(ka, i), nb = segment_normal(kb, i);
            const double d = 1.0 + glm::dot(na, nb);
            if (!(d > 1e-12) || !(1.0 + glm::dot(t[ka], t[kb]) > 1e-12))
                throw invalid_input("space curve: the polyline turns back on itself at vertex " + std::to_string(i));
            mitre_[i] = (na + nb) / d;
            binormal_[i] = glm::normalize(glm::cross(glm::normalize(t[ka] + t[kb]), glm::normalize(mitre_[i])));
        }
    }

    // up x t, or the axis least along t crossed with t when up is (nearly) along t.
    [[nodiscard]] static vec3 first_normal(const vec3& t, const vec3& up) {
        vec3 n = glm::cross(up, t);
        if (glm::length(n) <= 1e-9 * std::max(1.0, glm::length(up))) {
            const vec3 a = std::abs(t.x) <= std::abs(t.y) && std::abs(t.x) <= std::abs(t.z) ? vec3(1, 0, 0)
                           : std::abs(t.y) <= std::abs(t.z)                              ? vec3(0, 1, 0)
                                                                                         : vec3(0, 0, 1);
            n = glm::cross(a, t);
        }
        return glm::normalize(n);
    }
    // n (normal to a) carried across a vertex by the smallest rotation taking a to b; renormalised
    // against b so rounding does not accumulate.
    [[nodiscard]] static vec3 carry(const vec3& n, const vec3& a, const vec3& b, std::size_t vertex) {
        const double d = 1.0 + glm::dot(a, b);
        if (!(d > 1e-12)) throw invalid_input("space curve: the polyline turns back on itself at vertex " + std::to_string(vertex));
        const vec3 r = n - (glm::dot(n, b) / d) * (a + b);
        return glm::normalize(r - glm::dot(r, b) * b);
    }
    [[nodiscard]] std::size_t segment_of(double u) const noexcept { return detail::curve::segment_at(arc_, u); }
    [[nodiscard]] double segment_fraction(std::size_t k, double u) const noexcept { return detail::curve::fraction_in_segment(arc_, k, u); }

    bool closed_ = false;
    double length_ = 0.0;
    std::vector<vec3> points_;    // polyline vertices
    std::vector<double> arc_;     // arc length at each vertex (+ the closing vertex when closed)
    std::vector<vec3> tangent_;   // unit tangent per segment
    std::vector<vec3> mitre_;     // mitre vector per vertex
    std::vector<vec3> binormal_;  // unit binormal per vertex
};

}  // namespace fabsynth
