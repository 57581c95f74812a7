// SPDX-License-Identifier: MIT
#pragma once
/// @file elasticity.hpp  Elasticity control (paper §4.2): from a target Young's modulus to foam
/// parameters (rho, tau), given a fitted model E = P(rho, tau).
///
/// The fitted degree-4 polynomial of the paper (§4.1) is data: elasticity_fit.hpp holds the
/// coefficients that examples/foam_fit computed by homogenizing periodic foam samples (provenance
/// in that header and in data/foam/README.md); fitted_elasticity() wraps them. Strategy of §4.2:
/// tau = tau_min (thinnest printable beam), rho solves P(rho, tau_min) = E_target. The generic
/// inverse_elasticity bisects on [rho_min, rho_max] with rho_max = 1 / (2 tau_min)^3 (the block
/// is full beyond it), so it needs a model that is monotone there. The shipped polynomial is only
/// valid where it was sampled, the band f_min <= rho (2 tau)^3 <= f_max, tau_min <= tau <= tau_max
/// of elasticity_fit.hpp (E depends on rho and tau through f = rho (2 tau)^3 only: a foam scaled
/// by s has density rho / s^3 and radius s tau and the same relative stiffness); so
/// inverse_fitted_elasticity bisects on that band and refuses radii outside the sampled range.
///
/// Usage:
///   foam_parameters p = inverse_fitted_elasticity(0.05, 0.25);       // E/Es = 0.05, tau_min = 0.25 mm
///   double e = fitted_elasticity()(p.density, p.radius);              // ~ 0.05
///   foam_parameters q = inverse_elasticity(my_model, 0.01, 0.25);    // any monotone model
#include <algorithm>
#include <cmath>
#include <concepts>
#include <iterator>
#include <utility>
#include <cstddef>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/elasticity_fit.hpp"

namespace fabsynth::foam {

/// A model E(rho [seeds/mm^3], tau [mm]) -> Young's modulus (any unit, e.g. relative E/Es).
template <class M>
concept elasticity_model = std::invocable<const M&, double, double> &&
                           std::convertible_to<std::invoke_result_t<const M&, double, double>, double>;

/// Bivariate polynomial P(rho, tau) = sum_{i + j <= degree} c_ij rho^i tau^j. Coefficients are
/// ordered by total degree d = 0..degree, then by i = d..0 (so: 1, rho, tau, rho^2, rho tau,
/// tau^2, ...): (degree + 1)(degree + 2) / 2 of them.
struct elasticity_polynomial {
    int degree = 4;
    std::vector<double> coeffs;

    /// Throws invalid_input unless the table has the right size and finite entries.
    void validate() const {
        if (degree < 0 || degree > 12) throw invalid_input("elasticity polynomial degree must be in [0, 12]");
        const std::size_t n = static_cast<std::size_t>((degree + 1) * (degree + 2) / 2);
        if (coeffs.size() != n)
            throw invalid_input("elasticity polynomial of degree " + std::to_string(degree) + " needs " +
                                std::to_string(n) + " coefficients, got " + std::to_string(coeffs.size()));
        for (double c : coeffs) require_finite(c, "elasticity polynomial coefficient");
    }
    [[nodiscard]] double operator()(double rho, double tau) const {
        double sum = 0;
        std::size_t k = 0;
        for (int d = 0; d <= degree; ++d)
            for (int i = d; i >= 0; --i) {
                if (k >= coeffs.size()) return sum;
                sum += coeffs[k++] * std::pow(rho, i) * std::pow(tau, d - i);
            }
        return sum;
    }
};

/// Foam parameters for one point.
struct foam_parameters {
    double density = 0;  ///< seeds/mm^3
    double radius = 0;   ///< mm
};

/// What to do when E_target is outside [P(rho_min, tau_min), P(rho_max, tau_min)].
enum class out_of_range { clamp, throw_no_solution };

/// (rho, tau) with tau = tau_min and P(rho, tau_min) = e_target, rho in [rho_min, 1/(2 tau_min)^3].
/// Throws invalid_input for non-finite input or tau_min <= 0, and no_solution (or clamps, by
/// `policy`) when the target is not bracketed.
template <elasticity_model Model>
[[nodiscard]] foam_parameters inverse_elasticity(const Model& P, double e_target, double tau_min, double rho_min = 0,
                                                 out_of_range policy = out_of_range::clamp) {
    require_finite(e_target, "target Young's modulus");
    require_positive(tau_min, "minimum beam radius tau_min");
    if (!(std::isfinite(rho_min) && rho_min >= 0)) throw invalid_input("rho_min must be finite and >= 0");
    const double rho_max = 1.0 / std::pow(2 * tau_min, 3);
    if (rho_min > rho_max) throw invalid_input("rho_min exceeds the full-block density 1/(2 tau_min)^3");
    double lo = rho_min, hi = rho_max;
    double flo = static_cast<double>(P(lo, tau_min)) - e_target, fhi = static_cast<double>(P(hi, tau_min)) - e_target;
    if (!std::isfinite(flo) || !std::isfinite(fhi)) throw invalid_input("elasticity model is not finite at tau_min");
    if (flo > 0 || fhi < 0) {
        if (policy == out_of_range::throw_no_solution)
            throw no_solution("target Young's modulus " + std::to_string(e_target) + " is outside [" +
                              std::to_string(flo + e_target) + ", " + std::to_string(fhi + e_target) +
                              "] reachable with tau = tau_min");
        return {flo > 0 ? lo : hi, tau_min};
    }
    for (int it = 0; it < 200 && hi - lo > 1e-14 * (1 + hi); ++it) {
        const double mid = 0.5 * (lo + hi);
        const double fm = static_cast<double>(P(mid, tau_min)) - e_target;
        if (fm < 0) lo = mid;
        else hi = mid;
    }
    return {0.5 * (lo + hi), tau_min};
}

/// The shipped fit of elasticity_fit.hpp as a polynomial: E/Es = P(rho [seeds/mm^3], tau [mm]).
[[nodiscard]] inline elasticity_polynomial fitted_elasticity() {
    return {fitted::degree, std::vector<double>(std::begin(fitted::coefficients), std::end(fitted::coefficients))};
}

/// Densities of the sampled band at radius tau: [f_min, f_max] / (2 tau)^3 (see the file comment).
[[nodiscard]] inline std::pair<double, double> fitted_density_range(double tau) {
    const double b = 1.0 / (8.0 * tau * tau * tau);
    return {fitted::fraction_min * b, fitted::fraction_max * b};
}

/// Inverse of the shipped fit at tau = tau_min (§4.2): rho in the sampled band with
/// P(rho, tau_min) = e_target. Throws invalid_input for non-finite input or tau_min outside
/// [fitted::tau_min, fitted::tau_max]; outside [P(rho_lo), P(rho_hi)] clamps or throws
/// no_solution by `policy`.
[[nodiscard]] inline foam_parameters inverse_fitted_elasticity(double e_target, double tau_min,
                                                               out_of_range policy = out_of_range::clamp) {
    require_finite(e_target, "target Young's modulus");
    require_positive(tau_min, "minimum beam radius tau_min");
    if (tau_min < fitted::tau_min * (1 - 1e-12) || tau_min > fitted::tau_max * (1 + 1e-12))
        throw invalid_input("beam radius tau_min = " + std::to_string(tau_min) + " mm is outside the radii [" +
                            std::to_string(fitted::tau_min) + ", " + std::to_string(fitted::tau_max) +
                            "] mm the shipped elasticity fit was sampled on (re-run examples/foam_fit for other radii)");
    const elasticity_polynomial P = fitted_elasticity();
    // not a structured binding: clang 14 cannot capture one in a lambda
    const auto band = fitted_density_range(tau_min);
    const double lo = band.first, hi = band.second;
    // inverse_elasticity bisects on [rho_min, full-block bound]; restrict the model to the band by
    // holding it constant above hi, then pull the answer back into the band.
    const auto banded = [&](double rho, double tau) { return P(std::min(rho, hi), tau); };
    const double e_hi = P(hi, tau_min);
    if (e_target > e_hi) {
        if (policy == out_of_range::throw_no_solution)
            throw no_solution("target Young's modulus " + std::to_string(e_target) + " is above " + std::to_string(e_hi) +
                              ", the stiffest foam of the fitted range at tau = " + std::to_string(tau_min) + " mm");
        return {hi, tau_min};
    }
    foam_parameters p = inverse_elasticity(banded, e_target, tau_min, lo, policy);
    p.density = std::min(p.density, hi);
    return p;
}

}  // namespace fabsynth::foam
