// SPDX-License-Identifier: MIT
#pragma once
/// @file fit.hpp  Fitting the elasticity model of procedural-voronoi-foams.md §4 to homogenized
/// samples: the degree-4 polynomial E = P(rho, tau) of §4.1 and the Gibson-Ashby power law
/// E/Es = C w^n of §4.3.1 (eq. 2).
///
/// Usage:
///   std::vector<elasticity_sample> s = ...;            // homogenized foams (elasticity_samples.hpp)
///   elasticity_polynomial P = fit_polynomial(s, 4);     // least squares on E
///   auto [Q, dev] = fit_elasticity(s);                  // degree 4 on s and its scale equivalents
///   power_law g = fit_power_law(s, 0.04, 0.5);          // E/Es = g.C * w^g.n on 0.04 < w < 0.5
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/foam/elasticity.hpp"

namespace fabsynth::foam {

/// One homogenized foam realisation.
struct elasticity_sample {
    double density = 0;          ///< rho, seeds/mm^3
    double radius = 0;           ///< tau, mm
    std::uint64_t seed = 0;      ///< global random seed of the realisation
    double E = 0;                ///< fitted isotropic Young's modulus, relative to the base material (E/Es)
    double nu = 0;               ///< fitted Poisson's ratio
    double anisotropy = 0;       ///< relative residual of the isotropic fit (0 = isotropic)
    double volume_fraction = 0;  ///< w: solid volume / cell volume
};

/// Which residual fit_polynomial minimises.
enum class fit_error {
    absolute,  ///< sum_i (P_i - E_i)^2: the paper's objective (§4.1)
    relative,  ///< sum_i ((P_i - E_i) / E_i)^2: equal accuracy across moduli that span decades
};

/// Least-squares fit of P(rho, tau) of total degree `degree` minimising sum_i (P(rho_i, tau_i) - E_i)^2
/// (paper §4.1), or the relative residuals (fit_error::relative; needs every E_i > 0). Why offer the
/// second: with moduli spanning a factor of ~100, the absolute fit spreads one absolute error over
/// all samples, which is tens of percent of the softest foams' E; the inverse mapping of §4.2 is
/// used with relative targets (E/Es), so relative accuracy is what a user gets. Columns are scaled to unit norm before the rank-revealing QR solve, because raw
/// monomials of rho (up to ~10 seeds/mm^3) and tau (~0.2 mm) differ by many orders of magnitude.
/// @throws invalid_input with fewer samples than coefficients or non-finite samples.
[[nodiscard]] inline elasticity_polynomial fit_polynomial(std::span<const elasticity_sample> samples, int degree = 4,
                                                        fit_error error = fit_error::absolute) {
    elasticity_polynomial P;
    P.degree = degree;
    const int n = (degree + 1) * (degree + 2) / 2;
    if (degree < 0 || degree > 12) throw invalid_input("fit_polynomial: degree must be in [0, 12]");
    if (static_cast<int>(samples.size()) < n)
        throw invalid_input("fit_polynomial: degree " + std::to_string(degree) + " needs at least " + std::to_string(n) +
                            " samples, got " + std::to_string(samples.size()));
    Eigen::MatrixXd A(static_cast<Eigen::Index>(samples.size()), n);
    Eigen::VectorXd b(static_cast<Eigen::Index>(samples.size()));
    for (std::size_t r = 0; r < samples.size(); ++r) {
        const auto& s = samples[r];
        if (!std::isfinite(s.density) || !std::isfinite(s.radius) || !std::isfinite(s.E))
            throw invalid_input("fit_polynomial: sample " + std::to_string(r) + " is not finite");
        if (error == fit_error::relative && !(s.E > 0))
            throw invalid_input("fit_polynomial: relative fit needs E > 0, sample " + std::to_string(r) + " has E = " + std::to_string(s.E));
        const double row_weight = error == fit_error::relative ? 1.0 / s.E : 1.0;
        int k = 0;
        for (int d = 0; d <= degree; ++d)  // same monomial order as elasticity_polynomial
            for (int i = d; i >= 0; --i) A(static_cast<Eigen::Index>(r), k++) = row_weight * std::pow(s.density, i) * std::pow(s.radius, d - i);
        b(static_cast<Eigen::Index>(r)) = row_weight * s.E;
    }
    Eigen::VectorXd scale = A.colwise().norm().transpose();
    for (Eigen::Index c = 0; c < n; ++c)
        if (scale(c) == 0) scale(c) = 1;
    const Eigen::MatrixXd As = A * scale.cwiseInverse().asDiagonal();
    const Eigen::VectorXd x = As.colPivHouseholderQr().solve(b).cwiseQuotient(scale);
    P.coeffs.assign(x.data(), x.data() + x.size());
    return P;
}

/// Largest |P(rho_i, tau_i) - E_i| / E_i over the samples (the paper reports 3.3% for its fit).
[[nodiscard]] inline double max_relative_deviation(const elasticity_polynomial& P, std::span<const elasticity_sample> samples) {
    double worst = 0;
    for (const auto& s : samples)
        if (s.E > 0) worst = std::max(worst, std::abs(P(s.density, s.radius) - s.E) / s.E);
    return worst;
}

/// The fit points of the degree-4 polynomial: every homogenized sample (rho, tau) together with
/// its exact scale equivalents (rho (tau / t)^3, t) at each other sampled radius t, in sample order,
/// radii increasing within a sample. Why: the sample of (rho, tau) is the sample of (rho s^3, tau / s)
/// scaled by s — side 60 tau, element size tau, the period in coarse cells (a function of rho tau^3),
/// the coarse cell and every seed position all scale with tau (elasticity_samples.hpp) — and C^H
/// does not depend on scale, so E is a function of f = rho (2 tau)^3 alone (tests/foam/
/// elasticity_fit_run.cpp checks this by homogenizing a scaled sample). The paper fits P on a
/// uniform (rho, tau) grid of independent samples; here each computed sample covers its whole
/// curve rho tau^3 = const, so a fit on the equivalents is a fit on a full grid (same number of
/// points per radius) at 1/(number of radii) of the cost. Documented deviation.
[[nodiscard]] inline std::vector<elasticity_sample> fit_points(std::span<const elasticity_sample> samples) {
    std::vector<double> taus;
    for (const auto& s : samples)
        if (std::find(taus.begin(), taus.end(), s.radius) == taus.end()) taus.push_back(s.radius);
    std::sort(taus.begin(), taus.end());
    std::vector<elasticity_sample> out;
    for (const auto& s : samples)
        for (double t : taus) {
            elasticity_sample e = s;
            if (t != s.radius) {
                const double k = s.radius / t;
                e.density = s.density * k * k * k, e.radius = t;
            }
            out.push_back(e);
        }
    return out;
}

/// The degree-4 fit of §4.1 on fit_points(samples) and its largest relative deviation there.
/// @throws invalid_input with fewer than 15 fit points (see fit_polynomial).
[[nodiscard]] inline std::pair<elasticity_polynomial, double> fit_elasticity(std::span<const elasticity_sample> samples,
                                                                             fit_error error = fit_error::relative) {
    const std::vector<elasticity_sample> pts = fit_points(samples);
    elasticity_polynomial P = fit_polynomial(pts, 4, error);
    return {P, max_relative_deviation(P, pts)};
}

/// Gibson-Ashby model E/Es = C w^n (procedural-voronoi-foams.md eq. 2).
struct power_law {
    double C = 0, n = 0;
    std::size_t samples_used = 0;
    [[nodiscard]] double operator()(double w) const { return C * std::pow(w, n); }
};

/// Fits log(E) = log(C) + n log(w) by least squares over the samples with w_lo < w < w_hi and E > 0.
/// @throws no_solution if fewer than two distinct w fall in the range.
[[nodiscard]] inline power_law fit_power_law(std::span<const elasticity_sample> samples, double w_lo = 0.04, double w_hi = 0.5) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    std::size_t m = 0;
    for (const auto& s : samples) {
        if (!(s.volume_fraction > w_lo && s.volume_fraction < w_hi && s.E > 0)) continue;
        const double x = std::log(s.volume_fraction), y = std::log(s.E);
        sx += x, sy += y, sxx += x * x, sxy += x * y, ++m;
    }
    const double det = static_cast<double>(m) * sxx - sx * sx;
    if (m < 2 || !(det > 1e-12 * static_cast<double>(m) * sxx))
        throw no_solution("fit_power_law: fewer than two distinct relative volumes in (" + std::to_string(w_lo) + ", " +
                          std::to_string(w_hi) + ")");
    power_law g;
    g.n = (static_cast<double>(m) * sxy - sx * sy) / det;
    g.C = std::exp((sy - g.n * sx) / static_cast<double>(m));
    g.samples_used = m;
    return g;
}

}  // namespace fabsynth::foam
