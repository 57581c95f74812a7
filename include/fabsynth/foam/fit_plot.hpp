// SPDX-License-Identifier: MIT
#pragma once
/// @file fit_plot.hpp  The figure of an elasticity fit (foam_fit --plot), drawn with core/canvas.hpp
/// so no plotting package is needed. Two panels:
///  - left (like the paper's Figure 5, procedural-voronoi-foams.md §4.2): E/Es against rho, one
///    colour per beam radius tau; filled marks are the samples, hollow marks their scale
///    equivalents (fit_points), lines the fitted polynomial P(rho, tau) over the densities its
///    points cover at that tau;
///  - right (like Figure 8a): E/Es against the relative volume w, the samples, the fitted
///    Gibson-Ashby curve C w^n over its fit range (black) and the paper's C = 0.85, n = 1.95 (grey).
///
///     const auto report = fabsynth::foam::run_elasticity_fit(config, &cache, progress);
///     fabsynth::io::write_png("fit.png", fabsynth::foam::draw_elasticity_fit(config, report));
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fabsynth/core/canvas.hpp>
#include <fabsynth/core/image.hpp>
#include <fabsynth/foam/elasticity_study.hpp>
#include <fabsynth/foam/fit.hpp>

namespace fabsynth::foam {

/// The figure of a finished elasticity fit (see the file comment): a 1640 x 700 RGB image.
/// `c`: the configuration the run used (its Gibson-Ashby range omega_lo..omega_hi); `r`: its report
/// (samples, P, max_deviation, gibson_ashby). A report without a polynomial (fewer than 15
/// samples) or without a Gibson-Ashby fit draws the samples without those curves.
[[nodiscard]] inline image8 draw_elasticity_fit(const elasticity_fit_config& c, const elasticity_fit_report& r) {
    canvas cv(1640, 700);
    std::vector<double> taus;
    double rmax = 0, emax = 0, wmax = 0;
    for (const auto& s : r.samples) {
        if (std::find(taus.begin(), taus.end(), s.s.radius) == taus.end()) taus.push_back(s.s.radius);
        emax = std::max(emax, s.s.E), wmax = std::max(wmax, s.s.volume_fraction);
    }
    std::sort(taus.begin(), taus.end());
    const std::vector<elasticity_sample> pts = fit_points(r.plain_samples());
    for (const auto& e : pts) rmax = std::max(rmax, e.density);
    auto tau_index = [&](double t) { return static_cast<std::size_t>(std::find(taus.begin(), taus.end(), t) - taus.begin()); };
    const double ytop = emax * 1.08 > 0 ? emax * 1.08 : 1.0;

    plot_panel left{cv, 110, 70, 700, 560, 0.0, rmax * 1.05 > 0 ? rmax * 1.05 : 1.0, 0.0, ytop};
    left.axes("RHO (SEEDS/MM^3)", "E/ES", "YOUNG'S MODULUS VS DENSITY, PER BEAM RADIUS");
    if (!r.P.coeffs.empty())
        for (double t : taus) {  // the fit over the densities its points cover at this radius
            double lo = 1e300, hi = 0;
            for (const auto& e : pts)
                if (e.radius == t) lo = std::min(lo, e.density), hi = std::max(hi, e.density);
            left.curve(lo, hi, [&](double rho) { return r.P(rho, t); }, plot_colour(tau_index(t)));
        }
    for (const auto& e : pts) left.ring(e.density, e.E, plot_colour(tau_index(e.radius)));
    for (const auto& s : r.samples) left.dot(s.s.density, s.s.E, plot_colour(tau_index(s.s.radius)));
    int ly = 84;
    for (std::size_t i = 0; i < taus.size(); ++i, ly += 22) {
        char buf[48];
        std::snprintf(buf, sizeof buf, "TAU = %.3g MM", taus[i]);
        cv.rect(left.px1 + 14, ly + 2, left.px1 + 26, ly + 12, plot_colour(i));
        cv.text(left.px1 + 32, ly, buf);
    }
    char note[96];
    std::snprintf(note, sizeof note, "FILLED: SAMPLES; HOLLOW: SCALE EQUIVALENTS; LINES: DEGREE-4 FIT (MAX DEV %.1f%%)", 100 * r.max_deviation);
    cv.text(left.px0 - 60, left.py1 + 60, note);

    plot_panel right{cv, 1020, 70, 1610, 560, 0.0, std::max(0.1, std::min(1.0, wmax * 1.08)), 0.0, ytop};
    right.axes("RELATIVE VOLUME W", "E/ES", "YOUNG'S MODULUS VS RELATIVE VOLUME");
    right.curve(c.omega_lo, c.omega_hi, [](double w) { return 0.85 * std::pow(w, 1.95); }, {150, 150, 150}, 2, 6);
    if (r.gibson_ashby_ok) right.curve(c.omega_lo, c.omega_hi, [&](double w) { return r.gibson_ashby(w); }, {0, 0, 0}, 2);
    for (const auto& s : r.samples) right.dot(s.s.volume_fraction, s.s.E, plot_colour(tau_index(s.s.radius)));
    char ga[96];
    if (r.gibson_ashby_ok) {
        std::snprintf(ga, sizeof ga, "FIT C W^N: C = %.3f, N = %.3f", r.gibson_ashby.C, r.gibson_ashby.n);
        right.cv.line(right.px0 + 14, 92, right.px0 + 44, 92, {0, 0, 0}, 2);
        cv.text(right.px0 + 52, 85, ga);
    }
    right.cv.line(right.px0 + 14, 114, right.px0 + 44, 114, {150, 150, 150}, 2, 6);
    cv.text(right.px0 + 52, 107, "PAPER: C = 0.85, N = 1.95");
    std::snprintf(ga, sizeof ga, "CURVES ON %.2g < W < %.2g (GIBSON-ASHBY RANGE)", c.omega_lo, c.omega_hi);
    cv.text(right.px0 + 10, right.py1 + 60, ga);
    return cv.img;
}

}  // namespace fabsynth::foam
