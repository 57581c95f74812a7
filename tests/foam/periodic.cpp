// Periodic seeds (seeds.hpp, seed_options::period / foam_options::period): the seed set and the foam
// evaluated on it tile space exactly with one period = period * cell.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "fabsynth/foam/evaluator.hpp"
#include "fabsynth/foam/seeds.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

namespace {
bool lex_less(const vec3& a, const vec3& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}
// Matches two seed sets up to `tol` (sorted by x, greedy nearest within tol).
bool same_points(std::vector<vec3> a, std::vector<vec3> b, double tol) {
    if (a.size() != b.size()) return false;
    std::sort(a.begin(), a.end(), lex_less), std::sort(b.begin(), b.end(), lex_less);
    for (std::size_t i = 0; i < a.size(); ++i)
        if (glm::length(a[i] - b[i]) > tol) return false;
    return true;
}
}  // namespace

TEST_CASE("periodic seeds: a box shifted by one period holds the shifted seeds", "[foam][periodic]") {
    // graded density (wrapped lookups) across subdivision levels: t = L^3 rho from 0.7 to 23
    const i64vec3 P(3, 4, 2);
    const double L = 1.7;
    seed_generator g(linear_field{0, 0.15, 4.7, 0, 3 * L}, {.cell = L, .seed = 11, .period = P});
    REQUIRE(g.periodic());
    const box3 b({-2.3, -1.1, 0.4}, {4.9, 5.2, 6.3});
    const std::vector<vec3> base = g.seeds_in_box(b);
    REQUIRE(base.size() > 100);
    for (int a = 0; a < 3; ++a)
        for (int k : {-2, 1, 3}) {
            vec3 shift(0.0);
            shift[a] = k * static_cast<double>(P[a]) * L;
            std::vector<vec3> moved = g.seeds_in_box(box3(b.lo + shift, b.hi + shift));
            for (vec3& s : moved) s -= shift;
            // seeds on the box boundary may fall either side after rounding: compare well inside
            auto inner = [&](std::vector<vec3> v) {
                std::erase_if(v, [&](const vec3& s) {
                    for (int d = 0; d < 3; ++d)
                        if (s[d] < b.lo[d] + 1e-9 || s[d] > b.hi[d] - 1e-9) return true;
                    return false;
                });
                return v;
            };
            INFO("axis " << a << " shift " << k << " periods");
            CHECK(same_points(inner(base), inner(moved), 1e-11));
        }
    // cell by cell: cell c + P_a e_a holds the seeds of c moved by P_a L
    for (std::int64_t x = -4; x <= 4; ++x) {
        std::vector<vec3> s0, s1;
        g.cell_seeds({x, 1, -1}, s0);
        g.cell_seeds({x + P.x, 1, -1 - 2 * P.z}, s1);
        REQUIRE(s0.size() == s1.size());
        for (std::size_t i = 0; i < s0.size(); ++i) CHECK(glm::length(s1[i] - (s0[i] + vec3(P.x * L, 0, -2 * P.z * L))) < 1e-12);
    }
}

TEST_CASE("periodic seeds equal the aperiodic seeds inside the base period", "[foam][periodic]") {
    // wrapping is the identity on cells [0, P): same hash keys, same density lookups
    const double L = 2.0;
    auto rho = [](const vec3& x) { return 0.3 + 1.5 * std::exp(-glm::dot(x - vec3(4), x - vec3(4)) / 8.0); };
    seed_generator per(rho, {.cell = L, .seed = 5, .period = {4, 4, 4}});
    seed_generator aper(rho, {.cell = L, .seed = 5});
    const box3 base({0, 0, 0}, {4 * L - 1e-9, 4 * L - 1e-9, 4 * L - 1e-9});
    CHECK(same_points(per.seeds_in_box(base), aper.seeds_in_box(base), 0.0));
    // and differ outside it (the aperiodic process does not repeat)
    const box3 next({4 * L, 0, 0}, {8 * L - 1e-9, 4 * L - 1e-9, 4 * L - 1e-9});
    CHECK_FALSE(same_points(per.seeds_in_box(next), aper.seeds_in_box(next), 1e-6));
}

TEST_CASE("periodic foam: F(q) == F(q + S e_a) for random q", "[foam][periodic]") {
    const double L = 2.5, tau = 0.3;
    const i64vec3 P(3, 2, 4);
    const vec3 S = vec3(P) * L;
    voronoi_foam foam(constant_field{0.35}, constant_field{tau}, {.cell = L, .seed = 2016, .period = P});
    REQUIRE(foam.seeds().periodic());
    REQUIRE(foam.seeds().period_length() == S);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-6.0, 12.0);
    int solid = 0, checked = 0;
    for (int i = 0; i < 3000; ++i) {
        const vec3 q(u(rng), u(rng), u(rng));
        // points within 1e-9 of the beam surface may flip by rounding; skip them
        const double d = foam.distance_to_edges(q, L);
        if (std::abs(d - tau) < 1e-9) continue;
        const bool f = foam.contains(q);
        solid += f, ++checked;
        for (int a = 0; a < 3; ++a)
            for (int k : {-1, 1, 2}) {
                vec3 shift(0.0);
                shift[a] = k * S[a];
                if (foam.contains(q + shift) != f) {
                    FAIL_CHECK("F differs at q = (" << q.x << ", " << q.y << ", " << q.z << ") shifted by " << k << " periods along axis " << a);
                }
            }
    }
    INFO("solid fraction " << double(solid) / checked);
    CHECK(checked > 2900);
    CHECK(solid > 100);
    CHECK(solid < checked - 100);
}

TEST_CASE("periodic seeds: bad periods are refused", "[foam][periodic]") {
    CHECK_THROWS_AS(seed_generator(constant_field{1.0}, {.cell = 2, .period = {0, 3, 3}}), invalid_input);
    CHECK_THROWS_AS(seed_generator(constant_field{1.0}, {.cell = 2, .period = {3, -1, 3}}), invalid_input);
    CHECK_THROWS_AS(seed_generator(constant_field{1.0}, {.cell = 2, .period = {3, 3, std::int64_t{1} << 40}}), invalid_input);
    CHECK_THROWS_AS(voronoi_foam(constant_field{0.5}, constant_field{0.2}, {.cell = 2, .period = {2, 0, 2}}), invalid_input);
    CHECK_NOTHROW(seed_generator(constant_field{1.0}, {.cell = 2, .period = {1, 1, 1}}));
    CHECK_FALSE(seed_generator(constant_field{1.0}, {.cell = 2}).periodic());
}
