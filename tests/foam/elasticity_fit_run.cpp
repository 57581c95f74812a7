// The elasticity fit end to end on small samples (foam/elasticity_samples.hpp,
// foam/elasticity_study.hpp, foam/elasticity_text.hpp): the CSV text, its determinism across thread
// counts, the scale invariance the fit relies on, the sample cache, the coverage against the
// evaluator's own coverage, and bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/foam/elasticity_samples.hpp"
#include "fabsynth/foam/elasticity_study.hpp"
#include "fabsynth/foam/elasticity_text.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

namespace {
elasticity_fit_config small_config() {
    elasticity_fit_config c;
    c.pairs = {{0.15, 0.25}, {0.3, 0.25}, {0.15, 0.3}};
    c.seeds_per_pair = 1;
    c.first_seed = 3;
    c.elements = 16;
    c.supersample = 3;
    return c;
}
}  // namespace

TEST_CASE("foam_fit small run: E grows with rho and tau, nu near 0.3, same CSV on 1 and 2 threads", "[foam][elasticity_fit]") {
    elasticity_fit_config c = small_config();
    std::string csv[2];
    sample_cache cache;  // filled by the second run
    std::size_t computed = 0;
    auto count = [&](const homogenized_sample&, std::size_t, std::size_t, bool fresh) { computed += fresh; };
    for (unsigned t : {1u, 2u}) {
        set_num_threads(t);
        const elasticity_fit_report r = t == 1 ? run_elasticity_fit(c) : run_elasticity_fit(c, &cache, count);
        REQUIRE(r.samples.size() == 3);
        csv[t - 1] = format_samples_csv(r.samples);
    }
    set_num_threads(0);
    CHECK(csv[0] == csv[1]);
    const auto s = parse_samples_csv(csv[0], "run");
    REQUIRE(s.size() == 3);
    CHECK(s[1].E > s[0].E);  // denser, same radius
    CHECK(s[2].E > s[0].E);  // same density, thicker beams
    CHECK(s[1].volume_fraction > s[0].volume_fraction);
    for (const auto& x : s) {
        INFO("rho " << x.density << " tau " << x.radius << ": E " << x.E << " nu " << x.nu << " w " << x.volume_fraction);
        CHECK(x.E > 0.005);
        CHECK(x.E < x.volume_fraction);  // Voigt bound (Es = 1)
        // open-cell foams keep roughly the base material's Poisson's ratio (paper §4.3.1, Fig. 8b):
        // between 0.2 and 0.4 for these relative volumes
        CHECK(x.nu > 0.2);
        CHECK(x.nu < 0.4);
        CHECK(x.anisotropy < 0.25);  // small samples: 16^3 elements, few seeds
    }
    // a run through the cache (written as text and read back) computes nothing and reports the same
    CHECK(computed == 3);
    CHECK(cache.size() == 3);
    const sample_cache reread = parse_sample_cache(format_sample_cache(cache), "cache");
    sample_cache again = reread;
    const elasticity_fit_report r2 = run_elasticity_fit(c, &again, count);
    CHECK(computed == 3);
    CHECK(format_samples_csv(r2.samples) == csv[0]);
    for (const auto& x : r2.samples) CHECK(x.cached);
}

TEST_CASE("foam_fit samples are scale invariant: (rho, tau) and (8 rho, tau / 2) give the same E", "[foam][elasticity_fit]") {
    // the property fit_points (fit.hpp) relies on, checked by homogenizing both samples
    elasticity_fit_config c = small_config();
    const auto a = homogenize_sample(0.2, 0.3, 9, c);
    const auto b = homogenize_sample(1.6, 0.15, 9, c);
    CHECK(a.period == b.period);
    CHECK(std::abs(a.s.volume_fraction - b.s.volume_fraction) <= 1e-3 * a.s.volume_fraction);
    CHECK(std::abs(a.s.E - b.s.E) <= 1e-3 * a.s.E);
    CHECK(std::abs(a.s.nu - b.s.nu) <= 1e-3);
    // a different seed is a genuinely different sample (so the check above is not vacuous)
    const auto d = homogenize_sample(0.2, 0.3, 10, c);
    CHECK(d.s.volume_fraction != a.s.volume_fraction);
}

TEST_CASE("foam_fit voxel densities equal voronoi_foam::coverage", "[foam][elasticity_fit]") {
    elasticity_fit_config c = small_config();
    c.elements = 12;
    std::int64_t P = 0;
    const double rho = 0.5, tau = 0.25;
    const voxel_grid<double> g = sample_densities(rho, tau, 4, c, &P);
    const double L = c.elements * tau / static_cast<double>(P);
    const voronoi_foam foam(constant_field{rho}, constant_field{tau},
                                  {.cell = L, .seed = 4, .period = i64vec3(P)});
    int differ = 0, partial = 0;
    for (int z = 0; z < c.elements; ++z)
        for (int y = 0; y < c.elements; ++y)
            for (int x = 0; x < c.elements; ++x) {
                const double want = foam.coverage((vec3(x, y, z) + 0.5) * tau, tau, c.supersample);
                differ += std::abs(g.get({x, y, z}) - want) > 1e-12;
                partial += want > 0 && want < 1;
            }
    CHECK(differ == 0);
    CHECK(partial > 100);
}

TEST_CASE("foam_fit rejects bad input", "[foam][elasticity_fit]") {
    auto with = [](auto change) {
        elasticity_fit_config c = small_config();
        change(c);
        return c;
    };
    using C = elasticity_fit_config;
    CHECK_THROWS_AS(with([](C& c) { c.pairs.clear(); }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.pairs[0].density = std::nan(""); }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.pairs[0].density = -0.1; }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.pairs[0].density = 0; }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.pairs[1].radius = std::nan(""); }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.pairs[1].radius = -0.25; }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.pairs[1].radius = 0; }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.pairs[1].radius = std::numeric_limits<double>::infinity(); }).validate(), invalid_input);
    // above the full-block bound 1 / (2 tau)^3 = 8 for tau = 0.25
    CHECK_THROWS_AS(with([](C& c) { c.pairs[0] = {8.01, 0.25}; }).validate(), invalid_input);
    CHECK_NOTHROW(with([](C& c) { c.pairs[0] = {8.0, 0.25}; }).validate());
    CHECK_THROWS_AS(with([](C& c) { c.elements = 6; }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.elements = 17; }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.seeds_per_pair = 0; }).validate(), invalid_input);
    CHECK_THROWS_AS(with([](C& c) { c.supersample = 0; }).validate(), invalid_input);
    CHECK_THROWS_AS(run_elasticity_fit(with([](C& c) { c.pairs.clear(); })), invalid_input);
    // a header needs at least 15 fit points
    const elasticity_fit_report few = run_elasticity_fit(with([&](C& c) {
        c.pairs.resize(1);
        c.elements = 8;
    }));
    CHECK(few.P.coeffs.empty());
    CHECK_THROWS_AS(format_elasticity_fit_header(small_config(), few), invalid_input);
}
