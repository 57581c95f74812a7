// surface/offset.hpp (eq. 9 of filigree-synthesis.md §6.2): volumes of thickened open
// surfaces against Steiner's formula (a square: slab + half cylinders + a ball; an open cylinder:
// annulus + two half tori), watertightness and one component, a closed sphere's void (filled or
// kept, volumes of the balls), a graded thickness, bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/surface/offset.hpp"
#include "support/sphere_mesh.hpp"

namespace offset_test {

using fabsynth::triangle_mesh;
using fabsynth::vec3;

inline void check_closed_piece(const triangle_mesh& s) {
    const auto t = fabsynth::analyze_topology(s);
    CHECK(t.is_watertight());
    std::size_t parts = 0;
    (void)fabsynth::face_components(s, &parts);
    CHECK(parts == 1);
}

TEST_CASE("thicken_surface: a square sheet has Steiner's volume", "[geometry][surface_offset]") {
    const triangle_mesh sq = fabsynth::test::plane_grid(10, 1.0, 1, 0.0);  // [0, 10]^2
    const double tau = 1.0, r = tau / 2, a = 10.0;
    const double exact = a * a * tau + 4 * a * (std::numbers::pi * r * r / 2) + 4.0 / 3 * std::numbers::pi * r * r * r;
    const triangle_mesh s = fabsynth::thicken_surface(sq, tau, {.cell = 0.05});
    check_closed_piece(s);
    INFO("volume " << fabsynth::signed_volume(s) << " exact " << exact);
    CHECK(fabsynth::signed_volume(s) == Approx(exact).epsilon(1e-3));  // measured 116.202 vs 116.232
}

TEST_CASE("thicken_surface: an open cylinder band has Steiner's volume", "[geometry][surface_offset]") {
    const double R = 10.0, h = 10.0, tau = 1.0, rho = tau / 2;
    const triangle_mesh band = fabsynth::test::cylinder(R, h, 256, 0.5);
    const double exact = 2 * std::numbers::pi * R * tau * h + 2 * std::numbers::pi * std::numbers::pi * R * rho * rho;  // annulus + 2 half tori
    const triangle_mesh s = fabsynth::thicken_surface(band, tau, {.cell = 0.08});
    check_closed_piece(s);
    INFO("volume " << fabsynth::signed_volume(s) << " exact " << exact);
    CHECK(fabsynth::signed_volume(s) == Approx(exact).epsilon(1e-3));  // measured 677.44 vs 677.67
}

TEST_CASE("thicken_surface: a closed sphere's void is filled by default, kept on request", "[geometry][surface_offset]") {
    const double R = 5.0, tau = 1.0;
    const triangle_mesh sphere = fabsynth::test::sphere_mesh(R, 4);  // 2048 faces, edges about 0.3 mm
    const double outer = 4.0 / 3 * std::numbers::pi * std::pow(R + tau / 2, 3), inner = 4.0 / 3 * std::numbers::pi * std::pow(R - tau / 2, 3);
    const triangle_mesh kept = fabsynth::thicken_surface(sphere, tau, {.cell = 0.1, .fill_cavities = false});
    std::size_t shells = 0;
    (void)fabsynth::face_components(kept, &shells);
    CHECK(shells == 2);  // the outer surface and the void's
    CHECK(fabsynth::is_watertight(kept));
    INFO("kept " << fabsynth::signed_volume(kept) << " exact " << outer - inner);
    CHECK(fabsynth::signed_volume(kept) == Approx(outer - inner).epsilon(1e-2));
    const triangle_mesh filled = fabsynth::thicken_surface(sphere, tau, {.cell = 0.1});
    check_closed_piece(filled);
    INFO("filled " << fabsynth::signed_volume(filled) << " exact " << outer);
    CHECK(fabsynth::signed_volume(filled) == Approx(outer).epsilon(1e-2));
}

TEST_CASE("thicken_surface: a graded thickness", "[geometry][surface_offset]") {
    const int n = 10;
    const triangle_mesh sq = fabsynth::test::plane_grid(n, 1.0, 1, 0.0);
    std::vector<double> tau;
    for (const vec3& v : sq.vertices) tau.push_back(0.5 + 0.1 * v.x);  // 0.5 mm at x = 0, 1.5 mm at x = 10
    const double cell = 0.04;
    const triangle_mesh s = fabsynth::thicken_surface(sq, tau, {.cell = cell});
    check_closed_piece(s);
    for (const double x0 : {2.0, 5.0, 8.0}) {  // the top surface over (x0, 5) stands at tau(x0) / 2
        double top = -1;
        for (const vec3& v : s.vertices)
            if (std::abs(v.x - x0) < cell && std::abs(v.y - 5.0) < cell) top = std::max(top, v.z);
        INFO("x0 " << x0);
        CHECK(top == Approx(0.5 * (0.5 + 0.1 * x0)).margin(cell));
    }
}

TEST_CASE("thicken_surface: bad input is named, large grids refused before work", "[geometry][surface_offset]") {
    const triangle_mesh sq = fabsynth::test::plane_grid(2, 1.0, 1, 0.0);
    using fabsynth::invalid_input;
    CHECK_THROWS_AS(fabsynth::thicken_surface(sq, 0.0), invalid_input);
    CHECK_THROWS_AS(fabsynth::thicken_surface(sq, NAN), invalid_input);
    CHECK_THROWS_AS(fabsynth::thicken_surface(sq, 1.0, {.cell = 0.0}), invalid_input);
    const std::vector<double> two{1.0, 1.0};
    CHECK_THROWS_AS(fabsynth::thicken_surface(sq, two), invalid_input);
    CHECK_THROWS_AS(fabsynth::thicken_surface(triangle_mesh{}, 1.0), invalid_input);
    CHECK_THROWS_AS(fabsynth::thicken_surface(sq, 1.0, {.cell = 1e-3, .max_samples = 1e6}), fabsynth::no_solution);
}

}  // namespace offset_test
