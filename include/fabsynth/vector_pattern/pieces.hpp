// SPDX-License-Identifier: MIT
#pragma once
/// @file pieces.hpp  Slicing an exemplar into pieces along x (Zhou et al. 2014, §3.3, §5.1, §5.2.1).
///
/// t slicing lines x = c_0 < ... < c_{t-1} cut the exemplar into t+1 pieces P_0..P_t (P_0 starts at
/// the exemplar's left end, P_t stops at its right end). Each piece knows
///   - its geometry (the exemplar clipped to [x0, x1] by Clipper, geometry/clip.hpp);
///   - its *portals* on each side (§3.3): the maximal segments of the piece's boundary lying on the
///     side line, i.e. where the pattern interior was sliced, ordered top to bottom (increasing y;
///     for SVG input y points down, so this is top to bottom on screen). Each portal has two
///     endpoints with heights (y, mm) and unit boundary tangents g (the direction of the outline as
///     it leaves the side line, oriented left to right: g.x >= 0, so the tangents of the two pieces
///     meeting at a cut agree where the outline is smooth), and the index of the piece component
///     it belongs to;
///   - its topology: components, the `enclosed` ones touching no side, and holes; descriptor()
///     gives the topology::descriptor the DP solver merges (§3.4).
///
/// Cut positions are rounded to the Clipper grid (clip_grid::snap); piece.x0/x1 hold the rounded
/// values. Where a cut runs exactly along a vertical edge of the exemplar, the portals of the two
/// pieces meeting there may differ (each piece sees its own boundary); choose cuts off such edges
/// (reeb_slicing does, up to the raster resolution).
///
/// Usage:
///   auto cuts   = fabsynth::vector_pattern::uniform_cuts(ex, 7);              // §5.1: 8 pieces
///   auto pieces = fabsynth::vector_pattern::slice(ex, cuts);
///   pieces[2].right.size();                                            // portals on its right side
///   auto d = pieces[2].descriptor();                                   // for dp::solve_sequence
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"
#include "fabsynth/topology/descriptor.hpp"

namespace fabsynth::vector_pattern {

/// A segment of a piece side where the pattern interior was sliced.
struct portal {
    double top = 0.0;                ///< y of the upper endpoint (smaller y), mm
    double bottom = 0.0;             ///< y of the lower endpoint, mm (bottom > top)
    vec2 tangent_top{1.0, 0.0};      ///< unit outline tangent at the upper endpoint, x >= 0
    vec2 tangent_bottom{1.0, 0.0};   ///< unit outline tangent at the lower endpoint, x >= 0
    std::uint32_t component = 0;     ///< index into piece::polygons
    [[nodiscard]] double width() const noexcept { return bottom - top; }
};

/// Which side of a piece.
enum class piece_side { left, right };

/// One piece of a sliced exemplar.
struct piece {
    double x0 = 0.0, x1 = 0.0;                  ///< side positions (mm), x0 < x1
    std::vector<polygon_with_holes> polygons;   ///< components of the piece, oriented
    std::vector<portal> left, right;            ///< portals, top to bottom
    std::uint32_t enclosed = 0;                 ///< components touching neither side

    [[nodiscard]] double width() const noexcept { return x1 - x0; }
    [[nodiscard]] std::size_t components() const noexcept { return polygons.size(); }
    [[nodiscard]] std::uint32_t holes() const noexcept {
        std::size_t h = 0;
        for (const auto& p : polygons) h += p.holes.size();
        return static_cast<std::uint32_t>(h);
    }
    [[nodiscard]] const std::vector<portal>& side(piece_side s) const noexcept { return s == piece_side::left ? left : right; }
    /// Portal endpoint heights of a side, two per portal, top to bottom (the y^j of §3.3).
    [[nodiscard]] std::vector<double> heights(piece_side s) const {
        std::vector<double> h;
        for (const portal& p : side(s)) h.push_back(p.top), h.push_back(p.bottom);
        return h;
    }
    /// Outline tangents at those endpoints (the g^j of §3.3).
    [[nodiscard]] std::vector<vec2> tangents(piece_side s) const {
        std::vector<vec2> g;
        for (const portal& p : side(s)) g.push_back(p.tangent_top), g.push_back(p.tangent_bottom);
        return g;
    }
    /// Topology descriptor (§3.4): component of each left / right portal, enclosed components, holes.
    [[nodiscard]] topology::descriptor descriptor() const {
        std::vector<std::uint32_t> l, r;
        for (const portal& p : left) l.push_back(p.component);
        for (const portal& p : right) r.push_back(p.component);
        return topology::descriptor(l, r, enclosed, holes());
    }
};

/// t cut positions spaced W / (t+1) apart (§5.1). Throws invalid_input if t > 1e6.
[[nodiscard]] inline std::vector<double> uniform_cuts(const exemplar& ex, std::size_t t) {
    if (t > 1'000'000) throw invalid_input("uniform_cuts: t = " + std::to_string(t) + " slicing lines is too many (limit 1e6)");
    if (ex.bounds.empty()) throw invalid_input("uniform_cuts: empty exemplar");
    std::vector<double> c;
    for (std::size_t k = 1; k <= t; ++k)
        c.push_back(ex.bounds.lo.x + ex.width() * static_cast<double>(k) / static_cast<double>(t + 1));
    return c;
}

/// The solid intervals [top, bottom] of the exemplar along the vertical line x (touching intervals
/// merged), top to bottom. Computed from the exemplar's rings (even-odd crossings). O(n).
[[nodiscard]] inline std::vector<std::pair<double, double>> cross_section(const exemplar& ex, double x) {
    require_finite(x, "cross_section: x");
    std::vector<double> ys;
    auto scan = [&](const ring2& r) {
        for (std::size_t i = 0; i < r.size(); ++i) {
            const vec2 a = r[i], b = r[(i + 1) % r.size()];
            if ((a.x <= x) != (b.x <= x)) ys.push_back(a.y + (b.y - a.y) * ((x - a.x) / (b.x - a.x)));
        }
    };
    for (const auto& p : ex.polygons) {
        scan(p.outer);
        for (const auto& h : p.holes) scan(h);
    }
    std::sort(ys.begin(), ys.end());
    std::vector<std::pair<double, double>> out;
    for (std::size_t i = 0; i + 1 < ys.size(); i += 2) {
        if (!out.empty() && out.back().second >= ys[i]) out.back().second = std::max(out.back().second, ys[i + 1]);
        else if (ys[i + 1] > ys[i]) out.emplace_back(ys[i], ys[i + 1]);
    }
    return out;
}

/// Drops the cuts whose narrowest portal is thinner than min_width (mm) (§5.2.1: weak connections).
/// Cuts through no material are kept. Throws invalid_input for a negative or non-finite min_width.
[[nodiscard]] inline std::vector<double> filter_thin_cuts(const exemplar& ex, std::span<const double> cuts, double min_width) {
    if (!(std::isfinite(min_width) && min_width >= 0.0)) throw invalid_input("filter_thin_cuts: min_width must be finite and >= 0");
    std::vector<double> out;
    for (double c : cuts) {
        bool thin = false;
        for (const auto& [t, b] : cross_section(ex, c)) thin = thin || (b - t) < min_width;
        if (!thin) out.push_back(c);
    }
    return out;
}

namespace detail {

/// Portals of the piece side at x = xs (exact grid value): maximal runs of ring edges on the line.
inline std::vector<portal> side_portals(const std::vector<polygon_with_holes>& polys, double xs) {
    std::vector<portal> out;
    auto dir = [](vec2 d) {
        const double l = glm::length(d);
        d = l > 0.0 ? d / l : vec2(1.0, 0.0);
        return d.x < 0.0 ? -d : d;
    };
    for (std::size_t c = 0; c < polys.size(); ++c) {
        auto scan = [&](const ring2& r) {
            const std::size_t n = r.size();
            auto on = [&](std::size_t i) { return r[i % n].x == xs && r[(i + 1) % n].x == xs; };
            std::size_t start = n;  // an edge off the line, so runs do not wrap around the start
            for (std::size_t i = 0; i < n && start == n; ++i)
                if (!on(i)) start = i;
            if (start == n) return;  // degenerate ring lying on the line
            for (std::size_t k = 1; k <= n; ++k) {
                const std::size_t i = (start + k) % n;
                if (!on(i) || on(i + n - 1)) continue;  // not the first edge of a run
                std::size_t e = i;
                while (on(e + 1)) ++e;  // run = edges i..e, points i..e+1
                const vec2 p = r[i], q = r[(e + 1) % n];
                const vec2 tp = dir(p - r[(i + n - 1) % n]), tq = dir(r[(e + 2) % n] - q);
                if (p.y == q.y) continue;
                portal pt;
                pt.component = static_cast<std::uint32_t>(c);
                if (p.y < q.y) pt.top = p.y, pt.tangent_top = tp, pt.bottom = q.y, pt.tangent_bottom = tq;
                else pt.top = q.y, pt.tangent_top = tq, pt.bottom = p.y, pt.tangent_bottom = tp;
                out.push_back(pt);
            }
        };
        scan(polys[c].outer);
        for (const ring2& h : polys[c].holes) scan(h);
    }
    std::sort(out.begin(), out.end(), [](const portal& a, const portal& b) { return a.top < b.top || (a.top == b.top && a.bottom < b.bottom); });
    return out;
}

}  // namespace detail

/// Cuts the exemplar at the given x positions (strictly increasing, strictly inside the exemplar's
/// x extent) into cuts.size() + 1 pieces. Throws invalid_input for unsorted, duplicate (after
/// rounding to the grid), non-finite or out-of-range cuts, or an empty exemplar. One Clipper
/// intersection per piece: O(P (n + k) log n).
[[nodiscard]] inline std::vector<piece> slice(const exemplar& ex, std::span<const double> cuts) {
    if (ex.polygons.empty() || ex.bounds.empty()) throw invalid_input("slice: empty exemplar");
    const box2 b = ex.bounds;
    const double margin = std::max(1.0, b.size().y);
    box2 all = b;
    all.extend(vec2(b.lo.x, b.lo.y - margin)).extend(vec2(b.hi.x, b.hi.y + margin));
    const clip_grid grid = clip_grid::for_bounds(all);
    std::vector<double> xs{grid.snap(b.lo.x)};
    for (std::size_t i = 0; i < cuts.size(); ++i) {
        const double c = cuts[i];
        if (!std::isfinite(c) || !(c > b.lo.x && c < b.hi.x))
            throw invalid_input("slice: cut " + std::to_string(i) + " at x = " + std::to_string(c) +
                                " is not strictly inside the exemplar's x range [" + std::to_string(b.lo.x) + ", " +
                                std::to_string(b.hi.x) + "]");
        const double s = grid.snap(c);
        if (!(s > xs.back()))
            throw invalid_input("slice: cuts must be strictly increasing (cut " + std::to_string(i) + " at x = " +
                                std::to_string(c) + ")");
        xs.push_back(s);
    }
    const double end = grid.snap(b.hi.x);
    if (!(end > xs.back())) throw invalid_input("slice: the last cut coincides with the exemplar's right end");
    xs.push_back(end);
    std::vector<piece> out(xs.size() - 1);
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
        piece& p = out[i];
        p.x0 = xs[i];
        p.x1 = xs[i + 1];
        p.polygons = clip_strip(ex.polygons, p.x0, p.x1, grid);
        p.left = detail::side_portals(p.polygons, p.x0);
        p.right = detail::side_portals(p.polygons, p.x1);
        std::vector<char> touches(p.polygons.size(), 0);
        for (const portal& q : p.left) touches[q.component] = 1;
        for (const portal& q : p.right) touches[q.component] = 1;
        p.enclosed = static_cast<std::uint32_t>(std::count(touches.begin(), touches.end(), 0));
    }
    return out;
}

}  // namespace fabsynth::vector_pattern
