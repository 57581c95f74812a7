#pragma once
/// @file elasticity.hpp  Elasticity control hook (paper §4.2): from a target Young's modulus to
/// foam parameters (rho, tau), given a fitted model E = P(rho, tau).
///
/// The fitted degree-4 polynomial of the paper (§4.1) comes from homogenization, which is not
/// part of this header: the coefficients are data (`elasticity_polynomial`), to be filled from a
/// fit. Strategy of §4.2: tau = tau_min (thinnest printable beam), rho solves
/// P(rho, tau_min) = E_target on [rho_min, rho_max] with rho_max = 1 / (2 tau_min)^3 (the block is
/// full beyond it). The solve is bisection on a bracket, so it needs P(rho_min) <= E <= P(rho_max)
/// (monotone models; the paper's fit is increasing in rho).
///
/// Usage:
///   elasticity_polynomial P{4, coeffs};          // coeffs ordered as in elasticity_polynomial
///   foam_parameters p = inverse_elasticity(P, 0.01, 0.25);   // E relative to the base material
#include <cmath>
#include <concepts>
#include <cstddef>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"

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

/// PROVISIONAL model until the homogenization fit exists (issue 4, item 4): Gibson-Ashby
/// E/Es = 0.85 w^1.95 (paper §4.3.1 constants) with the relative volume estimated as
/// w = pi tau^2 * 5.832 rho^(2/3), the edge length per volume of a Poisson-Voronoi tessellation
/// (Meijering 1953) times the beam cross-section, capped at 1. Not the paper's fitted polynomial.
struct provisional_elasticity_model {
    [[nodiscard]] double operator()(double rho, double tau) const {
        const double w = std::min(1.0, 3.14159265358979323846 * tau * tau * 5.832 * std::cbrt(rho * rho));
        return 0.85 * std::pow(w, 1.95);
    }
};

}  // namespace fabsynth::foam
