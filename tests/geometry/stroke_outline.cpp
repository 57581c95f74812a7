// geometry/clip.hpp stroke_outline against analytic areas (a stadium, a closed ring of strokes).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "fabsynth/geometry/clip.hpp"

using namespace fabsynth;

TEST_CASE("stroke_outline: one segment is a stadium of area 2hL + pi h^2", "[clip][stroke]") {
    const double h = 0.75, L = 10;
    const auto out = stroke_outline({{{0, 0}, {L, 0}}}, h, 0.001);
    REQUIRE(out.size() == 1);
    CHECK(out[0].holes.empty());
    CHECK(area(out) == Approx(2 * h * L + std::numbers::pi * h * h).epsilon(1e-3));
    for (const vec2& p : out[0].outer) CHECK(p.y <= h + 1e-9);
}

TEST_CASE("stroke_outline: a square path of strokes encloses one hole", "[clip][stroke]") {
    const double h = 0.5, s = 8;
    const auto out = stroke_outline({{{0, 0}, {s, 0}, {s, s}, {0, s}, {0, 0}}}, h, 0.001);
    REQUIRE(out.size() == 1);
    REQUIRE(out[0].holes.size() == 1);
    // outer: (s + 2h)^2 minus the four rounded corners' missing (4 - pi) h^2; hole: (s - 2h)^2
    const double expect = (s + 2 * h) * (s + 2 * h) - (4 - std::numbers::pi) * h * h - (s - 2 * h) * (s - 2 * h);
    CHECK(area(out) == Approx(expect).epsilon(1e-3));
}

TEST_CASE("stroke_outline: bad input", "[clip][stroke]") {
    CHECK_THROWS_AS(stroke_outline({{{0, 0}, {1, 0}}}, 0.0), invalid_input);
    CHECK_THROWS_AS(stroke_outline({{{0, 0}, {1, 0}}}, std::nan("")), invalid_input);
    CHECK_THROWS_AS(stroke_outline({{{0, 0}, {std::nan(""), 0}}}, 1.0), invalid_input);
    CHECK(stroke_outline({}, 1.0).empty());
}
