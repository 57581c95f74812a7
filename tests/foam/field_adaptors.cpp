// Field adaptors (foam/fields.hpp variant_field, foam/field_adaptors.hpp), each against a direct
// computation written here without the adaptor.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/foam/elasticity.hpp"
#include "fabsynth/foam/evaluator.hpp"
#include "fabsynth/foam/field_adaptors.hpp"
#include "support/sphere_mesh.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

TEST_CASE("image_field: nearest pixel of the picture seen from +z, row 0 at y1", "[foam][fields]") {
    image8 img(4, 3, 1, 0);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) img.at(i, j) = static_cast<std::uint8_t>(20 * (i + 4 * j));
    const box2 rect({1, 2}, {9, 8});  // pixels of 2 x 2 mm
    const image_field f(img, rect, 0.1, 0.6);
    STATIC_REQUIRE(bounded_field<image_field>);
    CHECK(f.max_value() == 0.6);
    // centres of pixel (i, j): x = 1 + 2 i + 1, y = 8 - 2 j - 1
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) {
            const double want = 0.1 + 0.5 * (20.0 * (i + 4 * j)) / 255.0;
            CHECK(f({2.0 + 2 * i, 7.0 - 2 * j, 5.0}) == Approx(want).epsilon(1e-14));
            CHECK(f({2.0 + 2 * i, 7.0 - 2 * j, -40.0}) == f({2.0 + 2 * i, 7.0 - 2 * j, 5.0}));  // every z-plane
        }
    // outside the rectangle: the nearest border pixel
    CHECK(f({-5, 7.5, 0}) == f({1.5, 7.5, 0}));
    CHECK(f({100, -100, 0}) == f({8.5, 2.5, 0}));
    CHECK(f({8.5, 2.5, 0}) == Approx(0.1 + 0.5 * 220.0 / 255.0));
    // a random point against the index computed here
    counter_rng rng(1, 2);
    for (int n = 0; n < 200; ++n) {
        const vec3 p(rng.uniform() * 8 + 1, rng.uniform() * 6 + 2, 0);
        const int i = std::min(3, static_cast<int>((p.x - 1) / 2)), j = std::min(2, static_cast<int>((8 - p.y) / 2));
        CHECK(f(p) == Approx(0.1 + 0.5 * img.at(i, j) / 255.0).epsilon(1e-14));
    }
    CHECK_THROWS_AS(image_field(img, box2({1, 2}, {1, 8}), 0, 1), invalid_input);
    CHECK_THROWS_AS(image_field(image8(), rect, 0, 1), invalid_input);
    CHECK_THROWS_AS(image_field(img, rect, std::nan(""), 1), invalid_input);
}

TEST_CASE("surface_distance_field: linear in the distance to the surface up to depth", "[foam][fields]") {
    const triangle_mesh m = test::sphere_mesh(5.0, 3);
    const mesh_distance md(m);
    const surface_distance_field f(md, 0.6, 0.1, 2.0);
    STATIC_REQUIRE(bounded_field<surface_distance_field>);
    CHECK(f.max_value() == 0.6);
    counter_rng rng(3, 4);
    for (int n = 0; n < 300; ++n) {
        const vec3 p = vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 14.0 - 7.0;
        const double d = md.unsigned_distance(p);  // the direct computation
        const double want = 0.6 + (0.1 - 0.6) * std::min(d / 2.0, 1.0);
        INFO("p " << p.x << " " << p.y << " " << p.z << " d " << d);
        CHECK(f(p) == Approx(want).margin(1e-12));
    }
    CHECK(f(vec3(0)) == Approx(0.1).epsilon(1e-14));  // centre: 5 mm deep
    CHECK_THROWS_AS(surface_distance_field(md, 0.6, 0.1, 0.0), invalid_input);
}

TEST_CASE("elasticity_density_field: E/Es -> density by the shipped fit", "[foam][fields]") {
    const double tau = 0.25;
    const linear_field e{.axis = 2, .v0 = 0.05, .v1 = 0.4, .x0 = 0, .x1 = 30};
    const elasticity_density_field rho(e, tau, 0.05, 0.4);
    STATIC_REQUIRE(bounded_field<elasticity_density_field<linear_field>>);
    const elasticity_polynomial P = fitted_elasticity();
    // exact at the 257 table nodes: the inverse of the fit, computed directly
    for (int i = 0; i <= 256; i += 8) {
        const double target = 0.05 + (0.4 - 0.05) * i / 256.0;
        const double z = (target - 0.05) / (0.4 - 0.05) * 30;
        const double direct = inverse_fitted_elasticity(target, tau).density;
        INFO("node " << i << " target " << target);
        CHECK(rho({0, 0, z}) == Approx(direct).epsilon(1e-9));
    }
    // between nodes the modulus of the mapped density is within 1e-3 (relative) of the target
    const auto [reach_lo, reach_hi] = rho.reachable();
    CHECK(reach_lo == P(fitted_density_range(tau).first, tau));
    CHECK(reach_hi == P(fitted_density_range(tau).second, tau));
    counter_rng rng(5, 6);
    for (int n = 0; n < 200; ++n) {
        const double z = rng.uniform() * 30;
        const double target = e({0, 0, z});
        if (target < reach_lo || target > reach_hi) continue;
        CHECK(P(rho({0, 0, z}), tau) == Approx(target).epsilon(1e-3));
    }
    // monotone, and bounded by its max_value
    double prev = 0;
    for (int k = 0; k <= 300; ++k) {
        const double v = rho({0, 0, 0.1 * k});
        CHECK(v >= prev);
        CHECK(v <= rho.max_value());
        prev = v;
    }
    // below e_lo / above e_hi: clamped to the ends
    CHECK(rho({0, 0, -10}) == rho({0, 0, 0}));
    CHECK(rho({0, 0, 99}) == rho({0, 0, 30}));
    // a constant field (equal ends) works; a radius outside the fit, or e_lo > e_hi, throws
    const elasticity_density_field flat(constant_field{0.1}, tau, 0.1, 0.1);
    CHECK(flat({1, 2, 3}) == Approx(inverse_fitted_elasticity(0.1, tau).density).epsilon(1e-9));
    CHECK_THROWS_AS(elasticity_density_field(e, 1.0, 0.05, 0.4), invalid_input);
    CHECK_THROWS_AS(elasticity_density_field(e, tau, 0.4, 0.05), invalid_input);
}

TEST_CASE("variant_field: the held field's values and bound, bit for bit", "[foam][fields]") {
    using V = variant_field<constant_field, linear_field>;
    STATIC_REQUIRE(bounded_field<V>);
    const linear_field l{.axis = 1, .v0 = 2, .v1 = 5, .x0 = -1, .x1 = 3};
    const V a{l}, b{constant_field{0.7}};
    counter_rng rng(7, 8);
    for (int n = 0; n < 100; ++n) {
        const vec3 p = vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0 - 5.0;
        CHECK(a(p) == l(p));
        CHECK(b(p) == 0.7);
    }
    CHECK(a.max_value() == 5);
    CHECK(b.max_value() == 0.7);
    // an unbounded alternative makes the variant unbounded
    auto lambda = [](const vec3& p) { return p.x; };
    STATIC_REQUIRE(scalar_field<variant_field<constant_field, decltype(lambda)>>);
    STATIC_REQUIRE_FALSE(bounded_field<variant_field<constant_field, decltype(lambda)>>);
    // and a foam over it is the foam over the held field
    const voronoi_foam f1(V{l}, constant_field{0.2}, {.cell = 2, .seed = 5});
    const voronoi_foam f2(l, constant_field{0.2}, {.cell = 2, .seed = 5});
    CHECK(f1.seeds().seeds_in_box({{0, 0, 0}, {6, 6, 6}}) == f2.seeds().seeds_in_box({{0, 0, 0}, {6, 6, 6}}));
}
