// geometry/cdt.hpp: the constrained Delaunay triangulation from an ear clipping, against a brute-
// force Delaunay oracle on a convex polygon (the CDT is then the unique Delaunay triangulation),
// the empty-circle property of every interior edge and the kept outline on a polygon with a hole,
// rings touching at a point merged, bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/cdt.hpp"
#include "fabsynth/geometry/triangulate.hpp"

namespace cdt_test {

using fabsynth::planar_triangulation;
using fabsynth::polygon_with_holes;
using fabsynth::ring2;
using fabsynth::vec2;

// In-circle determinant of (a, b, c) counter-clockwise and d: > 0 inside (written out here).
inline double incircle(vec2 a, vec2 b, vec2 c, vec2 d) {
    const double adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y, cdx = c.x - d.x, cdy = c.y - d.y;
    return (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) - (bdx * bdx + bdy * bdy) * (adx * cdy - cdx * ady) +
           (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
}

inline double twice_area(vec2 a, vec2 b, vec2 c) { return (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y); }

inline std::array<std::uint32_t, 3> sorted(std::array<std::uint32_t, 3> t) {
    std::sort(t.begin(), t.end());
    return t;
}

TEST_CASE("constrained_delaunay: a convex polygon gets the brute-force Delaunay triangulation", "[geometry][cdt]") {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        INFO("seed " << seed);
        fabsynth::counter_rng rng(seed);
        ring2 ring;  // 14 points on an ellipse at jittered angles: convex, in general position
        for (int k = 0; k < 14; ++k) {
            const double a = 2 * 3.141592653589793 * (k + rng.uniform(-0.3, 0.3)) / 14;
            ring.push_back({7.0 * std::cos(a), 3.0 * std::sin(a)});
        }
        const planar_triangulation ears = fabsynth::triangulate({polygon_with_holes{ring, {}}});
        const planar_triangulation d = fabsynth::constrained_delaunay(ears);
        REQUIRE(d.vertices.size() == ring.size());
        std::set<std::array<std::uint32_t, 3>> oracle, got;
        const auto n = static_cast<std::uint32_t>(ring.size());
        for (std::uint32_t i = 0; i < n; ++i)
            for (std::uint32_t j = i + 1; j < n; ++j)
                for (std::uint32_t k = j + 1; k < n; ++k) {
                    vec2 a = ring[i], b = ring[j], c = ring[k];
                    if (twice_area(a, b, c) < 0) std::swap(b, c);
                    bool empty = true;
                    for (std::uint32_t m = 0; m < n && empty; ++m)
                        if (m != i && m != j && m != k && incircle(a, b, c, ring[m]) > 0) empty = false;
                    if (empty) oracle.insert({i, j, k});
                }
        for (const auto& t : d.triangles) {
            CHECK(twice_area(d.vertices[t[0]], d.vertices[t[1]], d.vertices[t[2]]) > 0);
            got.insert(sorted(t));
        }
        CHECK(got == oracle);
        CHECK(got.size() == ring.size() - 2);
    }
}

TEST_CASE("constrained_delaunay: a polygon with a hole keeps its outline and every interior edge is locally Delaunay", "[geometry][cdt]") {
    // a comb (long thin teeth make the ear clipping's fans far from Delaunay) around a square hole
    ring2 outer{{0, 0}, {20, 0}, {20, 10}};
    for (int k = 9; k >= 0; --k) outer.push_back({2.0 * k + 1.5, 10}), outer.push_back({2.0 * k + 1.0, 4}), outer.push_back({2.0 * k + 0.5, 10});
    outer.push_back({0, 10});
    const ring2 hole{{8, 1}, {8, 3}, {12, 3}, {12, 1}};
    const polygon_with_holes poly{outer, {hole}};
    const planar_triangulation ears = fabsynth::triangulate({poly});
    const planar_triangulation d = fabsynth::constrained_delaunay(ears);
    double area = 0;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::pair<std::size_t, std::uint32_t>>> edge_use;  // -> (triangle, apex)
    for (std::size_t f = 0; f < d.triangles.size(); ++f) {
        const auto& t = d.triangles[f];
        const double a2 = twice_area(d.vertices[t[0]], d.vertices[t[1]], d.vertices[t[2]]);
        CHECK(a2 > 0);
        area += 0.5 * a2;
        for (int k = 0; k < 3; ++k) edge_use[std::minmax(t[k], t[(k + 1) % 3])].push_back({f, t[(k + 2) % 3]});
    }
    CHECK(area == Approx(std::abs(fabsynth::signed_area(outer)) - 8.0).epsilon(1e-12));
    std::set<std::pair<vec2, vec2>, bool (*)(const std::pair<vec2, vec2>&, const std::pair<vec2, vec2>&)> outline(
        [](const std::pair<vec2, vec2>& l, const std::pair<vec2, vec2>& r) {
            return std::tie(l.first.x, l.first.y, l.second.x, l.second.y) < std::tie(r.first.x, r.first.y, r.second.x, r.second.y);
        });
    auto key = [](vec2 a, vec2 b) { return (a.x < b.x || (a.x == b.x && a.y < b.y)) ? std::pair{a, b} : std::pair{b, a}; };
    for (const ring2* r : std::array<const ring2*, 2>{&outer, &hole})
        for (std::size_t k = 0; k < r->size(); ++k) outline.insert(key((*r)[k], (*r)[(k + 1) % r->size()]));
    std::size_t boundary = 0, flipped_check = 0;
    for (const auto& [e, uses] : edge_use) {
        REQUIRE(uses.size() <= 2);
        if (uses.size() == 1) {  // a boundary edge is an outline edge
            ++boundary;
            CHECK(outline.count(key(d.vertices[e.first], d.vertices[e.second])) == 1);
            continue;
        }
        if (outline.count(key(d.vertices[e.first], d.vertices[e.second]))) continue;  // a constraint may stay
        const auto& t = d.triangles[uses[0].first];
        CHECK(incircle(d.vertices[t[0]], d.vertices[t[1]], d.vertices[t[2]], d.vertices[uses[1].second]) <= 1e-9);
        ++flipped_check;
    }
    CHECK(boundary == outline.size());
    CHECK(flipped_check > 20);
    // the ear clipping was not Delaunay already (the test would not test the flips otherwise)
    std::size_t violations = 0;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::pair<std::size_t, std::uint32_t>>> ear_use;
    for (std::size_t f = 0; f < ears.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) ear_use[std::minmax(ears.triangles[f][k], ears.triangles[f][(k + 1) % 3])].push_back({f, ears.triangles[f][(k + 2) % 3]});
    for (const auto& [e, uses] : ear_use)
        if (uses.size() == 2) {
            const auto& t = ears.triangles[uses[0].first];
            violations += incircle(ears.vertices[t[0]], ears.vertices[t[1]], ears.vertices[t[2]], ears.vertices[uses[1].second]) > 1e-9;
        }
    CHECK(violations > 0);
}

TEST_CASE("constrained_delaunay: rings touching at a point share it; bad input", "[geometry][cdt]") {
    const ring2 a{{0, 0}, {2, 0}, {2, 2}, {0, 2}}, b{{2, 2}, {4, 2}, {4, 4}, {2, 4}};
    const planar_triangulation ears = fabsynth::triangulate({polygon_with_holes{a, {}}, polygon_with_holes{b, {}}});
    std::vector<std::uint32_t> vertex_of;
    const planar_triangulation d = fabsynth::constrained_delaunay(ears, &vertex_of);
    REQUIRE(vertex_of.size() == ears.vertices.size());
    CHECK(d.vertices.size() == 7);  // (2, 2) once
    for (std::size_t v = 0; v < ears.vertices.size(); ++v) CHECK(d.vertices[vertex_of[v]] == ears.vertices[v]);
    CHECK(d.triangles.size() == 4);
    planar_triangulation flat{{{0, 0}, {1, 0}, {2, 0}}, {{0, 1, 2}}};
    CHECK_THROWS_AS(fabsynth::constrained_delaunay(flat), fabsynth::solver_error);
}

}  // namespace cdt_test
