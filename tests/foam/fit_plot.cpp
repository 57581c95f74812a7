// foam/fit_plot.hpp: the elasticity-fit figure puts every sample in both panels in its radius's
// colour and draws the fitted Gibson-Ashby curve through its own values.
#include <catch2/catch.hpp>

#include <cmath>

#include "fabsynth/foam/fit_plot.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

TEST_CASE("elasticity fit figure: samples in their radius colour, the fitted curve", "[foam][fit_plot]") {
    elasticity_fit_config c;  // omega range 0.04..0.5
    elasticity_fit_report r;
    const double taus[2] = {0.2, 0.3};
    for (int i = 0; i < 6; ++i) {
        homogenized_sample s;
        s.s.radius = taus[i % 2];
        s.s.density = 0.05 * (i + 1);
        s.s.volume_fraction = 0.05 + 0.06 * i;
        s.s.E = 0.85 * std::pow(s.s.volume_fraction, 1.95);
        r.samples.push_back(s);
    }
    r.gibson_ashby = {.C = 0.85, .n = 1.95, .samples_used = 6};
    r.gibson_ashby_ok = true;
    const image8 img = draw_elasticity_fit(c, r);
    REQUIRE(img.width == 1640);
    REQUIRE(img.height == 700);
    REQUIRE(img.channels == 3);
    auto at = [&](double x, double y) { return rgb8{img.at(int(std::lround(x)), int(std::lround(y)), 0), img.at(int(std::lround(x)), int(std::lround(y)), 1),
                                                   img.at(int(std::lround(x)), int(std::lround(y)), 2)}; };
    // the right panel: w in [0, max(0.1, min(1, 1.08 w_max))] over x = 1020..1610, E/Es in
    // [0, 1.08 E_max] over y = 560..70 (the layout documented in the header's panels)
    double wmax = 0, emax = 0;
    for (const auto& s : r.samples) wmax = std::max(wmax, s.s.volume_fraction), emax = std::max(emax, s.s.E);
    const double wtop = std::max(0.1, std::min(1.0, 1.08 * wmax)), etop = 1.08 * emax;
    auto X = [&](double w) { return 1020 + w / wtop * 590; };
    auto Y = [&](double e) { return 560 - e / etop * 490; };
    for (std::size_t i = 0; i < r.samples.size(); ++i) {
        const auto& s = r.samples[i].s;
        INFO("sample " << i);
        CHECK(at(X(s.volume_fraction), Y(s.E)) == plot_colour(i % 2));
    }
    CHECK(plot_colour(0) != plot_colour(1));
    // the fitted curve (black, 2 px) at the middle of its range, where no sample lies
    const double w = 0.5 * (c.omega_lo + c.omega_hi) + 0.013;
    bool black = false;
    for (int d = -1; d <= 1; ++d) black = black || at(X(w), Y(r.gibson_ashby(w)) + d) == rgb8{0, 0, 0};
    CHECK(black);
    // a report with no samples still draws the axes (no division by zero, no crash)
    const image8 empty = draw_elasticity_fit(c, elasticity_fit_report{});
    CHECK(empty.width == 1640);
}
