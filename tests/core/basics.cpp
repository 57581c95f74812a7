#include <catch2/catch.hpp>

#include <fabsynth/core.hpp>

#include <limits>

using namespace fabsynth;

TEST_CASE("box extends, contains, intersects", "[core][box]") {
    box3 b;
    CHECK(b.empty());
    CHECK(b.volume() == 0.0);
    b.extend({1, 2, 3}).extend({-1, 0, 5});
    CHECK_FALSE(b.empty());
    CHECK(b.lo == vec3(-1, 0, 3));
    CHECK(b.hi == vec3(1, 2, 5));
    CHECK(b.volume() == 8.0);
    CHECK(b.contains({0, 1, 4}));
    CHECK_FALSE(b.contains({0, 1, 6}));
    CHECK(b.intersects(box3({1, 2, 5}, {3, 3, 7})));
    CHECK_FALSE(b.intersects(box3({1.1, 2, 5}, {3, 3, 7})));
    CHECK(b.inflated(1).volume() == 4.0 * 4 * 4);
}

TEST_CASE("errors carry the fabsynth prefix and their category", "[core][error]") {
    try {
        throw io_error("mesh.obj", 12, "face index 9 out of range");
    } catch (const error& e) {
        CHECK(std::string(e.what()) == "fabsynth: mesh.obj:12: face index 9 out of range");
    }
    CHECK(std::string(io_error::at_byte("a.stl", 84, "truncated").what()) == "fabsynth: a.stl: byte 84: truncated");
    CHECK_THROWS_AS(require_positive(-1, "radius"), invalid_input);
    CHECK_THROWS_AS(require_positive(std::numeric_limits<double>::quiet_NaN(), "radius"), invalid_input);
    CHECK_THROWS_WITH(require_finite(std::numeric_limits<double>::infinity(), "x"), Catch::Contains("x must be finite"));
    CHECK(all_finite(vec3(1, 2, 3)));
    CHECK_FALSE(all_finite(vec3(1, std::numeric_limits<double>::quiet_NaN(), 3)));
}

TEST_CASE("progress callbacks: void, bool and type-erased", "[core][progress]") {
    int calls = 0;
    auto counting = [&](double, std::string_view) { ++calls; };
    report_progress(counting, 0.5, "stage");
    CHECK(calls == 1);
    auto stopper = [](double f, std::string_view) { return f < 0.5; };
    report_progress(stopper, 0.1, "a");
    CHECK_THROWS_AS(report_progress(stopper, 0.9, "b"), cancelled);
    progress_function empty;
    report_progress(empty, 0.5, "nothing");
    no_progress none;
    report_progress(none, 1.0, "done");
    static_assert(progress_callback<no_progress>);
    static_assert(!progress_callback<int>);
}

TEST_CASE("grey_levels: grey kept, grey+alpha drops alpha, colour averaged", "[core][image]") {
    image8 g(2, 1, 1);
    g.at(0, 0) = 7, g.at(1, 0) = 250;
    CHECK(grey_levels(g) == g);
    image8 ga(1, 1, 2);
    ga.at(0, 0, 0) = 90, ga.at(0, 0, 1) = 0;  // transparent: the grey level still counts
    CHECK(grey_levels(ga).at(0, 0) == 90);
    image8 rgba(2, 1, 4, 255);
    rgba.at(0, 0, 0) = 255, rgba.at(0, 0, 1) = 0, rgba.at(0, 0, 2) = 0;  // pure red: 85
    rgba.at(1, 0, 0) = 10, rgba.at(1, 0, 1) = 20, rgba.at(1, 0, 2) = 31;  // 61 / 3 = 20
    const image8 r = grey_levels(rgba);
    CHECK(r.channels == 1);
    CHECK(r.at(0, 0) == 85);
    CHECK(r.at(1, 0) == 20);
}
