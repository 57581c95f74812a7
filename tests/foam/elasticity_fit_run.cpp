// foam_fit end to end on small samples (examples/foam_fit/foam_fit.hpp): the CSV it writes, its
// determinism across thread counts, the scale invariance its fit relies on, its coverage against
// the evaluator's own coverage, and bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../../examples/foam_fit/foam_fit.hpp"

using namespace fabsynth;
namespace fs = std::filesystem;

namespace {
std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}
foam_fit::config small_config() {
    foam_fit::config c;
    c.pairs = {{0.15, 0.25}, {0.3, 0.25}, {0.15, 0.3}};
    c.seeds_per_pair = 1;
    c.first_seed = 3;
    c.elements = 16;
    c.supersample = 3;
    return c;
}
}  // namespace

TEST_CASE("foam_fit small run: E grows with rho and tau, nu near 0.3, same CSV on 1 and 2 threads", "[foam][elasticity_fit]") {
    const fs::path dir = fs::path(FABSYNTH_TEST_TMP) / "foam_fit_run";
    fs::create_directories(dir);
    foam_fit::config c = small_config();
    std::string csv[2];
    for (unsigned t : {1u, 2u}) {
        set_num_threads(t);
        c.csv = (dir / ("samples_" + std::to_string(t) + ".csv")).string();
        const foam_fit::report r = foam_fit::run(c);
        REQUIRE(r.samples.size() == 3);
        csv[t - 1] = slurp(c.csv);
    }
    set_num_threads(0);
    CHECK(csv[0] == csv[1]);
    const auto s = foam_fit::read_csv(c.csv);
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
}

TEST_CASE("foam_fit samples are scale invariant: (rho, tau) and (8 rho, tau / 2) give the same E", "[foam][elasticity_fit]") {
    // the property foam_fit::fit_points relies on, checked by homogenizing both samples
    foam_fit::config c = small_config();
    const auto a = foam_fit::homogenize_sample(0.2, 0.3, 9, c);
    const auto b = foam_fit::homogenize_sample(1.6, 0.15, 9, c);
    CHECK(a.period == b.period);
    CHECK(std::abs(a.s.volume_fraction - b.s.volume_fraction) <= 1e-3 * a.s.volume_fraction);
    CHECK(std::abs(a.s.E - b.s.E) <= 1e-3 * a.s.E);
    CHECK(std::abs(a.s.nu - b.s.nu) <= 1e-3);
    // a different seed is a genuinely different sample (so the check above is not vacuous)
    const auto d = foam_fit::homogenize_sample(0.2, 0.3, 10, c);
    CHECK(d.s.volume_fraction != a.s.volume_fraction);
}

TEST_CASE("foam_fit voxel densities equal voronoi_foam::coverage", "[foam][elasticity_fit]") {
    foam_fit::config c = small_config();
    c.elements = 12;
    std::int64_t P = 0;
    const double rho = 0.5, tau = 0.25;
    const voxel_grid<double> g = foam_fit::sample_densities(rho, tau, 4, c, &P);
    const double L = c.elements * tau / static_cast<double>(P);
    const foam::voronoi_foam foam(foam::constant_field{rho}, foam::constant_field{tau},
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
        foam_fit::config c = small_config();
        change(c);
        return c;
    };
    using C = foam_fit::config;
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.pairs.clear(); })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.pairs[0].rho = std::nan(""); })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.pairs[0].rho = -0.1; })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.pairs[0].rho = 0; })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.pairs[1].tau = std::nan(""); })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.pairs[1].tau = -0.25; })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.pairs[1].tau = 0; })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.pairs[1].tau = std::numeric_limits<double>::infinity(); })), invalid_input);
    // above the full-block bound 1 / (2 tau)^3 = 8 for tau = 0.25
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.pairs[0] = {8.01, 0.25}; })), invalid_input);
    CHECK_NOTHROW(foam_fit::validate(with([](C& c) { c.pairs[0] = {8.0, 0.25}; })));
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.elements = 6; })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.elements = 17; })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.seeds_per_pair = 0; })), invalid_input);
    CHECK_THROWS_AS(foam_fit::validate(with([](C& c) { c.supersample = 0; })), invalid_input);
    CHECK_THROWS_AS(foam_fit::run(with([](C& c) { c.pairs.clear(); })), invalid_input);
    // a header needs at least 15 fit points; nothing is written when refused
    const fs::path hdr = fs::path(FABSYNTH_TEST_TMP) / "foam_fit_refused.hpp";
    fs::remove(hdr);
    CHECK_THROWS_AS(foam_fit::run(with([&](C& c) {
                        c.pairs.resize(1);
                        c.elements = 8;
                        c.header = hdr.string();
                    })),
                    invalid_input);
    CHECK_FALSE(fs::exists(hdr));
}
