// Tests for geometry/extrude.hpp: watertight, outward, volume = area x thickness; conforming
// refinement; the curve extrusion of §6.3 with seam welding on closed curves.
#include <catch2/catch.hpp>

#include "support/test_util.hpp"

#include <cmath>
#include <array>
#include <map>
#include <set>
#include <numbers>
#include <string>
#include <vector>

#include "fabsynth/geometry/extrude.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/triangulate.hpp"
#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"
#include "support/vector_band.hpp"

using namespace fabsynth;
using Catch::Matchers::Contains;

namespace {
using fabsynth::test::rect_ring;

// Independent watertightness check: every undirected edge in exactly two faces, traversed once in
// each direction.
bool closed_and_oriented(const triangle_mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
    for (const auto& [e, n] : directed)
        if (n != 1 || !directed.count({e.second, e.first}) || directed.at({e.second, e.first}) != 1) return false;
    return !m.faces.empty();
}
}  // namespace

TEST_CASE("extrude: slabs are watertight, outward, with volume = area x thickness", "[geometry][extrude]") {
    const polygon_with_holes p{rect_ring(0, 0, 10, 6), {rect_ring(2, 2, 4, 4), rect_ring(6, 1, 8, 5)}};
    const triangle_mesh m = extrude(triangulate(p), 1.5);
    const auto topo = analyze_topology(m);
    CHECK(topo.is_watertight());
    CHECK(closed_and_oriented(m));
    CHECK(topo.components == 1);
    CHECK(topo.genus == 2);  // two through-holes
    CHECK(signed_volume(m) == Approx(area(p) * 1.5).epsilon(1e-12));
    // surface = 2 area + perimeter x thickness
    const double perim = perimeter(p.outer) + perimeter(p.holes[0]) + perimeter(p.holes[1]);
    CHECK(surface_area(m) == Approx(2 * area(p) + 1.5 * perim).epsilon(1e-12));
    CHECK_THROWS_AS(extrude(triangulate(p), 0.0), invalid_input);
    CHECK_THROWS_AS(extrude(triangulate(p), std::nan("")), invalid_input);
    // a doubled triangle is an overlap
    planar_triangulation bad = triangulate(polygon_with_holes{rect_ring(0, 0, 1, 1), {}});
    bad.triangles.push_back(bad.triangles.front());
    CHECK_THROWS_WITH(extrude(bad, 1.0), Contains("used twice"));
}

TEST_CASE("extrude: refinement bounds the x-extent of every edge and stays conforming", "[geometry][extrude]") {
    const auto ex = vector_pattern::exemplar_from_svg(io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/greek_key.svg"));
    planar_triangulation t = triangulate(ex.polygons);
    const double a0 = area(ex.polygons);
    refine_x_extent(t, 0.7);
    double a = 0;
    for (const auto& tri : t.triangles) {
        const vec2 p = t.vertices[tri[0]], q = t.vertices[tri[1]], r = t.vertices[tri[2]];
        CHECK(orient2d(p, q, r) >= -1e-12);  // flat slivers allowed, no inverted triangle
        a += 0.5 * orient2d(p, q, r);
        for (auto [x, y] : {std::pair{p, q}, std::pair{q, r}, std::pair{r, p}}) CHECK(std::abs(x.x - y.x) <= 0.7 * (1 + 1e-12));
    }
    CHECK(a == Approx(a0).epsilon(1e-12));
    const triangle_mesh m = extrude(t, 1.0);
    CHECK(analyze_topology(m).is_watertight());
    CHECK(analyze_topology(m).genus == static_cast<long long>(ex.holes()));
    CHECK(signed_volume(m) == Approx(a0).epsilon(1e-12));
}

TEST_CASE("extrude_along_curve: straight line = plain extrusion", "[geometry][extrude]") {
    const std::vector<polygon_with_holes> band{{rect_ring(0, -2, 30, 2), {rect_ring(5, -1, 25, 1)}}};
    const triangle_mesh m = extrude_along_curve(band, planar_curve::line(30), {.thickness = 2.0});
    CHECK(analyze_topology(m).is_watertight());
    CHECK(signed_volume(m) == Approx(area(band) * 2.0).epsilon(1e-12));
}

TEST_CASE("extrude_along_curve: closed circle, the seam is welded", "[geometry][extrude]") {
    const double R = 20.0, L = 2 * std::numbers::pi * R, t = 1.0;
    const planar_curve c = planar_curve::circle(R);
    SECTION("a full annulus is one closed torus-like solid") {
        const std::vector<polygon_with_holes> band{{rect_ring(0, -2, L, 2), {}}};
        const triangle_mesh m = extrude_along_curve(band, c, {.thickness = t, .chord_tolerance = 1e-3});
        const auto topo = analyze_topology(m);
        CHECK(topo.is_watertight());
        CHECK(closed_and_oriented(m));
        CHECK(topo.components == 1);
        CHECK(topo.genus == 1);
        // exact annulus area pi ((R+2)^2 - (R-2)^2) = 8 pi R; the chords lose at most ~tol x perimeter
        const double exact = 8 * std::numbers::pi * R * t;
        CHECK(signed_volume(m) < exact);
        CHECK(signed_volume(m) > exact - 2 * std::numbers::pi * (2 * R) * 1e-3 * t * 1.01);
        // every vertex at radius R + v, v in [-2, 2]; the side walls exactly at R - 2 and R + 2
        std::size_t inner = 0, outer = 0;
        for (const vec3& p : m.vertices) {
            const double r = std::hypot(p.x, p.y);
            CHECK(r >= R - 2 - 1e-9);
            CHECK(r <= R + 2 + 1e-9);
            inner += std::abs(r - (R - 2)) < 1e-9;
            outer += std::abs(r - (R + 2)) < 1e-9;
        }
        CHECK(inner >= 2 * 100);  // refined rim: many vertices on each circle, top and bottom
        CHECK(outer >= 2 * 100);
    }
    SECTION("shapes cut at u = 0 and u = L become one component, with different vertices on each cut") {
        // one bar crossing the seam, cut into [0, 3] and [L - 4, L]; the u = 0 side has an extra
        // vertex on its cut (conform_seam inserts it on the other side), plus a hole in the bar
        const std::vector<polygon_with_holes> band{
            {{{0, -1}, {3, -1}, {3, 1}, {0, 1}, {0, 0.25}}, {}},
            {rect_ring(L - 4, -1, L, 1), {rect_ring(L - 3, -0.5, L - 1, 0.5)}},
            {rect_ring(10, -1, 20, 1), {}}};
        const triangle_mesh m = extrude_along_curve(band, c, {.thickness = t});
        const auto topo = analyze_topology(m);
        CHECK(topo.is_watertight());
        CHECK(topo.components == 2);
        CHECK(topo.genus == 1);
    }
    SECTION("a shape touching a cut at one vertex needs no partner (vine.svg on a circle did this)") {
        const std::vector<polygon_with_holes> band{{{{L - 5, -1}, {L, -0.5}, {L - 5, 1}}, {}},
                                                   {{{0, 0.7}, {5, 0}, {5, 1.5}}, {}}};
        const triangle_mesh m = extrude_along_curve(band, c, {.thickness = t});
        const auto topo = analyze_topology(m);
        CHECK(topo.is_watertight());
        CHECK(closed_and_oriented(m));
        CHECK(topo.components == 2);
    }
    SECTION("cuts that do not match are rejected") {
        const std::vector<polygon_with_holes> band{{rect_ring(0, -1, 3, 1), {}}, {rect_ring(L - 4, -1.5, L, 1.5), {}}};
        CHECK_THROWS_WITH(extrude_along_curve(band, c, {.thickness = t}), Contains("no partner"));
    }
    SECTION("bad input") {
        CHECK_THROWS_WITH(extrude_along_curve({{rect_ring(0, -1, L + 1, 1), {}}}, c), Contains("outside"));
        CHECK_THROWS_WITH(extrude_along_curve({{rect_ring(0, -R, 5, 1), {}}}, c), Contains("radius of curvature"));
        CHECK_THROWS_AS(extrude_along_curve({{rect_ring(0, -1, 5, 1), {}}}, c, {.thickness = -1}), invalid_input);
    }
}

TEST_CASE("extrude_along_curve: a bundled exemplar along an open arc", "[geometry][extrude]") {
    const auto ex = vector_pattern::exemplar_from_svg(io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/lace_scallop.svg"));
    std::vector<polygon_with_holes> band = test::vector_band("lace_scallop.svg");  // u from 0, v centred
    const double W = ex.width(), R = 1.5 * W / std::numbers::pi;  // a third of a circle
    std::vector<vec2> arc;
    for (int i = 0; i <= 2000; ++i) {
        const double a = (W / R) * i / 2000.0;
        arc.push_back({R * std::sin(a), R - R * std::cos(a)});
    }
    const planar_curve c = planar_curve::polyline(arc, false);
    const double L = c.length();
    for (auto& p : band) {  // fit u into [0, L] (the polyline is a little shorter than the arc)
        for (vec2& q : p.outer) q.x *= L / W;
        for (auto& h : p.holes)
            for (vec2& q : h) q.x *= L / W;
    }
    const triangle_mesh m = extrude_along_curve(band, c, {.thickness = 0.8, .chord_tolerance = 0.01});
    const auto topo = analyze_topology(m);
    CHECK(topo.is_watertight());
    CHECK(topo.components == ex.components());
    CHECK(topo.genus == static_cast<long long>(ex.holes()));
    // area element of the band map (1 - v / R) integrates to the band polygons' area when the pattern
    // is symmetric enough; compare against the exact integral of (1 - v/R) over the polygons instead:
    // integral of v over a polygon = area x centroid_v (shoelace moments)
    double expected = 0.0;
    for (const auto& p : band) {
        auto moment = [&](const ring2& r) {
            double a = 0, mv = 0;
            for (std::size_t i = 0; i < r.size(); ++i) {
                const vec2 p0 = r[i], p1 = r[(i + 1) % r.size()];
                const double cr = p0.x * p1.y - p1.x * p0.y;
                a += 0.5 * cr;
                mv += cr * (p0.y + p1.y) / 6.0;
            }
            return std::pair{a, mv};
        };
        auto [a, mv] = moment(p.outer);
        expected += a - mv / R;
        for (const auto& h : p.holes) {
            auto [ah, mvh] = moment(h);
            expected += ah - mvh / R;
        }
    }
    // the arc bends to the left (towards +y), and n = (-t.y, t.x) points to the left, i.e. towards
    // the centre: radius R - v, area element (1 - v / R)
    CHECK(signed_volume(m) / 0.8 == Approx(expected).epsilon(2e-3));
}

// Reproducer of the GCC 12 SLP miscompile (core/compiler.hpp): without FABSYNTH_NO_SLP_VECTORIZE
// on weld_to_float, GCC 12.2 -O2 rounds only z to float. Checked per component against an oracle
// written component by component.
TEST_CASE("weld_to_float rounds every component to single precision", "[extrude][float]") {
    triangle_mesh m;
    m.vertices = {{0.1, 0.2, 0.3}, {1.1, 2.2, 3.3}, {-7.7, 1e-3, 12345.678}, {0.1 + 1e-12, 0.2, 0.3}};
    m.faces = {{0, 1, 2}, {3, 1, 2}};
    const std::vector<vec3> before = m.vertices;
    weld_to_float(m);
    REQUIRE(m.vertices.size() == 3);  // vertex 3 equals vertex 0 in float
    for (std::size_t i = 0; i < 3; ++i) {
        const float x = static_cast<float>(before[i].x), y = static_cast<float>(before[i].y), z = static_cast<float>(before[i].z);
        CHECK(m.vertices[i].x == static_cast<double>(x));
        CHECK(m.vertices[i].y == static_cast<double>(y));
        CHECK(m.vertices[i].z == static_cast<double>(z));
    }
    CHECK(m.faces.size() == 2);
    CHECK(m.faces[1][0] == 0);
}

TEST_CASE("weld_to_float keeps apart what a merge would open or pinch", "[extrude][float]") {
    SECTION("two squares touching at a corner: the shared corner stays two vertices") {
        // the slab's two walls meet along one vertical edge; welding by position alone makes that
        // edge non-manifold (4 faces)
        const std::vector<polygon_with_holes> polys{{rect_ring(0, 0, 1, 1), {}}, {rect_ring(1, 1, 2, 2), {}}};
        triangle_mesh m = extrude(triangulate(polys), 1.0);
        REQUIRE(closed_and_oriented(m));
        const std::size_t vertices = m.vertices.size();
        weld_to_float(m);
        CHECK(closed_and_oriented(m));
        CHECK(analyze_topology(m).is_watertight());
        CHECK(m.vertices.size() == vertices);  // the corners at (1, 1, z) are kept apart
        std::set<std::array<float, 3>> positions;  // every vertex a distinct float position
        for (const vec3& p : m.vertices) {
            const std::array<float, 3> k{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
            CHECK(static_cast<double>(k[0]) == p.x);
            positions.insert(k);
        }
        CHECK(positions.size() == m.vertices.size());
        for (const vec3& p : m.vertices) CHECK(glm::length(p - vec3(glm::round(p))) < 1e-6);  // moved by float steps only
    }
    SECTION("a collapse that breaks the link condition is not made") {
        // a tetrahedron a b c d with face b c d split at e; b and c 1e-9 apart, 100 mm from the
        // origin (one float position): the edge b-c has faces with a and e opposite, but d is also
        // a common neighbour, so collapsing b-c makes c-d an edge of four faces
        triangle_mesh m;
        m.vertices = {{100, 0, 1}, {100, 0, 0}, {100 + 1e-9, 0, 0}, {100, 1, 0}, {100.3, 0.3, 0}};  // a b c d e
        m.faces = {{0, 2, 1}, {0, 3, 2}, {0, 1, 3}, {4, 1, 2}, {4, 2, 3}, {4, 3, 1}};
        REQUIRE(closed_and_oriented(m));
        weld_to_float(m);
        CHECK(closed_and_oriented(m));
        CHECK(m.vertices.size() == 5);
        CHECK(m.faces.size() == 6);
    }
    SECTION("a collapse that keeps the surface closed is still made") {
        // an extruded square 100 mm from the origin with a vertex 1e-9 from a corner on one edge
        // (one float position): the short edges collapse, their faces are dropped, the slab stays
        // closed
        ring2 r{{100, 0}, {100 + 1e-9, 0}, {101, 0}, {101, 1}, {100, 1}};
        triangle_mesh m = extrude(triangulate(std::vector<polygon_with_holes>{{r, {}}}), 1.0);
        REQUIRE(m.vertices.size() == 10);
        weld_to_float(m);
        CHECK(m.vertices.size() == 8);
        CHECK(closed_and_oriented(m));
    }
}
