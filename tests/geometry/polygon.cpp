// Tests for geometry/polygon.hpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/hull_simplify.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/io/svg.hpp"

using fabsynth::ring2;
using fabsynth::vec2;

namespace {
// Brute-force oracle for is_simple: every pair of edges, no sweep.
bool simple_brute(const ring2& r) {
    const std::size_t n = r.size();
    if (n < 3) return false;
    for (std::size_t i = 0; i < n; ++i)
        if (r[i] == r[(i + 1) % n]) return false;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            const vec2 a = r[i], b = r[(i + 1) % n], c = r[j], d = r[(j + 1) % n];
            const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if (adjacent) {
                // share exactly one vertex: the other endpoint of either edge must not lie on the other edge
                const vec2 shared = j == i + 1 ? b : a;
                const vec2 p = shared == a ? b : a, q = shared == c ? d : c;
                if (fabsynth::on_segment(c, d, p) || fabsynth::on_segment(a, b, q)) return false;
            } else if (fabsynth::detail::segments_intersect(a, b, c, d)) {
                return false;
            }
        }
    return true;
}
}  // namespace

TEST_CASE("polygon: signed area, orientation and perimeter on hand cases", "[geometry][polygon]") {
    const ring2 sq{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
    CHECK(fabsynth::signed_area(sq) == 4);
    CHECK(fabsynth::is_ccw(sq));
    CHECK(fabsynth::perimeter(sq) == 8);
    ring2 cw(sq.rbegin(), sq.rend());
    CHECK(fabsynth::signed_area(cw) == -4);
    fabsynth::orient(cw, true);
    CHECK(fabsynth::signed_area(cw) == 4);
    CHECK(cw.front() == vec2(0, 2));  // first point kept
    const ring2 tri{{0, 0}, {4, 0}, {0, 3}};
    CHECK(fabsynth::signed_area(tri) == 6);
    CHECK(fabsynth::perimeter(tri) == 12);
    CHECK(fabsynth::signed_area(ring2{{0, 0}, {1, 1}}) == 0);
    // L-shape (concave): 3x3 minus 2x2.
    const ring2 ell{{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}};
    CHECK(fabsynth::signed_area(ell) == 5);
    // Shoelace is translation invariant even far from the origin.
    ring2 far = ell;
    for (vec2& p : far) p += vec2(1e8, -1e8);
    CHECK(fabsynth::signed_area(far) == 5);
    fabsynth::polygon_with_holes p{sq, {{{0.5, 0.5}, {1, 0.5}, {1, 1}}}};
    fabsynth::orient(p);
    CHECK(fabsynth::signed_area(p.outer) > 0);
    CHECK(fabsynth::signed_area(p.holes[0]) < 0);
    CHECK(fabsynth::area(p) == 4 - 0.125);
    CHECK(fabsynth::bounding_box(ell) == fabsynth::box2({0, 0}, {3, 3}));
}

TEST_CASE("polygon: point in ring and winding numbers", "[geometry][polygon]") {
    const ring2 ell{{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}};
    CHECK(fabsynth::point_in_ring(ell, {0.5, 0.5}));
    CHECK(fabsynth::point_in_ring(ell, {2.5, 0.5}));
    CHECK(fabsynth::point_in_ring(ell, {0.5, 2.5}));
    CHECK(!fabsynth::point_in_ring(ell, {2, 2}));  // in the notch
    CHECK(!fabsynth::point_in_ring(ell, {-1, 0.5}));
    CHECK(!fabsynth::point_in_ring(ell, {4, 0}));  // on the line of an edge, outside it
    CHECK(fabsynth::point_in_ring(ell, {3, 0.5}));  // on an edge
    CHECK(fabsynth::point_in_ring(ell, {1, 1}));    // reflex vertex
    CHECK(fabsynth::point_in_ring(ell, {0, 3}));    // convex vertex
    CHECK(fabsynth::point_in_ring(ell, {2, 1}));    // on the notch edge
    // Ray through a vertex (y = 1 passes the vertices (3,1) and (1,1)).
    CHECK(fabsynth::point_in_ring(ell, {0.5, 1}));
    CHECK(!fabsynth::point_in_ring(ell, {-0.5, 1}));
    CHECK(!fabsynth::point_in_ring(ell, {3.5, 1}));
    CHECK(fabsynth::winding_number(ell, {0.5, 0.5}) == 1);
    ring2 cw(ell.rbegin(), ell.rend());
    CHECK(fabsynth::winding_number(cw, {0.5, 0.5}) == -1);
    // A square traversed twice winds twice: nonzero fills it, even-odd does not.
    const ring2 twice{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}, {1, 0}, {1, 1}, {0, 1}};
    CHECK(fabsynth::winding_number(twice, {0.5, 0.5}) == 2);
    // Nested rings: same orientation vs opposite orientation.
    const ring2 big{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, small{{1, 1}, {2, 1}, {2, 2}, {1, 2}};
    const ring2 small_cw(small.rbegin(), small.rend());
    using fabsynth::fill_rule;
    CHECK(fabsynth::point_in_rings({big, small}, {1.5, 1.5}, fill_rule::nonzero));
    CHECK(!fabsynth::point_in_rings({big, small}, {1.5, 1.5}, fill_rule::evenodd));
    CHECK(!fabsynth::point_in_rings({big, small_cw}, {1.5, 1.5}, fill_rule::nonzero));
    CHECK(fabsynth::point_in_rings({big, small_cw}, {3, 3}, fill_rule::evenodd));
    const fabsynth::polygon_with_holes poly{big, {small_cw}};
    CHECK(!fabsynth::point_in_polygon(poly, {1.5, 1.5}));
    CHECK(fabsynth::point_in_polygon(poly, {2, 1.5}));  // on the hole boundary: inside the material
    CHECK(fabsynth::point_in_polygon(poly, {3, 3}));
    CHECK(!fabsynth::point_in_polygon(poly, {5, 3}));
}

TEST_CASE("polygon: point in ring agrees with the analytic disk", "[geometry][polygon]") {
    // Regular 64-gon inscribed in the unit circle: points inside r*cos(pi/64) are inside, points
    // beyond r = 1 are outside (independent oracle: distance to the center).
    ring2 g;
    for (int k = 0; k < 64; ++k) g.push_back({std::cos(2 * std::numbers::pi * k / 64), std::sin(2 * std::numbers::pi * k / 64)});
    const double inner = std::cos(std::numbers::pi / 64);
    fabsynth::counter_rng rng(7);
    int tested = 0;
    for (int i = 0; i < 20000; ++i) {
        const vec2 p{rng.uniform(-1.2, 1.2), rng.uniform(-1.2, 1.2)};
        const double r = glm::length(p);
        if (r < inner - 1e-12) {
            CHECK(fabsynth::point_in_ring(g, p));
            ++tested;
        } else if (r > 1 + 1e-12) {
            CHECK(!fabsynth::point_in_ring(g, p));
            ++tested;
        }
    }
    CHECK(tested > 19000);
}

TEST_CASE("polygon: is_simple on hand cases", "[geometry][polygon]") {
    CHECK(fabsynth::is_simple(ring2{{0, 0}, {1, 0}, {1, 1}, {0, 1}}));
    CHECK(fabsynth::is_simple(ring2{{0, 0}, {1, 0}, {0, 1}}));
    CHECK(!fabsynth::is_simple(ring2{{0, 0}, {1, 1}, {1, 0}, {0, 1}}));            // bow-tie
    CHECK(!fabsynth::is_simple(ring2{{0, 0}, {1, 0}, {1, 0}, {1, 1}}));            // repeated point
    CHECK(!fabsynth::is_simple(ring2{{0, 0}, {2, 0}, {1, 0}, {1, 1}}));            // fold-back spike
    CHECK(!fabsynth::is_simple(ring2{{0, 0}, {1, 0}, {2, 0}}));                    // degenerate
    CHECK(!fabsynth::is_simple(ring2{{0, 0}, {1, 0}}));
    CHECK(!fabsynth::is_simple(ring2{{0, 0}, {2, 0}, {2, 2}, {1, 0}, {0, 2}}));    // vertex touches an edge
    CHECK(!fabsynth::is_simple(ring2{{0, 0}, {1, 1}, {2, 0}, {2, 2}, {1, 1}, {0, 2}}));  // figure eight at a vertex
    CHECK(fabsynth::is_simple(ring2{{0, 0}, {1, 0}, {2, 0}, {2, 1}, {0, 1}}));     // collinear, same direction
    CHECK(!fabsynth::is_simple(ring2{{0, 0}, {3, 0}, {3, 1}, {2, 1}, {2, 0}, {1, 0}, {1, 1}, {0, 1}}));  // overlapping edges
}

TEST_CASE("polygon: is_simple agrees with a brute-force check on random rings", "[geometry][polygon]") {
    int simple = 0, not_simple = 0;
    for (std::uint64_t trial = 0; trial < 400; ++trial) {
        fabsynth::counter_rng rng(11, trial);
        const std::size_t n = 3 + rng.uniform_int(12);
        ring2 r;
        if (trial % 2 == 0) {
            // star-shaped: angles sorted around the origin (simple unless radii make edges touch)
            std::vector<double> ang;
            for (std::size_t i = 0; i < n; ++i) ang.push_back(rng.uniform(0, 2 * std::numbers::pi));
            std::sort(ang.begin(), ang.end());
            for (double a : ang) {
                const double rad = 0.2 + rng.uniform();
                r.push_back({rad * std::cos(a), rad * std::sin(a)});
            }
        } else {
            // small integer grid: many collinear and touching cases
            for (std::size_t i = 0; i < n; ++i) r.push_back({double(rng.uniform_int(4)), double(rng.uniform_int(4))});
        }
        const bool expect = simple_brute(r);
        CHECK(fabsynth::is_simple(r) == expect);
        (expect ? simple : not_simple)++;
    }
    CHECK(simple > 100);
    CHECK(not_simple > 100);
}

TEST_CASE("polygon: bundled exemplar rings are simple and group into the documented polygons", "[geometry][polygon]") {
    struct row {
        const char* file;
        std::size_t components, holes;
    };
    // data/README.md, vector/ table.
    const row rows[] = {{"lace_scallop.svg", 1, 78}, {"greek_key.svg", 1, 6}, {"pearls.svg", 44, 11}, {"vine.svg", 1, 20},
                        {"quatrefoil.svg", 7, 35},   {"hearts.svg", 1, 12},   {"zigzag.svg", 1, 0}};
    for (const row& r : rows) {
        INFO(r.file);
        const auto doc = fabsynth::io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/" + r.file);
        std::vector<ring2> all;
        double area_paths = 0;
        for (const auto& s : doc.shapes)
            for (const auto& sp : s.subpaths) {
                CHECK(fabsynth::is_simple(sp));
                all.push_back(sp);
                area_paths += fabsynth::signed_area(sp);  // outer positive, holes negative
            }
        // Grouping by geometric nesting recovers the per-path structure of the file.
        const auto polys = fabsynth::group_rings(all);
        std::size_t holes = 0;
        double area_polys = 0;
        for (const auto& p : polys) holes += p.holes.size(), area_polys += fabsynth::area(p);
        CHECK(polys.size() == r.components);
        CHECK(holes == r.holes);
        CHECK(area_polys == Approx(area_paths).epsilon(1e-12));
    }
    // A bow-tie is not simple.
    CHECK(!fabsynth::is_simple(ring2{{0, 0}, {10, 10}, {10, 0}, {0, 10}}));
}

TEST_CASE("polygon: group_rings nests islands inside holes", "[geometry][polygon]") {
    auto square = [](double lo, double hi) { return ring2{{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}}; };
    // 0..10 outer, 1..9 hole, 2..8 island, 3..7 hole of the island; plus a separate square.
    const auto polys = fabsynth::group_rings({square(3, 7), square(0, 10), square(20, 21), square(2, 8), square(1, 9)});
    REQUIRE(polys.size() == 3);
    CHECK(polys[0].outer == square(0, 10));
    REQUIRE(polys[0].holes.size() == 1);
    CHECK(fabsynth::signed_area(polys[0].holes[0]) == -64);
    CHECK(polys[1].outer == square(20, 21));
    CHECK(fabsynth::signed_area(polys[2].outer) == 36);
    REQUIRE(polys[2].holes.size() == 1);
    CHECK(fabsynth::signed_area(polys[2].holes[0]) == -16);
    CHECK_THROWS_AS(fabsynth::group_rings({ring2{{0, 0}, {std::nan(""), 0}, {1, 1}}}), fabsynth::invalid_input);
}

// convex_intersection_area: closed forms for squares and a triangle, and Clipper's boolean (a
// second library, integer arithmetic) on random convex polygons.
TEST_CASE("convex_intersection_area: closed forms and Clipper's boolean", "[geometry][polygon]") {
    const ring2 sq{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
    auto moved = [](const ring2& r, vec2 d) {
        ring2 o = r;
        for (vec2& p : o) p += d;
        return o;
    };
    CHECK(fabsynth::convex_intersection_area(sq, sq) == Approx(4.0));
    CHECK(fabsynth::convex_intersection_area(sq, moved(sq, {0.5, 1.5})) == Approx(1.5 * 0.5));
    CHECK(fabsynth::convex_intersection_area(sq, moved(sq, {3, 0})) == 0.0);
    CHECK(fabsynth::convex_intersection_area(sq, moved(sq, {2, 0})) == Approx(0.0).margin(1e-12));  // edge contact
    const ring2 tri{{0, 0}, {2, 0}, {0, 2}};  // the square's lower-left half
    CHECK(fabsynth::convex_intersection_area(sq, tri) == Approx(2.0));
    CHECK(fabsynth::convex_intersection_area(tri, sq) == Approx(2.0));
    CHECK(fabsynth::convex_intersection_area(sq, ring2{{0, 0}, {1, 1}}) == 0.0);  // degenerate ring

    fabsynth::counter_rng rng(11);
    auto random_convex = [&](vec2 c, double r) {
        std::vector<vec2> pts;
        for (int k = 0; k < 12; ++k) pts.push_back(c + vec2(rng.uniform(-r, r), rng.uniform(-r, r)));
        return fabsynth::convex_hull(pts);
    };
    for (int t = 0; t < 200; ++t) {
        const ring2 a = random_convex({0, 0}, 5), b = random_convex({rng.uniform(-6.0, 6.0), rng.uniform(-6.0, 6.0)}, 5);
        const double oracle =
            fabsynth::area(fabsynth::polygon_intersection({fabsynth::polygon_with_holes{a, {}}}, {fabsynth::polygon_with_holes{b, {}}}));
        INFO("trial " << t);
        CHECK(fabsynth::convex_intersection_area(a, b) == Approx(oracle).margin(1e-4));
        CHECK(fabsynth::convex_intersection_area(b, a) == Approx(oracle).margin(1e-4));
    }
}
