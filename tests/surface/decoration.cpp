// surface/decoration.hpp: on a flat plate the embossed and carved solids are watertight,
// their volumes match Steiner's formula for the shell plus / minus the pattern's prisms, and their
// topology matches the developed band's, counted independently (tests/support/raster_topology.hpp):
// embossing adds no component or handle, carving punches one handle per pattern component and
// leaves one island per pattern hole. Bad input is refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/surface/disk_parameterization.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/space_curve.hpp"
#include "fabsynth/surface/curve.hpp"
#include "fabsynth/surface/decoration.hpp"
#include "fabsynth/io/mesh.hpp"
#include "support/raster_topology.hpp"

using namespace fabsynth;

namespace geometry_surface_decoration_test {

constexpr double plate_w = 60, plate_h = 40, shell = 2.0, relief = 1.0;

triangle_mesh plate() {  // z = 0, normals +z, 2 mm cells
    triangle_mesh m;
    const int nx = 30, ny = 20;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) m.vertices.emplace_back(i * plate_w / nx, j * plate_h / ny, 0.0);
    auto id = [](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return m;
}

ring2 circle(vec2 c, double r, bool ccw) {
    ring2 out;
    for (int i = 0; i < 96; ++i) {
        const double a = 2 * std::numbers::pi * i / 96 * (ccw ? 1 : -1);
        out.push_back(c + r * vec2(std::cos(a), std::sin(a)));
    }
    return out;
}

polygon_with_holes rect(double u0, double u1, double v0, double v1) { return {{{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}}, {}}; }

double pattern_area(const std::vector<polygon_with_holes>& p) {
    double a = 0;
    for (const auto& q : p) a += area(q);
    return a;
}

// The shell |w| <= T/2 around the plate: Steiner's formula for a flat convex body (2 r A + pi/2 P
// r^2 + 4/3 pi r^3, r = T/2).
double shell_volume() {
    const double r = shell / 2;
    return 2 * r * plate_w * plate_h + std::numbers::pi / 2 * 2 * (plate_w + plate_h) * r * r + 4.0 / 3 * std::numbers::pi * r * r * r;
}

long long total_genus(const triangle_mesh& m) { return analyze_topology(m).genus; }

TEST_CASE("surface decoration: emboss and carve on a plate, volumes and topology", "[geometry][decoration]") {
    const triangle_mesh base = plate();
    // the band along y = 20 from x = 5 to 55: u = x - 5, v = y - 20 (n = z x t = +y, b = +z)
    const space_curve band = space_curve::polyline({{5, 20, 0}, {55, 20, 0}}, false);
    struct pattern_case {
        const char* name;
        std::vector<polygon_with_holes> shapes;
    };
    const std::vector<pattern_case> cases{
        {"three bars", {rect(2, 10, -4, 4), rect(17, 25, -4, 4), rect(32, 40, -4, 4)}},
        {"a ring and a disk", {{circle({15, 0}, 7, true), {circle({15, 0}, 3.5, false)}}, {circle({36, 1}, 5, true), {}}}},
        {"a frame with two windows", {{rect(4, 44, -8, 8).outer, {rect(8, 20, -5, 5).outer, rect(26, 40, -5, 5).outer}}}},
    };
    for (const auto& pc : cases) {
        INFO(pc.name);
        std::vector<polygon_with_holes> shapes = pc.shapes;
        for (auto& p : shapes) orient(p);
        const auto topo = fabsynth::test::raster_topology(shapes, {-5, -20}, {55, 20}, 0.05);
        const double a = pattern_area(shapes);
        {
            const triangle_mesh m = decorate_surface(base, band, shapes, {.mode = decoration_mode::emboss, .shell = shell, .height = relief, .cell = 0.25});
            const mesh_topology_info info = analyze_topology(m);
            REQUIRE(info.is_watertight());
            CHECK(info.components == 1);
            CHECK(info.genus == 0);
            CHECK(signed_volume(m) == Approx(shell_volume() + a * relief).epsilon(0.01));
            const box3 b = bounding_box(m);
            CHECK(b.hi.z == Approx(shell / 2 + relief).margin(0.05));  // the relief is on the normals' side
            CHECK(b.lo.z == Approx(-shell / 2).margin(0.05));
        }
        {
            const triangle_mesh m = decorate_surface(base, band, shapes, {.mode = decoration_mode::carve, .shell = shell, .cell = 0.25});
            const mesh_topology_info info = analyze_topology(m);
            REQUIRE(info.is_watertight());
            CHECK(info.components == 1 + topo.holes);      // each hole of the pattern leaves an island
            CHECK(total_genus(m) == static_cast<long long>(topo.components));  // each component punches a handle
            CHECK(signed_volume(m) == Approx(shell_volume() - a * shell).epsilon(0.01));
        }
    }
}

TEST_CASE("surface decoration: the relief follows a curved surface", "[geometry][decoration]") {
    // a cylinder patch of radius 30 around the y axis (an open disk), the band along its generator
    triangle_mesh m;
    const int na = 24, ny = 20;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= na; ++i) {
            const double a = -0.6 + 1.2 * i / na;
            m.vertices.emplace_back(30 * std::sin(a), 2.0 * j, 30 * std::cos(a));
        }
    auto id = [](int i, int j) { return static_cast<std::uint32_t>(j * (na + 1) + i); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < na; ++i) {  // outward normals (away from the axis)
            m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    // the band runs along the generator x = 0 (a line of the mesh), with v around the cylinder
    const space_curve band = space_curve::polyline({{0, 4, 30}, {0, 36, 30}}, false, {.up = {0, 0, 1}});
    const std::vector<polygon_with_holes> bar{rect(4, 28, -12, 12)};  // 24 mm across: wraps around the cylinder
    const triangle_mesh out = decorate_surface(m, band, bar, {.mode = decoration_mode::emboss, .shell = shell, .height = relief, .cell = 0.25});
    const mesh_topology_info info = analyze_topology(out);
    REQUIRE(info.is_watertight());
    CHECK(info.components == 1);
    CHECK(info.genus == 0);
    // every vertex of the relief's top lies at radius 30 + shell/2 + relief: none floats off the surface
    double top = 0;
    for (const vec3& p : out.vertices)
        if (p.y > 12 && p.y < 28) top = std::max(top, std::hypot(p.x, p.z));
    CHECK(top == Approx(30 + shell / 2 + relief).margin(0.05));
}

TEST_CASE("surface decoration: band coordinates are continuous around the bends of the polyline", "[geometry][decoration]") {
    // a coarse polyline bending in and out of its band's plane (15 degrees per vertex)
    std::vector<vec3> p;
    for (int i = 0; i <= 12; ++i) p.push_back({8.0 * std::sin(0.26 * i) * 10, 10.0 * i, 6.0 * std::cos(0.2 * i)});
    const space_curve c = space_curve::polyline(p, false);
    const detail::decoration::band_coordinates coords(c);
    const mesh_distance on_curve(detail::decoration::polyline_mesh(c));
    // walks along the curve at offsets up to 4 mm across it (the band lies along x, v = -x), in
    // steps of a few um: u and v move by a few steps at most (a closest-point u jumps by offset x bend)
    double worst = 0.0;
    for (const vec3 off : {vec3(3, 0, 1.5), vec3(-3, 0, -1.5), vec3(4, 0, 0), vec3(-4, 0, 1)}) {  // across the band, and off its plane
        vec2 last{0};
        for (int i = 0; i <= 100000; ++i) {
            const double y = 20.0 + 60.0 * i / 100000;
            const double s = y / 10.0;  // follow the curve's x and z at this height, offset
            const vec3 q = vec3(8.0 * std::sin(0.26 * s) * 10, y, 6.0 * std::cos(0.2 * s)) + off;
            const vec2 uv = coords(q, on_curve.closest(q).face);
            if (i > 0) worst = std::max(worst, glm::length(uv - last));
            last = uv;
        }
    }
    CHECK(worst < 0.01);  // steps are 0.6 um along y, ~2 um in space
}

TEST_CASE("surface decoration: a closed sphere, cut open away from the band", "[geometry][decoration]") {
    triangle_mesh sphere = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/icosphere.obj");
    for (vec3& p : sphere.vertices) p *= 30.0;  // a 30 mm sphere
    std::vector<vec3> loop;  // 6 points around the equator, tilted
    for (int i = 0; i < 6; ++i) {
        const double a = 2 * std::numbers::pi * i / 6, z = 5 * std::sin(a);
        loop.push_back(glm::normalize(vec3(std::cos(a), std::sin(a), z / 30)) * 30.0);
    }
    const std::uint32_t cut = farthest_vertex(sphere, loop);
    CHECK(std::abs(sphere.vertices[cut].z) > 29.0);  // a pole
    const disk_parameterization phi(cut_open(sphere, cut));
    const surface_curve s = trace_surface_curve(phi, loop, true);
    const mesh_distance md(sphere);
    for (const vec3& p : s.points) REQUIRE(std::sqrt(md.closest(p).dist2) < 1e-9 * 60);
    const space_curve band = s.band_curve(1.0);
    // three bars across the band
    const double L = band.length();
    const std::vector<polygon_with_holes> bars{rect(0.1 * L, 0.1 * L + 8, -4, 4), rect(0.4 * L, 0.4 * L + 8, -4, 4), rect(0.7 * L, 0.7 * L + 8, -4, 4)};
    const triangle_mesh e = decorate_surface(sphere, band, bars, {.mode = decoration_mode::emboss, .shell = 2.0, .height = 1.0, .cell = 0.4});
    const mesh_topology_info ei = analyze_topology(e);
    REQUIRE(ei.is_watertight());
    CHECK(ei.components == 1);  // the cavity inside the shell is filled: a solid ball with reliefs
    CHECK(ei.genus == 0);
    const triangle_mesh c = decorate_surface(sphere, band, bars, {.mode = decoration_mode::carve, .shell = 2.0, .cell = 0.4});
    const mesh_topology_info ci = analyze_topology(c);
    REQUIRE(ci.is_watertight());
    CHECK(ci.components == 1);  // a hollow shell with three windows (its inside reaches the outside)
    CHECK(ci.genus == 2);       // a sphere's shell with three holes: genus 3 - 1
}

TEST_CASE("surface decoration: the same bits for 1 and 2 threads", "[geometry][decoration]") {
    const triangle_mesh base = plate();
    const space_curve band = space_curve::polyline({{5, 20, 0}, {55, 20, 0}}, false);
    const std::vector<polygon_with_holes> shapes{{circle({15, 0}, 7, true), {circle({15, 0}, 3.5, false)}}};
    set_num_threads(1);
    const triangle_mesh one = decorate_surface(base, band, shapes, {.mode = decoration_mode::emboss, .cell = 0.4});
    set_num_threads(2);
    const triangle_mesh two = decorate_surface(base, band, shapes, {.mode = decoration_mode::emboss, .cell = 0.4});
    set_num_threads(0);
    CHECK(one.vertices == two.vertices);
    CHECK(one.faces == two.faces);
}

TEST_CASE("surface decoration: bad input is refused", "[geometry][decoration]") {
    const triangle_mesh base = plate();
    const space_curve band = space_curve::polyline({{5, 20, 0}, {55, 20, 0}}, false);
    const std::vector<polygon_with_holes> bar{rect(2, 10, -4, 4)};
    CHECK_THROWS_AS(decorate_surface(base, band, {}, {}), invalid_input);
    CHECK_THROWS_AS(decorate_surface(base, band, bar, {.shell = 0}), invalid_input);
    CHECK_THROWS_AS(decorate_surface(base, band, bar, {.height = NAN}), invalid_input);
    CHECK_THROWS_AS(decorate_surface(base, band, bar, {.cell = -1}), invalid_input);
    CHECK_THROWS_AS(decorate_surface(triangle_mesh{}, band, bar, {}), invalid_input);
    CHECK_THROWS_AS(decorate_surface(base, band, bar, {.cell = 0.001}), no_solution);
    std::vector<polygon_with_holes> bad = bar;
    bad[0].outer[1].x = NAN;
    CHECK_THROWS_AS(decorate_surface(base, band, bad, {}), invalid_input);
}

}  // namespace geometry_surface_decoration_test
