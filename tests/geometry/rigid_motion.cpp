// geometry/rigid_motion.hpp: the least-squares rigid motion recovers a known rotation and
// translation exactly, its inverse undoes it, a noisy fit is the closed-form optimum of two
// points, bad input is named.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/geometry/rigid_motion.hpp"

namespace rigid_motion_test {

using fabsynth::vec2;

TEST_CASE("fit_rigid_motion: a rotated, moved point set gives its motion back; inverse undoes it", "[geometry][rigid_motion]") {
    const std::vector<vec2> from{{0, 0}, {3, 1}, {-2, 4}, {5, -3}, {1.5, 2.5}};
    for (const double angle : {0.0, 0.7, -2.9, 3.14159}) {
        INFO("angle " << angle);
        const double c = std::cos(angle), s = std::sin(angle);
        const vec2 t(12.5, -7.25);
        std::vector<vec2> to;
        for (const vec2& p : from) to.push_back(vec2(c * p.x - s * p.y, s * p.x + c * p.y) + t);  // by hand
        const fabsynth::rigid_motion2 m = fabsynth::fit_rigid_motion(from, to);
        CHECK(m.c == Approx(c).margin(1e-12));
        CHECK(m.s == Approx(s).margin(1e-12));
        CHECK(m.t.x == Approx(t.x).margin(1e-12));
        CHECK(m.t.y == Approx(t.y).margin(1e-12));
        for (std::size_t k = 0; k < from.size(); ++k) {
            CHECK(glm::distance(m(from[k]), to[k]) < 1e-12);
            CHECK(glm::distance(m.inverse()(to[k]), from[k]) < 1e-12);
        }
    }
}

TEST_CASE("fit_rigid_motion: two points at a different distance are matched at their midpoints and direction", "[geometry][rigid_motion]") {
    // from (-1, 0), (1, 0) to (0, 0), (0, 4): the best motion turns by 90 degrees and puts the
    // centroid (0, 0) on (0, 2); no rotation can stretch, so each point is off by 1.
    const std::vector<vec2> from{{-1, 0}, {1, 0}}, to{{0, 0}, {0, 4}};
    const auto m = fabsynth::fit_rigid_motion(from, to);
    CHECK(m.c == Approx(0.0).margin(1e-12));
    CHECK(m.s == Approx(1.0).margin(1e-12));
    CHECK(glm::distance(m(vec2(0, 0)), vec2(0, 2)) < 1e-12);
    CHECK(glm::distance(m(from[0]), to[0]) == Approx(1.0).margin(1e-12));
}

TEST_CASE("fit_rigid_motion: bad input named", "[geometry][rigid_motion]") {
    const std::vector<vec2> two{{0, 0}, {1, 0}}, one{{0, 0}}, none;
    CHECK_THROWS_AS(fabsynth::fit_rigid_motion(two, one), fabsynth::invalid_input);
    CHECK_THROWS_AS(fabsynth::fit_rigid_motion(none, none), fabsynth::invalid_input);
    const std::vector<vec2> bad{{0, 0}, {NAN, 0}};
    CHECK_THROWS_AS(fabsynth::fit_rigid_motion(two, bad), fabsynth::invalid_input);
}

}  // namespace rigid_motion_test
