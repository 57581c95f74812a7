// Seed process (Algorithm 3): count vs integral of rho, >= 1 seed per coarse cell, order independence.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "fabsynth/foam/seeds.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

TEST_CASE("seed count matches the integral of rho within 2%", "[foam][seeds]") {
    SECTION("uniform") {
        seed_generator g(constant_field{0.7}, {.cell = 2, .seed = 3});
        const box3 b({0, 0, 0}, {40, 20, 20});
        const double want = 0.7 * b.volume();
        const double got = static_cast<double>(g.seeds_in_box(b).size());
        CHECK(std::abs(got - want) < 0.02 * want);
    }
    SECTION("linear gradient across subdivision levels") {
        // 0.2 .. 6 seeds/mm^3 with L = 2: t from 1.6 (leaf at level 0) to 48 (two levels)
        seed_generator g(linear_field{0, 0.2, 6.0, 0, 40}, {.cell = 2, .seed = 4});
        const box3 b({0, 0, 0}, {40, 12, 12});
        const double want = 0.5 * (0.2 + 6.0) * b.volume();  // exact integral of the ramp
        const double got = static_cast<double>(g.seeds_in_box(b).size());
        INFO("want " << want << " got " << got);
        CHECK(std::abs(got - want) < 0.02 * want);
    }
    SECTION("smooth radial field") {
        auto rho = [](const vec3& x) { return 0.3 + 2.0 * std::exp(-glm::dot(x, x) / 50.0); };
        seed_generator g(rho, {.cell = 2, .seed = 5});
        const box3 b({-20, -20, -20}, {20, 20, 20});
        // integral: 0.3 V + 2 (pi 50)^{3/2} (the Gaussian tail outside the box is negligible)
        const double want = 0.3 * b.volume() + 2.0 * std::pow(3.14159265358979 * 50.0, 1.5);
        const double got = static_cast<double>(g.seeds_in_box(b).size());
        INFO("want " << want << " got " << got);
        CHECK(std::abs(got - want) < 0.02 * want);
    }
}

TEST_CASE("every coarse cell holds a seed; seeds stay in their cell", "[foam][seeds]") {
    // a spiky field: high at cell centres, tiny elsewhere, so subdivided cells may draw nothing
    auto rho = [](const vec3& x) {
        const vec3 f = glm::fract(x / 2.0) - 0.5;
        return glm::dot(f, f) < 1e-4 ? 50.0 : 1e-6;
    };
    seed_generator g(rho, {.cell = 2, .seed = 6});
    std::vector<vec3> s;
    for (int z = -3; z < 3; ++z)
        for (int y = -3; y < 3; ++y)
            for (int x = -3; x < 3; ++x) {
                s.clear();
                g.cell_seeds({x, y, z}, s);
                REQUIRE(!s.empty());
                for (const vec3& p : s) REQUIRE(box3(vec3(x, y, z) * 2.0, vec3(x + 1, y + 1, z + 1) * 2.0).contains(p));
            }
}

TEST_CASE("seeds do not depend on query order or box split", "[foam][seeds]") {
    seed_generator g(linear_field{2, 0.1, 3.0, -5, 5}, {.cell = 2.5, .seed = 77});
    auto whole = g.seeds_in_box({{-5, -5, -5}, {5, 5, 5}});
    std::vector<vec3> parts;
    for (int z = 4; z >= 0; --z)  // reverse order, two-millimetre slabs
        for (const vec3& p : g.seeds_in_box({{-5, -5, -5 + 2.0 * z}, {5, 5, -3 + 2.0 * z}}))
            if (p.z < -3 + 2.0 * z || z == 4) parts.push_back(p);
    auto key = [](const vec3& a, const vec3& b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
    std::sort(whole.begin(), whole.end(), key);
    std::sort(parts.begin(), parts.end(), key);
    CHECK(whole == parts);
    seed_generator other(linear_field{2, 0.1, 3.0, -5, 5}, {.cell = 2.5, .seed = 78});
    CHECK(other.seeds_in_box({{-5, -5, -5}, {5, 5, 5}}).size() != 0);
    CHECK(other.seeds_in_box({{-5, -5, -5}, {5, 5, 5}}) != g.seeds_in_box({{-5, -5, -5}, {5, 5, 5}}));
}
