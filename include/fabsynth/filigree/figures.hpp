// SPDX-License-Identifier: MIT
#pragma once
/// @file figures.hpp  The two diagnostic figures of the structural optimization
/// (filigree-synthesis.md §5, §8.3.1), drawn with core/canvas.hpp into RGB pictures:
///   stress_map_image       Fig. 10: the piece coloured by nodal von Mises stress over the yield
///                          stress (blue 0, green half the yield, red at the yield, magenta above:
///                          the weak nodes), linear between nodes, with a colour bar;
///   stress_histogram_plot  Fig. 21: the percentage of nodes per stress bin before and after the
///                          optimization, side by side, with the yield stress and the weak shares.
///
/// Usage:
///   const auto f = fabsynth::filigree::make_filigree(classes, weights, domain, field, opt);
///   image8 map = fabsynth::filigree::stress_map_image(f.reinforcement.fem, f.reinforcement.final_report, f.view);
///   image8 hist = fabsynth::filigree::stress_histogram_plot(f.reinforcement);
///   fabsynth::io::write_png("stress.png", map);
///
/// Errors: invalid_input when the report does not belong to the triangulation (a stress per vertex)
/// or the record holds no analysis.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/canvas.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/filigree/reinforcement.hpp"

namespace fabsynth::filigree {

namespace detail::figures {

// The colour of stress ratio r = sigma / yield: blue (0), cyan, green (0.5), yellow, red (1),
// magenta above the yield.
[[nodiscard]] inline std::array<double, 3> stress_colour(double r) {
    if (r > 1.0) return {200, 0, 200};
    static constexpr std::array<std::array<double, 3>, 5> stops{{{40, 60, 200}, {0, 190, 220}, {40, 180, 40}, {240, 210, 0}, {220, 30, 20}}};
    const double t = std::clamp(r, 0.0, 1.0) * 4.0;
    const auto k = std::min<std::size_t>(3, static_cast<std::size_t>(t));
    const double u = t - static_cast<double>(k);
    std::array<double, 3> c{};
    for (std::size_t i = 0; i < 3; ++i) c[i] = stops[k][i] + u * (stops[k + 1][i] - stops[k][i]);
    return c;
}

[[nodiscard]] inline rgb8 to_rgb(const std::array<double, 3>& c) {
    return {static_cast<std::uint8_t>(std::lround(c[0])), static_cast<std::uint8_t>(std::lround(c[1])), static_cast<std::uint8_t>(std::lround(c[2]))};
}

[[nodiscard]] inline std::string mpa(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3g MPA", v);
    return b;
}

// The stress maps' legend in the column of `cv` from x = bx - 10 on, between the rows 0 and
// height: the thickness at the top, the colour bar (0 MPa at the bottom, the yield at the top, the
// weak colour above it, 30 pixels wide) and the count of weak nodes under it. Needs a column
// 260 pixels wide and a height of at least 420 pixels.
inline void draw_stress_legend(canvas& cv, int bx, int height, const structural_report& rep) {
    const int by0 = 60, by1 = height - 60;
    const int weak_h = 30;
    cv.rect(bx, by0, bx + 30, by0 + weak_h, to_rgb(stress_colour(2.0)));
    for (int y = by0 + weak_h + 4; y <= by1; ++y)
        cv.rect(bx, y, bx + 30, y, to_rgb(stress_colour(static_cast<double>(by1 - y) / (by1 - by0 - weak_h - 4))));
    cv.text(bx + 40, by0 + weak_h / 2 - 7, "WEAK");
    cv.text(bx + 40, by0 + weak_h + 4, mpa(rep.yield));
    cv.text(bx + 40, (by0 + weak_h + 4 + by1) / 2 - 7, mpa(rep.yield / 2));
    cv.text(bx + 40, by1 - 14, "0 MPA");
    char line[64];
    std::snprintf(line, sizeof line, "T = %.3g MM", rep.thickness);
    cv.text(bx - 10, 20, line);
    std::snprintf(line, sizeof line, "%zu WEAK", rep.weak_nodes.size());
    cv.text(bx - 10, by1 + 24, line);
}

}  // namespace detail::figures

/// Fig. 10: the triangulation `tri` (mm, domain frame, y down as drawn) filled with the colour of
/// rep.node_von_mises / rep.yield, interpolated linearly inside each triangle, over `view` (mm)
/// scaled so its longer side is `max_side` pixels, on white, with a colour bar and the thickness on
/// the right. Returns an RGB image8. Throws invalid_input if rep has no stress per vertex of tri,
/// rep.yield is not > 0, the view is empty or max_side < 64.
[[nodiscard]] inline image8 stress_map_image(const fem_triangulation& tri, const structural_report& rep, const box2& view, int max_side = 1600) {
    namespace df = detail::figures;
    if (rep.node_von_mises.size() != tri.mesh.vertices.size() || tri.mesh.triangles.empty())
        throw invalid_input("stress_map_image: the report has " + std::to_string(rep.node_von_mises.size()) + " nodal stresses for " +
                            std::to_string(tri.mesh.vertices.size()) + " vertices");
    if (!(rep.yield > 0)) throw invalid_input("stress_map_image: the report's yield stress must be > 0 MPa");
    if (view.empty() || !(view.size().x > 0 && view.size().y > 0)) throw invalid_input("stress_map_image: the view box is empty");
    if (max_side < 64) throw invalid_input("stress_map_image: max_side must be >= 64 pixels");
    const double s = max_side / std::max(view.size().x, view.size().y);
    const int w = std::max(1, static_cast<int>(std::lround(view.size().x * s))), h = std::max(1, static_cast<int>(std::lround(view.size().y * s)));
    constexpr int bar_w = 260;
    canvas cv(w + bar_w, std::max(h, 420));
    auto px = [&](vec2 p) { return vec2((p.x - view.lo.x) * s, (p.y - view.lo.y) * s); };
    for (const auto& t : tri.mesh.triangles) {
        const vec2 a = px(tri.mesh.vertices[t[0]]), b = px(tri.mesh.vertices[t[1]]), c = px(tri.mesh.vertices[t[2]]);
        const double ra = rep.node_von_mises[t[0]] / rep.yield, rb = rep.node_von_mises[t[1]] / rep.yield, rc = rep.node_von_mises[t[2]] / rep.yield;
        const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if (det == 0.0) continue;
        const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x})))), x1 = std::min(w - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
        const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y})))), y1 = std::min(h - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const vec2 p(x + 0.5, y + 0.5);
                const double l1 = ((p.x - a.x) * (c.y - a.y) - (c.x - a.x) * (p.y - a.y)) / det;
                const double l2 = ((b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y)) / det;
                const double l0 = 1.0 - l1 - l2;
                constexpr double eps = -1e-9;  // pixels on a shared edge are drawn by both triangles, the same colour
                if (l0 < eps || l1 < eps || l2 < eps) continue;
                // interpolate the ratio, then colour it, so the yield line is where the stress crosses it
                cv.put(x, y, df::to_rgb(df::stress_colour(l0 * ra + l1 * rb + l2 * rc)));
            }
    }
    df::draw_stress_legend(cv, w + 30, std::max(h, 420), rep);
    return cv.img;
}

/// Fig. 21 as the paper draws it (§8.3.1: "the vertical axis is the percentage of nodes lying in
/// each interval"): the record's histograms (histogram_before, histogram_after: node counts per
/// histogram_bin_mpa bin, the last bin open) as percentages of their nodes, paired bars, before in
/// grey and after in orange, over the stress in MPa, with the yield stress as a dashed red line and
/// the weak percentages (nodes above the yield, from weak_fraction_phase1 / _phase2) written beside
/// it; 1000 x 600 pixels. Throws invalid_input if the record holds no analysis.
[[nodiscard]] inline image8 stress_histogram_plot(const structural_record& r) {
    if (!r.analysed || r.histogram_before.empty() || r.histogram_after.size() != r.histogram_before.size() || !(r.histogram_bin_mpa > 0))
        throw invalid_input("stress_histogram_plot: the record holds no structural analysis");
    const std::size_t n = r.histogram_before.size();
    const double bin = r.histogram_bin_mpa;
    auto percent = [](const std::vector<std::size_t>& h) {
        double total = 0;
        for (const std::size_t c : h) total += static_cast<double>(c);
        std::vector<double> p(h.size(), 0.0);
        for (std::size_t k = 0; k < h.size() && total > 0; ++k) p[k] = 100.0 * static_cast<double>(h[k]) / total;
        return p;
    };
    const std::vector<double> before = percent(r.histogram_before), after = percent(r.histogram_after);
    double top = 1.0;
    for (std::size_t k = 0; k < n; ++k) top = std::max({top, before[k], after[k]});
    canvas cv(1000, 600);
    plot_panel p{cv, 110, 60, 960, 500, 0.0, bin * static_cast<double>(n), 0.0, std::min(100.0, 1.08 * top)};
    p.axes("VON MISES STRESS (MPA), LAST BIN OPEN", "NODES (%)", "NODAL STRESS BEFORE (GREY) AND AFTER (ORANGE)");
    const rgb8 grey{150, 150, 150}, orange{255, 127, 14};
    for (std::size_t k = 0; k < n; ++k) {
        const double x = bin * static_cast<double>(k);
        auto bar = [&](double a, double b, double share, rgb8 c) {
            if (share <= 0) return;
            // at least one pixel, so a bin with a few nodes (the weak tail) stays visible
            const int y_top = std::min(static_cast<int>(std::lround(p.Y(share))), static_cast<int>(std::lround(p.Y(0.0))) - 2);
            cv.rect(static_cast<int>(std::lround(p.X(a))), y_top, static_cast<int>(std::lround(p.X(b))) - 1, static_cast<int>(std::lround(p.Y(0.0))) - 1, c);
        };
        bar(x + 0.08 * bin, x + 0.5 * bin, before[k], grey);
        bar(x + 0.5 * bin, x + 0.92 * bin, after[k], orange);
    }
    const rgb8 red{220, 30, 20};
    if (r.yield_mpa > 0) cv.line(p.X(r.yield_mpa), p.py0, p.X(r.yield_mpa), p.py1, red, 2, 6);
    cv.text(static_cast<int>(p.X(r.yield_mpa)) + 6, p.py0 + 6, "YIELD " + detail::figures::mpa(r.yield_mpa), red);
    char line[80];
    const double wb = r.weak_fraction_phase1.empty() ? 0.0 : r.weak_fraction_phase1.front();
    const double wa = r.weak_fraction_phase2.empty() ? 0.0 : r.weak_fraction_phase2.back();
    std::snprintf(line, sizeof line, "WEAK %.2f%% BEFORE, %.2f%% AFTER", 100.0 * wb, 100.0 * wa);
    cv.text(static_cast<int>(p.X(r.yield_mpa)) + 6, p.py0 + 30, line, red);
    return cv.img;
}

}  // namespace fabsynth::filigree
