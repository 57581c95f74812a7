// Tests for vector_pattern/band_map.hpp: the map is exact on a line, radius R + v on a circle, chord error
// within the tolerance, closed curves glued at the seam (topology re-counted by the raster oracle
// of tests/support/raster_topology.hpp), bad input rejected.
#include <catch2/catch.hpp>

#include "support/test_util.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/curve.hpp"
#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern/band_map.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"
#include "support/raster_topology.hpp"
#include "support/vector_band.hpp"

using namespace fabsynth;
using Catch::Matchers::Contains;

namespace {
using fabsynth::test::rect_ring;

std::vector<polygon_with_holes> band_of(const char* file, double* width = nullptr) { return test::vector_band(file, width); }
}  // namespace

TEST_CASE("band map: a straight line maps the pattern isometrically (output = input)", "[pattern][band_map]") {
    double W = 0;
    const auto band = band_of("vine.svg", &W);
    const auto out = vector_pattern::map_to_curve(band, planar_curve::line(W), {.chord_tolerance = 1e-6});
    REQUIRE(out.size() == band.size());
    for (std::size_t i = 0; i < band.size(); ++i) {
        REQUIRE(out[i].outer.size() == band[i].outer.size());  // nothing to densify on a line
        for (std::size_t k = 0; k < band[i].outer.size(); ++k) {
            CHECK(out[i].outer[k].x == Approx(band[i].outer[k].x).margin(1e-12 * W));
            CHECK(out[i].outer[k].y == Approx(band[i].outer[k].y).margin(1e-12 * W));
        }
        REQUIRE(out[i].holes.size() == band[i].holes.size());
    }
    CHECK(area(out) == Approx(area(band)).epsilon(1e-12));
}

TEST_CASE("band map: on a circle every vertex lies at radius R + v, edges within the chord tolerance", "[pattern][band_map]") {
    const double R = 30.0, L = 2 * std::numbers::pi * R, tol = 1e-3;
    const planar_curve c = planar_curve::circle(R);
    // a sector [u0, u1] x [v0, v1]: its image is an annular sector of known area
    const double u0 = 5, u1 = 40, v0 = -4, v1 = 6;
    const auto out = vector_pattern::map_to_curve({{rect_ring(u0, v0, u1, v1), {}}}, c, {.chord_tolerance = tol});
    REQUIRE(out.size() == 1);
    std::size_t on_inner = 0, on_outer = 0;
    for (const vec2& p : out[0].outer) {
        const double r = glm::length(p);
        CHECK(r >= R + v0 - 1e-9);
        CHECK(r <= R + v1 + 1e-9);
        on_inner += std::abs(r - (R + v0)) < 1e-9;
        on_outer += std::abs(r - (R + v1)) < 1e-9;
    }
    // the two arcs are densified: sagitta r (1 - cos(dphi / 2)) <= tol at radius r
    const double dphi_outer = 2 * std::acos(1 - tol / (R + v1));
    CHECK(on_outer >= static_cast<std::size_t>((u1 - u0) / R / dphi_outer));
    CHECK(on_inner >= 2);
    // and no more than needed (at most 2x the minimal count, by the halving)
    CHECK(on_outer <= 2 * static_cast<std::size_t>(std::ceil((u1 - u0) / R / dphi_outer)) + 2);
    const double exact = 0.5 * (u1 - u0) / R * ((R + v1) * (R + v1) - (R + v0) * (R + v0));
    const double perim = (u1 - u0) / R * (2 * R + v0 + v1) + 2 * (v1 - v0);
    CHECK(area(out) <= exact);
    CHECK(area(out) >= exact - tol * perim);
    // vertex angles: u maps to angle -u/R
    const vec2 first = c.band_point(u0, v0);
    CHECK(glm::length(first - vec2((R + v0) * std::cos(-u0 / R), (R + v0) * std::sin(-u0 / R))) < 1e-12);
    (void)L;
}

TEST_CASE("band map: closed curves glue shapes cut at u = 0 and u = L", "[pattern][band_map]") {
    const double R = 20.0, L = 2 * std::numbers::pi * R;
    const planar_curve c = planar_curve::circle(R);
    SECTION("a bar cut by the seam becomes one polygon with its hole") {
        const std::vector<polygon_with_holes> band{{rect_ring(0, -1, 3, 1), {}},
                                                   {rect_ring(L - 4, -1, L, 1), {rect_ring(L - 3, -0.5, L - 1, 0.5)}},
                                                   {rect_ring(10, -1, 20, 1), {}}};
        const auto out = vector_pattern::map_to_curve(band, c, {.chord_tolerance = 1e-3});
        CHECK(out.size() == 2);
        std::size_t holes = 0;
        for (const auto& p : out) {
            holes += p.holes.size();
            CHECK(is_simple(p.outer));
        }
        CHECK(holes == 1);
        const auto t = test::raster_topology(out, {-R - 2, -R - 2}, {R + 2, R + 2}, 0.05);
        CHECK(t.components == 2);
        CHECK(t.holes == 1);
    }
    SECTION("a full-length band becomes an annulus (one component, one hole)") {
        const auto out = vector_pattern::map_to_curve({{rect_ring(0, -2, L, 2), {}}}, c, {.chord_tolerance = 1e-3});
        REQUIRE(out.size() == 1);
        CHECK(out[0].holes.size() == 1);
        const auto t = test::raster_topology(out, {-R - 3, -R - 3}, {R + 3, R + 3}, 0.05);
        CHECK(t.components == 1);
        CHECK(t.holes == 1);
    }
    SECTION("a periodic exemplar wrapped once around keeps its topology, plus the loop's hole") {
        // zigzag.svg is periodic with period 40 over its 480 width: glued, it closes into a ring
        double W = 0;
        const auto band = band_of("zigzag.svg", &W);
        const planar_curve loop = planar_curve::circle(W / (2 * std::numbers::pi));
        const auto out = vector_pattern::map_to_curve(band, loop, {.chord_tolerance = 0.01});
        const double r = loop.length() / (2 * std::numbers::pi) + 30;
        const auto t = test::raster_topology(out, {-r, -r}, {r, r}, 0.1);
        CHECK(t.components == 1);
        CHECK(t.holes == 1);
        // the band-coordinate oracle with wrap-around agrees
        const auto tb = test::raster_topology(band, {0, -30}, {W, 30}, 0.1, true);
        CHECK(tb.components == 1);
        CHECK(tb.holes == 0);  // the loop's hole is not a hole of the periodic strip
    }
}

TEST_CASE("band map: an exemplar with many holes along an open polyline keeps its topology", "[pattern][band_map]") {
    double W = 0;
    const auto band = band_of("lace_scallop.svg", &W);
    // an S-shaped polyline of length about W: a quarter circle bending left, then one bending right
    const double R = W / std::numbers::pi;
    std::vector<vec2> arc;
    for (int i = 0; i <= 500; ++i) {
        const double a = std::numbers::pi / 2 * i / 500.0;
        arc.push_back({R * std::sin(a), R - R * std::cos(a)});
    }
    for (int i = 1; i <= 500; ++i) {
        const double b = std::numbers::pi / 2 * i / 500.0;
        arc.push_back({2 * R - R * std::cos(b), R + R * std::sin(b)});
    }
    const planar_curve c = planar_curve::polyline(arc, false);
    std::vector<polygon_with_holes> fitted = band;
    for (auto& p : fitted) {
        for (vec2& q : p.outer) q.x *= c.length() / W;
        for (auto& h : p.holes)
            for (vec2& q : h) q.x *= c.length() / W;
    }
    const auto out = vector_pattern::map_to_curve(fitted, c, {.chord_tolerance = 0.01});
    const auto ex_t = test::raster_topology(fitted, {0, -40}, {c.length(), 40}, 0.1);
    const box2 b = bounding_box(out);
    const auto t = test::raster_topology(out, b.lo, b.hi, 0.1);
    CHECK(t.components == ex_t.components);
    CHECK(t.holes == ex_t.holes);
    CHECK(t.holes == 78);
    for (const auto& p : out) {
        CHECK(is_simple(p.outer));
        for (const auto& h : p.holes) CHECK(is_simple(h));
    }
}

TEST_CASE("band map: bad input is rejected with a message", "[pattern][band_map]") {
    const planar_curve c = planar_curve::circle(10.0);
    CHECK_THROWS_WITH(vector_pattern::map_to_curve({{rect_ring(0, -1, 100, 1), {}}}, c), Contains("outside"));
    CHECK_THROWS_WITH(vector_pattern::map_to_curve({{rect_ring(0, -10, 5, 1), {}}}, c), Contains("radius of curvature"));
    CHECK_THROWS_WITH(vector_pattern::map_to_curve({{{{0, 0}, {1, std::nan("")}, {2, 1}}, {}}}, c), Contains("non-finite"));
    CHECK_THROWS_AS(vector_pattern::map_to_curve({{rect_ring(0, -1, 5, 1), {}}}, c, {.chord_tolerance = 0}), invalid_input);
}
