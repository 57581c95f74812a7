#include <catch2/catch.hpp>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/foam/fit.hpp>

#include <cmath>
#include <vector>

using namespace fabsynth;
using namespace fabsynth::foam;

TEST_CASE("fit_polynomial recovers an exact degree-4 polynomial", "[foam][fit]") {
    elasticity_polynomial truth{4, {}};
    counter_rng r(11);
    for (int k = 0; k < 15; ++k) truth.coeffs.push_back(r.uniform(-1, 1));
    std::vector<elasticity_sample> s;
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 5; ++j) {
            elasticity_sample e;
            e.density = 0.05 + 0.6 * i;  // seeds/mm^3, the paper's range
            e.radius = 0.2 + 0.025 * j;  // mm
            e.E = truth(e.density, e.radius);
            s.push_back(e);
        }
    const auto P = fit_polynomial(s, 4);
    REQUIRE(P.coeffs.size() == 15);
    for (const auto& e : s) CHECK(P(e.density, e.radius) == Approx(e.E).margin(1e-8 * (1 + std::abs(e.E))));
    CHECK(max_relative_deviation(P, s) < 1e-6);
    CHECK_THROWS_AS(fit_polynomial(std::span(s).first(10), 4), invalid_input);
}

TEST_CASE("fit_power_law recovers Gibson-Ashby constants and respects the range", "[foam][fit]") {
    std::vector<elasticity_sample> s;
    for (int k = 1; k < 90; ++k) {
        const double w = 0.01 * k;
        elasticity_sample e;
        e.volume_fraction = w;
        e.E = 0.85 * std::pow(w, 1.95) * (w >= 0.5 ? 3.0 : 1.0);  // outside the range: must be ignored
        s.push_back(e);
    }
    const auto g = fit_power_law(s, 0.04, 0.5);
    CHECK(g.C == Approx(0.85).epsilon(1e-12));
    CHECK(g.n == Approx(1.95).epsilon(1e-12));
    CHECK(g.samples_used == 45);  // w = 0.05 .. 0.49: the range is open at both ends
    CHECK_THROWS_AS(fit_power_law(s, 0.95, 0.99), no_solution);
}
