// geometry/raster.hpp and geometry/segment.hpp against independent per-pixel oracles.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/raster.hpp"
#include "fabsynth/geometry/segment.hpp"

using namespace fabsynth;

namespace {
// Oracle: winding number of ring r around p by summing signed angles (no scanline code).
double winding(const ring2& r, vec2 p) {
    double a = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
        const vec2 u = r[i] - p, v = r[(i + 1) % r.size()] - p;
        a += std::atan2(u.x * v.y - u.y * v.x, u.x * v.x + u.y * v.y);
    }
    return a / (2 * M_PI);
}
std::vector<int> mask_from(const polygon_rasterizer& r, const raster_grid& g) {
    std::vector<int> m(static_cast<std::size_t>(g.width) * g.height, 0);
    r.for_each_run(g, [&](int j, int i0, int i1) {
        REQUIRE(0 <= i0);
        REQUIRE(i0 < i1);
        REQUIRE(i1 <= g.width);
        for (int i = i0; i < i1; ++i) ++m[static_cast<std::size_t>(j) * g.width + i];
    });
    return m;
}
ring2 random_ring(std::uint64_t seed, int n) {
    ring2 r;
    counter_rng rng(seed);
    for (int i = 0; i < n; ++i) r.push_back({rng.uniform() * 10, rng.uniform() * 10});  // self-intersecting star soup
    return r;
}
}  // namespace

TEST_CASE("raster: even-odd and nonzero agree with the winding-number oracle on random self-intersecting rings", "[raster]") {
    const raster_grid g{{-0.013, -0.007}, 0.1, 103, 101};  // offsets keep pixel centres off the vertices
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        const ring2 a = random_ring(seed, 7), b = random_ring(seed + 100, 5);
        for (fill_rule rule : {fill_rule::evenodd, fill_rule::nonzero}) {
            polygon_rasterizer r({.rule = rule});
            r.add_ring(a);
            r.add_ring(b);
            const auto m = mask_from(r, g);
            int wrong = 0;
            for (int j = 0; j < g.height; ++j)
                for (int i = 0; i < g.width; ++i) {
                    const vec2 c = g.origin + vec2((i + 0.5) * g.pixel, (j + 0.5) * g.pixel);
                    const long w = std::lround(winding(a, c) + winding(b, c));
                    const int expect = rule == fill_rule::evenodd ? static_cast<int>(std::labs(w) % 2) : (w != 0);
                    wrong += m[static_cast<std::size_t>(j) * g.width + i] != expect;
                }
            CHECK(wrong == 0);
        }
    }
}

TEST_CASE("raster: a rectangle with a hole covers exactly the pixel centres inside", "[raster]") {
    polygon_rasterizer r;
    r.add_polygon({{{1, 1}, {9, 1}, {9, 5}, {1, 5}}, {{{3, 2}, {3, 4}, {5, 4}, {5, 2}}}});
    const auto m = mask_from(r, {{0, 0}, 0.5, 24, 12});
    long n = 0;
    for (int v : m) n += v;
    CHECK(n == 16 * 8 - 4 * 4);  // centres x in [1, 9), y in [1, 5), minus [3, 5) x [2, 4)
}

TEST_CASE("raster: wrapped columns fold a band's overhang back to its start", "[raster]") {
    polygon_rasterizer r({.wrap_x = true});
    r.add_ring({{8, 0}, {12, 0}, {12, 1}, {8, 1}});  // x in [8, 12) on a 10-pixel periodic row
    std::vector<std::pair<int, int>> runs;
    r.for_each_run({{0, 0}, 1.0, 10, 1}, [&](int, int i0, int i1) { runs.emplace_back(i0, i1); });
    REQUIRE(runs.size() == 2);
    CHECK(runs[0] == std::pair{8, 10});
    CHECK(runs[1] == std::pair{0, 2});
    polygon_rasterizer wide({.wrap_x = true});
    wide.add_ring({{-3, 0}, {20, 0}, {20, 1}, {-3, 1}});
    runs.clear();
    wide.for_each_run({{0, 0}, 1.0, 10, 1}, [&](int, int i0, int i1) { runs.emplace_back(i0, i1); });
    CHECK(runs == std::vector<std::pair<int, int>>{{0, 10}});
}

TEST_CASE("segment distance: 2D and 3D against the minimum over a fine sampling of the segment", "[segment]") {
    counter_rng rng(7);
    for (int t = 0; t < 200; ++t) {
        const vec3 a(rng.uniform(), rng.uniform(), rng.uniform()), b(rng.uniform(), rng.uniform(), rng.uniform());
        const vec3 p(2 * rng.uniform() - 0.5, 2 * rng.uniform() - 0.5, 2 * rng.uniform() - 0.5);
        double best = 1e300;
        for (int k = 0; k <= 20000; ++k) best = std::min(best, glm::distance(p, a + (k / 20000.0) * (b - a)));
        CHECK(segment_distance(p, a, b) <= best + 1e-12);
        CHECK(segment_distance(p, a, b) >= best - 1e-4);
        const vec2 p2(p), a2(a), b2(b);
        CHECK(segment_distance2(p2, a2, a2) == Approx(glm::dot(p2 - a2, p2 - a2)));
    }
}
