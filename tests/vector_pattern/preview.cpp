// Tests for geometry/coverage_image.hpp: coverage values against hand-computed pixels.
#include <catch2/catch.hpp>

#include <vector>

#include "fabsynth/geometry/coverage_image.hpp"

using namespace fabsynth;

namespace {
polygon_with_holes rect_polygon(double x0, double y0, double x1, double y1) {
    return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}};
}
}  // namespace

TEST_CASE("preview: grey levels are the covered fraction of each pixel", "[pattern][preview]") {
    const box2 view({0.0, 0.0}, {10.0, 10.0});
    // Columns 0-4 fully covered, column 5 half covered (x in [5, 5.5]), the rest background.
    const image8 img = preview_image({rect_polygon(0.0, 0.0, 5.5, 10.0)}, view, {.max_side = 10, .supersample = 4});
    REQUIRE(img.width == 10);
    REQUIRE(img.height == 10);
    REQUIRE(img.channels == 1);
    for (int y = 0; y < 10; ++y) {
        for (int x = 0; x < 5; ++x) CHECK(img.at(x, y) == 0);
        CHECK(img.at(5, y) == 255 - (255 * 8) / 16);  // 8 of 16 sub-pixel centres inside
        for (int x = 6; x < 10; ++x) CHECK(img.at(x, y) == 255);
    }
    // Row 0 is the smallest y; a hole is background (even-odd).
    polygon_with_holes frame = rect_polygon(0.0, 0.0, 10.0, 2.0);
    frame.holes.push_back({{4.0, 0.5}, {4.0, 1.5}, {6.0, 1.5}, {6.0, 0.5}});
    const image8 f = preview_image({frame}, view, {.max_side = 10, .supersample = 2});
    CHECK(f.at(0, 0) == 0);
    CHECK(f.at(0, 5) == 255);
    CHECK(f.at(4, 0) == 255 - 255 * 2 / 4);  // half the sub-pixels of row 0 lie in the hole (y > 0.5)
    CHECK(f.at(5, 1) == 255 - 255 * 2 / 4);
    // The longer side gets max_side pixels, the other one is rounded up.
    const image8 wide = preview_image({}, box2({0.0, 0.0}, {20.0, 7.0}), {.max_side = 10});
    CHECK(wide.width == 10);
    CHECK(wide.height == 4);
    CHECK(wide.data == std::vector<std::uint8_t>(40, 255));
    CHECK_THROWS_AS(preview_image({}, box2{}, {}), invalid_input);
    CHECK_THROWS_AS(preview_image({}, view, {.max_side = 0}), invalid_input);
    CHECK_THROWS_AS(preview_image({}, view, {.supersample = 0}), invalid_input);
}

TEST_CASE("framed_view pads the bounds by a fraction of the longer side", "[pattern][preview]") {
    const box2 v = framed_view(box2({1.0, 2.0}, {101.0, 52.0}), 0.02);
    CHECK(v.lo.x == Approx(-1.0));
    CHECK(v.lo.y == Approx(0.0));
    CHECK(v.hi.x == Approx(103.0));
    CHECK(v.hi.y == Approx(54.0));
    CHECK_THROWS_AS(framed_view(box2{}), invalid_input);
    CHECK_THROWS_AS(framed_view(box2({0, 0}, {1, 1}), -0.1), invalid_input);
}
