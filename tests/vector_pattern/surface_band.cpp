// Bands on surfaces (§6.3, Fig. 19-23): a pattern synthesized along a curve drawn on the bundled
// vase, embossed onto and carved out of a shell. The solids are watertight and their topology is
// the one the developed band predicts, counted independently on the band by
// tests/support/raster_topology.hpp: embossing adds no component or handle; carving punches one
// handle per pattern component, leaves one island per pattern hole, and a pattern winding around a
// closed band cuts the vase in two (its upper part, an annulus thickened, is a solid torus).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "fabsynth/surface/disk_parameterization.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/surface/curve.hpp"
#include "fabsynth/surface/decoration.hpp"
#include "fabsynth/io/mesh.hpp"
#include "fabsynth/vector_pattern/synthesis.hpp"
#include "support/raster_topology.hpp"
#include "support/vector_band.hpp"

using namespace fabsynth;

namespace vector_pattern_surface_band_test {

// A wavy loop around the vase's belly through 8 points of its profile r(z) = 20 + 9 sin(pi z / 70).
std::vector<vec3> belly_loop() {
    std::vector<vec3> p;
    for (int i = 0; i < 8; ++i) {
        const double a = 2 * std::numbers::pi * i / 8, z = 45 + 6 * std::sin(2 * a), r = 20 + 9 * std::sin(std::numbers::pi * z / 70);
        p.push_back({r * std::cos(a), r * std::sin(a), z});
    }
    return p;
}

struct band_case {
    const char* exemplar;
    std::optional<std::uint32_t> components;
    bool closed_loop;
    double cell;
};

TEST_CASE("surface band: emboss and carve on the vase have the developed band's topology", "[vector_pattern][surface][slow]") {
    const triangle_mesh vase = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/vase.obj");
    const disk_parameterization phi(vase);
    const surface_curve drawn = trace_surface_curve(phi, belly_loop(), true);
    const double height = 12.0;
    const space_curve band = drawn.band_curve(height / 8);
    band.check_band(height / 2);
    for (const band_case& bc : {band_case{"disks.svg", std::nullopt, false, 0.5}, band_case{"greek_key.svg", 1u, true, 0.3}}) {
        INFO(bc.exemplar);
        const auto raw = fabsynth::test::load_vector_exemplar(bc.exemplar);
        const auto ex = vector_pattern::scaled(raw, height / raw.height());
        vector_pattern::synthesis_options so;
        so.band_height = height;
        so.length = band.length();
        so.closed = true;
        so.components = bc.components;
        so.closed_loop = bc.closed_loop;
        const auto res = vector_pattern::synthesize_along(ex, so);
        // the developed band's topology, counted on its own raster (glued at the seam)
        const auto topo = fabsynth::test::raster_topology(res.polygons, {0.0, -height}, {band.length(), height}, 0.04, true);
        // exactly the requested count, or (unconstrained) the count the synthesis reports
        CHECK(topo.components == bc.components.value_or(res.components));
        CHECK(topo.holes == res.holes);
        const triangle_mesh embossed = decorate_surface(vase, band, res.polygons, {.mode = decoration_mode::emboss, .shell = 2.0, .height = 1.0, .cell = bc.cell});
        const mesh_topology_info e = analyze_topology(embossed);
        REQUIRE(e.is_watertight());
        CHECK(e.components == 1);
        CHECK(e.genus == 0);
        const triangle_mesh carved = decorate_surface(vase, band, res.polygons, {.mode = decoration_mode::carve, .shell = 2.5, .cell = bc.cell});
        const mesh_topology_info c = analyze_topology(carved);
        REQUIRE(c.is_watertight());
        if (bc.closed_loop) {  // one component winding around: top and bottom part, islands in the holes
            CHECK(topo.components == 1);
            CHECK(c.components == 2 + topo.holes);
            CHECK(c.genus == 1);
        } else {
            CHECK(c.components == 1 + topo.holes);
            CHECK(c.genus == static_cast<long long>(topo.components));
        }
        // the relief adds about the pattern's area times its height (1 mm) to the volume
        double area = 0.0;
        for (const auto& p : res.polygons) area += fabsynth::area(p);
        // (the grid depends on the surface and the heights only: a speck of a pattern gives the bare shell on the same grid)
        const double shell_only = signed_volume(decorate_surface(vase, band, {{{{10, 0}, {10.01, 0}, {10, 0.01}}, {}}},
                                                                 {.mode = decoration_mode::emboss, .shell = 2.0, .height = 1.0, .cell = bc.cell}));
        CHECK(signed_volume(embossed) - shell_only == Approx(area * 1.0).epsilon(0.1));
    }
}

}  // namespace vector_pattern_surface_band_test
