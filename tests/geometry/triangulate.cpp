// Tests for geometry/triangulate.hpp.
//
// Oracle: a triangulation of a polygon with holes is correct iff (1) every triangle has positive
// area, (2) every directed ring edge (outer ccw, holes cw) is used by exactly one triangle and its
// reverse by none, (3) every other directed edge is matched by exactly one reverse edge, and (4)
// the areas sum to the polygon's area. (1)-(3) make the triangles a closed oriented covering of
// the polygon whose degree is constant; (4) forces the degree to be 1, i.e. no overlaps.
// Centroids inside the polygon are checked too (a cheap independent point-location test).
#include <catch2/catch.hpp>

#include "support/test_util.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/triangulate.hpp"
#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"

using namespace fabsynth;

namespace {

void check_triangulation(const polygon_with_holes& input, const planar_triangulation& t) {
    polygon_with_holes poly = input;
    orient(poly);
    // vertex ids: outer ring then holes, in input order
    std::size_t nv = input.outer.size();
    for (const ring2& h : input.holes) nv += h.size();
    REQUIRE(t.vertices.size() == nv);
    // Euler: n + 2h - 2 triangles (one fewer pair per hole joined at a shared vertex)
    CHECK(t.triangles.size() <= nv - 2 + 2 * input.holes.size());

    // vertices at the same position (a hole touching another ring) are one vertex for the edge checks
    std::map<std::pair<double, double>, std::uint32_t> first_at;
    std::vector<std::uint32_t> canon(t.vertices.size());
    for (std::uint32_t i = 0; i < t.vertices.size(); ++i) canon[i] = first_at.emplace(std::pair{t.vertices[i].x, t.vertices[i].y}, i).first->second;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    double sum = 0.0;
    for (const auto& tri : t.triangles) {
        const vec2 a = t.vertices[tri[0]], b = t.vertices[tri[1]], c = t.vertices[tri[2]];
        const double ar = 0.5 * orient2d(a, b, c);
        REQUIRE(ar > 0.0);
        sum += ar;
        REQUIRE(point_in_polygon(poly, (a + b + c) / 3.0));
        for (int k = 0; k < 3; ++k) ++directed[{canon[tri[k]], canon[tri[(k + 1) % 3]]}];
    }
    // ring edges with the orientation of the oriented polygon, as vertex ids
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> boundary;
    auto add_ring = [&](const ring2& r, std::uint32_t base, bool want_ccw) {
        const bool flip = (signed_area(r) > 0.0) != want_ccw;
        const std::uint32_t m = static_cast<std::uint32_t>(r.size());
        for (std::uint32_t i = 0; i < m; ++i) {
            std::uint32_t a = base + i, b = base + (i + 1) % m;
            if (flip) std::swap(a, b);
            boundary[{canon[a], canon[b]}] = 1;
        }
    };
    std::uint32_t base = 0;
    add_ring(input.outer, base, true);
    base += static_cast<std::uint32_t>(input.outer.size());
    for (const ring2& h : input.holes) add_ring(h, base, false), base += static_cast<std::uint32_t>(h.size());
    for (const auto& [e, k] : boundary) {
        INFO("boundary edge " << e.first << "-" << e.second);
        REQUIRE(directed.count(e) == 1);
        REQUIRE(directed[e] == 1);
        REQUIRE(directed.count({e.second, e.first}) == 0);
    }
    for (const auto& [e, k] : directed) {
        REQUIRE(k == 1);
        if (boundary.count(e)) continue;
        INFO("interior edge " << e.first << "-" << e.second);
        REQUIRE(directed.count({e.second, e.first}) == 1);
    }
    CHECK(std::abs(sum - area(poly)) <= 1e-9 * area(poly));
}

using fabsynth::test::rect_ring;

}  // namespace

TEST_CASE("triangulate: convex, concave and collinear rings", "[geometry][triangulate]") {
    SECTION("square") {
        polygon_with_holes p{rect_ring(0, 0, 1, 1), {}};
        check_triangulation(p, triangulate(p));
    }
    SECTION("clockwise input gives counter-clockwise triangles") {
        ring2 r = rect_ring(0, 0, 2, 1);
        orient(r, false);
        polygon_with_holes p{r, {}};
        check_triangulation(p, triangulate(p));
    }
    SECTION("collinear vertices on every side stay and are used") {
        polygon_with_holes p{{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 1}, {3, 2}, {1.5, 2}, {0, 2}, {0, 1}}, {}};
        check_triangulation(p, triangulate(p));
    }
    SECTION("comb with deep reflex teeth") {
        ring2 r{{0, 0}};
        for (int i = 0; i < 40; ++i) {
            r.push_back({i + 0.0, 10});
            r.push_back({i + 0.5, 10});
            r.push_back({i + 0.5, 1});
            r.push_back({i + 1.0, 1});
        }
        r.push_back({40, 0});
        polygon_with_holes p{r, {}};
        REQUIRE(is_simple(p.outer));
        check_triangulation(p, triangulate(p));
    }
    SECTION("random star-shaped polygons") {
        for (std::uint64_t s = 0; s < 50; ++s) {
            counter_rng rng(42, s);
            const int n = 3 + static_cast<int>(rng.uniform_int(200));
            ring2 r;
            for (int i = 0; i < n; ++i) {
                const double a = 2.0 * std::numbers::pi * i / n, rad = rng.uniform(0.2, 1.0);
                r.push_back({rad * std::cos(a), rad * std::sin(a)});
            }
            polygon_with_holes p{r, {}};
            INFO("seed " << s << " n " << n);
            check_triangulation(p, triangulate(p));
        }
    }
}

TEST_CASE("triangulate: holes, including holes in line with each other and with outer vertices", "[geometry][triangulate]") {
    SECTION("one hole") {
        polygon_with_holes p{rect_ring(0, 0, 4, 4), {rect_ring(1, 1, 3, 3)}};
        check_triangulation(p, triangulate(p));
    }
    SECTION("grid of holes sharing x and y extents") {
        polygon_with_holes p{rect_ring(0, 0, 11, 11), {}};
        for (int i = 0; i < 5; ++i)
            for (int j = 0; j < 5; ++j) p.holes.push_back(rect_ring(1 + 2 * i, 1 + 2 * j, 2 + 2 * i, 2 + 2 * j));
        check_triangulation(p, triangulate(p));
    }
    SECTION("holes whose rightmost vertex faces a reflex outer vertex") {
        polygon_with_holes p{{{0, 0}, {10, 0}, {10, 10}, {5, 5.5}, {0, 10}}, {rect_ring(1, 4, 3, 6), rect_ring(6, 1, 8, 3)}};
        check_triangulation(p, triangulate(p));
    }
    SECTION("a hole touching the outer ring at a vertex (as Clipper may return it)") {
        polygon_with_holes p{{{0, 0}, {5, 0}, {10, 0}, {10, 10}, {0, 10}}, {{{5, 0}, {4, 2}, {6, 2}}, rect_ring(6, 5, 8, 7)}};
        check_triangulation(p, triangulate(p));
        polygon_with_holes q{{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {{{10, 5}, {8, 4}, {8, 6}}}};  // touching the right side
        q.outer.insert(q.outer.begin() + 2, vec2{10, 5});
        check_triangulation(q, triangulate(q));
    }
    SECTION("random circular holes in a disc") {
        for (std::uint64_t s = 0; s < 10; ++s) {
            counter_rng rng(7, s);
            polygon_with_holes p;
            for (int i = 0; i < 64; ++i) p.outer.push_back({10 * std::cos(i * std::numbers::pi / 32), 10 * std::sin(i * std::numbers::pi / 32)});
            for (int hx = -3; hx <= 3; ++hx)
                for (int hy = -3; hy <= 3; ++hy) {
                    if (hx * hx + hy * hy > 9 || rng.uniform() < 0.3) continue;
                    const vec2 c{hx * 2.4 + rng.uniform(-0.2, 0.2), hy * 2.4 + rng.uniform(-0.2, 0.2)};
                    ring2 h;
                    const int m = 3 + static_cast<int>(rng.uniform_int(12));
                    for (int k = 0; k < m; ++k) h.push_back(c + 0.8 * vec2(std::cos(2 * std::numbers::pi * k / m), std::sin(2 * std::numbers::pi * k / m)));
                    p.holes.push_back(h);
                }
            INFO("seed " << s << " holes " << p.holes.size());
            check_triangulation(p, triangulate(p));
        }
    }
}

// Speed is measured in benchmarks/triangulate.cpp, not asserted here.
TEST_CASE("triangulate: every polygon of every bundled vector exemplar", "[geometry][triangulate]") {
    for (const char* f : {"lace_scallop.svg", "greek_key.svg", "pearls.svg", "vine.svg", "quatrefoil.svg", "hearts.svg", "zigzag.svg"}) {
        INFO(f);
        const auto ex = vector_pattern::exemplar_from_svg(io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/" + f));
        for (const auto& p : ex.polygons) check_triangulation(p, triangulate(p));
    }
}

TEST_CASE("triangulate: bad input is rejected with a message", "[geometry][triangulate]") {
    CHECK_THROWS_AS(triangulate(polygon_with_holes{{{0, 0}, {1, 0}}, {}}), invalid_input);
    CHECK_THROWS_AS(triangulate(polygon_with_holes{{{0, 0}, {1, 0}, {0, std::nan("")}}, {}}), invalid_input);
    CHECK_THROWS_AS(triangulate(polygon_with_holes{rect_ring(0, 0, 1, 1), {{{0.2, 0.2}, {0.4, 0.2}}}}), invalid_input);
    // a "hole" outside the outer ring has no bridge
    CHECK_THROWS_AS(triangulate(polygon_with_holes{rect_ring(0, 0, 1, 1), {rect_ring(5, 5, 6, 6)}}), solver_error);
}
