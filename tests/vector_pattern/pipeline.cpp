// Tests for vector_pattern/pipeline.hpp: make_pattern along a line, in a rectangle, along a curve
// in space and on a closed surface (cut open), on small inputs. The solids must be watertight and
// have the requested topology, counted independently (the drawing by tests/support/raster_topology.hpp,
// the solid by analyze_topology); the result must equal the phases chained by hand; a progress
// callback returning false cancels at every phase boundary.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/io/mesh.hpp"
#include "fabsynth/vector_pattern/pipeline.hpp"
#include "support/raster_topology.hpp"
#include "support/vector_band.hpp"

using namespace fabsynth;

namespace vector_pattern_pipeline_test {

namespace vp = fabsynth::vector_pattern;

vp::pattern_options options(double height, std::optional<std::uint32_t> components) {
    vp::pattern_options o;
    o.band_height = height;
    o.synthesis.components = components;
    return o;
}

// An extruded slab of a planar region: every component of the drawing is one solid component,
// and each of its holes one handle.
void check_slab(const vp::pattern_result& r, std::size_t components, std::size_t holes) {
    const mesh_topology_info t = analyze_topology(r.mesh);
    REQUIRE(t.is_watertight());
    CHECK(t.components == components);
    CHECK(t.genus == static_cast<long long>(holes));
}

bool same_polygons(const std::vector<polygon_with_holes>& a, const std::vector<polygon_with_holes>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].outer != b[i].outer || a[i].holes != b[i].holes) return false;
    return true;
}

TEST_CASE("pipeline: along a line, the result of the phases chained by hand", "[vector_pattern][pipeline]") {
    const vp::exemplar raw = fabsynth::test::load_vector_exemplar("greek_key.svg");
    const double H = 10.0;
    const planar_curve line = planar_curve::line(80.0);
    const vp::pattern_options opt = options(H, 1u);
    const vp::pattern_result r = vp::make_pattern(raw, vp::along_planar_curve{line}, opt);
    CHECK(r.synthesis.components == 1);
    CHECK_FALSE(r.in_space);
    CHECK(r.band_length == Approx(80.0));
    CHECK(r.stretch == Approx(80.0 / r.natural_length));
    // the drawing's topology, counted on its raster (the line lies along x, the band within H/2)
    const auto topo = fabsynth::test::raster_topology(r.drawn, {-1.0, -H}, {81.0, H}, 0.02);
    CHECK(topo.components == 1);
    CHECK(topo.holes == r.synthesis.holes);
    check_slab(r, 1, topo.holes);
    std::size_t rings = 0;
    for (const auto& p : r.drawn) rings += 1 + p.holes.size();
    CHECK(r.rings == rings);

    // by hand: scale, synthesize, map, extrude, mirror, weld, preview
    const vp::exemplar ex = vp::scaled(raw, H / raw.height());
    vp::synthesis_options so;
    so.length = line.length();
    so.band_height = H;
    so.components = 1u;
    const vp::synthesis_result s = vp::synthesize_along(ex, so);
    CHECK(same_polygons(s.polygons, r.synthesis.polygons));
    CHECK(s.sequence == r.synthesis.sequence);
    const std::vector<polygon_with_holes> drawn = vp::map_to_curve(s.polygons, line, {.chord_tolerance = H / 1000});
    CHECK(same_polygons(drawn, r.drawn));
    triangle_mesh m = extrude_along_curve(s.polygons, line, {.thickness = 1.0, .chord_tolerance = H / 1000});
    mirror_y(m);
    weld_to_float(m);
    CHECK(m.vertices == r.mesh.vertices);
    CHECK(m.faces == r.mesh.faces);
    const box2 view = framed_view(bounding_box(drawn), 0.02);
    CHECK(view.lo == r.view.lo);
    CHECK(view.hi == r.view.hi);
    const image8 png = preview_image(drawn, view, {.max_side = 1600, .supersample = 4});
    CHECK(png.width == r.preview.width);
    CHECK(png.data == r.preview.data);
}

TEST_CASE("pipeline: a progress callback returning false cancels at every phase", "[vector_pattern][pipeline]") {
    const vp::exemplar raw = fabsynth::test::load_vector_exemplar("greek_key.svg");
    const vp::pattern_where where = vp::along_planar_curve{planar_curve::line(50.0)};
    const vp::pattern_options opt = options(10.0, 1u);
    std::vector<double> fractions;
    std::vector<std::string> stages;
    (void)vp::make_pattern(raw, where, opt, [&](double f, std::string_view stage) {
        fractions.push_back(f);
        stages.emplace_back(stage);
    });
    // scale, synthesis, the DP's layers, stitching, extrusion, mesh, done
    REQUIRE(fractions.size() > 7);
    CHECK(fractions.front() == 0.0);
    CHECK(fractions.back() == 1.0);
    CHECK(std::is_sorted(fractions.begin(), fractions.end()));
    CHECK(stages[1] == "synthesis");
    const auto first_dp = std::find(stages.begin(), stages.end(), "sequence DP");
    REQUIRE(first_dp != stages.end());
    CHECK(std::count(stages.begin(), stages.end(), "sequence DP") >= 3);  // reported inside the DP
    // cancelled at every phase boundary and inside the DP
    std::set<std::size_t> points;
    for (std::size_t i = 0; i < stages.size(); ++i)
        if (i == 0 || stages[i] != stages[i - 1]) points.insert(i + 1);
    points.insert(static_cast<std::size_t>(first_dp - stages.begin()) + 2);
    for (const std::size_t k : points) {
        INFO("cancelled at call " << k << " (" << stages[k - 1] << ")");
        std::size_t calls = 0;
        CHECK_THROWS_AS(vp::make_pattern(raw, where, opt, [&](double, std::string_view) { return ++calls < k; }), cancelled);
        CHECK(calls == k);  // nothing reported after the cancellation
    }
    // a callback that never cancels gives the result of no callback
    const vp::pattern_result quiet = vp::make_pattern(raw, where, opt);
    const vp::pattern_result watched = vp::make_pattern(raw, where, opt, [](double, std::string_view) { return true; });
    CHECK(quiet.mesh.vertices == watched.mesh.vertices);
    CHECK(quiet.preview.data == watched.preview.data);
}

TEST_CASE("pipeline: bad requests are refused before any work", "[vector_pattern][pipeline]") {
    const vp::exemplar raw = fabsynth::test::load_vector_exemplar("greek_key.svg");
    CHECK_THROWS_AS(vp::make_pattern(raw, vp::along_planar_curve{planar_curve::line(50.0)}, options(0.0, 1u)), invalid_input);
    vp::pattern_options loop = options(10.0, 1u);
    loop.synthesis.closed_loop = true;
    CHECK_THROWS_AS(vp::make_pattern(raw, vp::along_planar_curve{planar_curve::line(50.0)}, loop), invalid_input);
    CHECK_THROWS_AS(vp::make_pattern(raw, vp::in_rectangle{40, 30}, loop), invalid_input);
    // a circle tighter than the band
    CHECK_THROWS_AS(vp::make_pattern(raw, vp::along_planar_curve{planar_curve::circle(4.0)}, options(10.0, 1u)), invalid_input);
    // an impossible topology is no_solution, not a wrong pattern
    vp::pattern_options impossible = options(10.0, 1u);
    impossible.synthesis.holes = 3;
    CHECK_THROWS_AS(vp::make_pattern(fabsynth::test::load_vector_exemplar("zigzag.svg"), vp::along_planar_curve{planar_curve::line(100.0)}, impossible),
                    no_solution);
}

TEST_CASE("pipeline: a rectangle", "[vector_pattern][pipeline]") {
    const vp::exemplar raw = fabsynth::test::load_vector_exemplar("greek_key.svg");
    const vp::pattern_options opt = options(10.0, 1u);
    const vp::pattern_result r = vp::make_pattern(raw, vp::in_rectangle{40, 30}, opt);
    CHECK(r.stretch == 1.0);
    const auto topo = fabsynth::test::raster_topology(r.drawn, {-1.0, -1.0}, {41.0, 31.0}, 0.02);
    CHECK(topo.components == 1);
    CHECK(topo.holes == r.synthesis.holes);
    check_slab(r, 1, topo.holes);
    // by hand
    vp::rectangle_options ro;
    ro.width = 40;
    ro.height = 30;
    ro.components = 1u;
    ro.base.band_height = 10.0;
    const vp::synthesis_result s = vp::synthesize_rectangle(vp::scaled(raw, 10.0 / raw.height()), ro);
    CHECK(same_polygons(s.polygons, r.drawn));
}

TEST_CASE("pipeline: along a twisted helix", "[vector_pattern][pipeline]") {
    const vp::exemplar raw = fabsynth::test::load_vector_exemplar("greek_key.svg");
    std::vector<vec3> helix;  // radius 20 mm, rising 20 mm over one turn
    for (int i = 0; i <= 120; ++i) {
        const double a = 2 * std::numbers::pi * i / 120;
        helix.push_back({20 * std::cos(a), 20 * std::sin(a), 20.0 * i / 120});
    }
    const space_curve curve = space_curve::polyline(helix, false, {.twist_degrees = 90});
    vp::pattern_options opt = options(8.0, 1u);
    opt.render.width = opt.render.height = 200;
    const vp::pattern_result r = vp::make_pattern(raw, vp::along_space_curve{curve}, opt);
    CHECK(r.in_space);
    CHECK(r.preview.channels == 3);
    CHECK(r.preview.width == 2 * 200 + opt.render.gap);
    const auto topo = fabsynth::test::raster_topology(r.drawn, {-1.0, -8.0}, {curve.length() + 1.0, 8.0}, 0.02);
    CHECK(topo.components == 1);
    CHECK(topo.holes == r.synthesis.holes);
    check_slab(r, 1, topo.holes);
    // by hand
    vp::synthesis_options so;
    so.length = curve.length();
    so.band_height = 8.0;
    so.components = 1u;
    const vp::synthesis_result s = vp::synthesize_along(vp::scaled(raw, 8.0 / raw.height()), so);
    CHECK(same_polygons(s.polygons, r.drawn));
    triangle_mesh m = extrude_along_space_curve(s.polygons, curve, {.thickness = 1.0, .chord_tolerance = 8.0 / 1000});
    weld_to_float(m);
    CHECK(m.vertices == r.mesh.vertices);
    CHECK(m.faces == r.mesh.faces);
    const image8 png = render_two_sides(m, opt.render_direction, opt.render);
    CHECK(png.data == r.preview.data);
}

TEST_CASE("pipeline: disks carved out of a closed sphere, greek key embossed on it", "[vector_pattern][pipeline][surface]") {
    triangle_mesh sphere = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/icosphere.obj");
    for (vec3& p : sphere.vertices) p *= 30.0;  // a 30 mm sphere
    std::vector<vec3> equator;
    for (int i = 0; i < 6; ++i) equator.push_back({30 * std::cos(i * std::numbers::pi / 3), 30 * std::sin(i * std::numbers::pi / 3), 0});
    const vp::on_surface where{.surface = sphere, .points = equator, .closed = true};

    vp::pattern_options carve = options(12.0, std::nullopt);  // as many disks as fit
    carve.decoration = {.mode = decoration_mode::carve, .shell = 2.0, .cell = 0.6};
    carve.render.width = carve.render.height = 100;
    const vp::pattern_result c = vp::make_pattern(fabsynth::test::load_vector_exemplar("disks.svg"), where, carve);
    CHECK(c.cut_open);
    CHECK(c.closed);
    CHECK(c.edge_crossings > 10);
    const auto topo = fabsynth::test::raster_topology(c.drawn, {0.0, -12.0}, {c.band_length, 12.0}, 0.04, true);
    CHECK(topo.components == c.synthesis.components);
    CHECK(topo.components >= 3);
    CHECK(topo.holes == 0);
    const mesh_topology_info ci = analyze_topology(c.mesh);
    REQUIRE(ci.is_watertight());
    CHECK(ci.components == 1);  // a hollow ball with a window per disk
    CHECK(ci.genus == static_cast<long long>(topo.components) - 1);
    CHECK(c.solid.components == ci.components);
    CHECK(c.solid.genus == ci.genus);

    // the phases by hand, up to the synthesis (the decoration is the expensive part)
    const vp::detail::pipeline::traced_band band = vp::detail::pipeline::traced_surface_band(where, carve);
    CHECK(band.edge_crossings == c.edge_crossings);
    CHECK(band.curve.length() == c.band_length);

    vp::pattern_options emboss = options(12.0, 1u);
    emboss.synthesis.closed_loop = true;
    emboss.decoration = {.mode = decoration_mode::emboss, .shell = 2.0, .height = 1.0, .cell = 0.6};
    emboss.render.width = emboss.render.height = 100;
    const vp::pattern_result e = vp::make_pattern(fabsynth::test::load_vector_exemplar("greek_key.svg"), where, emboss);
    const mesh_topology_info ei = analyze_topology(e.mesh);
    REQUIRE(ei.is_watertight());
    CHECK(ei.components == 1);  // the shell's inside is filled: a solid ball with a relief
    CHECK(ei.genus == 0);
    CHECK(fabsynth::test::raster_topology(e.drawn, {0.0, -12.0}, {e.band_length, 12.0}, 0.04, true).components == 1);
}

// A figure-eight (a self-intersecting outline, repaired into two triangles meeting at their
// tips) or two diamonds meeting at their corners, repeated along x: every extrusion of such a band
// has edges shared by four faces.
vp::exemplar touching_exemplar(bool figure_eight) {
    vp::exemplar_shape s;
    if (figure_eight) {
        s.subpaths = {{{0, 0}, {100, 40}, {100, 0}, {0, 40}}};
    } else {
        s.subpaths = {{{0, 20}, {25, 0}, {50, 20}, {25, 40}}, {{50, 20}, {75, 0}, {100, 20}, {75, 40}}};
    }
    return vp::make_exemplar({s});
}

TEST_CASE("pipeline: an exemplar whose shapes touch is refused before the synthesis, naming it", "[vector_pattern][pipeline]") {
    std::vector<vec3> helix;
    for (int i = 0; i <= 120; ++i) {
        const double a = 2 * std::numbers::pi * i / 120;
        helix.push_back({20 * std::cos(a), 20 * std::sin(a), 20.0 * i / 120});
    }
    const space_curve twisted = space_curve::polyline(helix, false, {.twist_degrees = 90});
    for (const bool eight : {true, false}) {
        INFO((eight ? "figure-eight" : "diamonds"));
        const vp::exemplar ex = touching_exemplar(eight);
        CHECK_THROWS_WITH(vp::require_separate_shapes(ex, "touching.svg"), Catch::Matchers::Contains("touching.svg") && Catch::Matchers::Contains("touch"));
        for (const vp::pattern_where& where : {vp::pattern_where{vp::along_planar_curve{planar_curve::line(200.0)}}, vp::pattern_where{vp::along_space_curve{twisted}},
                                               vp::pattern_where{vp::in_rectangle{60, 40}}}) {
            std::vector<std::string> stages;
            CHECK_THROWS_AS(vp::make_pattern(ex, where, options(8.0, std::nullopt),
                                             [&](double, std::string_view stage) {
                                                 stages.emplace_back(stage);
                                                 return true;
                                             }),
                            invalid_input);
            CHECK(std::find(stages.begin(), stages.end(), "synthesis") == stages.end());  // refused before the work
        }
    }
}

TEST_CASE("pipeline: bands along helices and twists are watertight in float or refused up front", "[vector_pattern][pipeline]") {
    // helices of radius 10 and 25 mm, near the origin and 300 mm from it (coarser floats), with a
    // quarter, a half and three quarters of a turn of twist either way; every result must be
    // watertight as written (float) or an invalid_input (the band folds), never a solver_error
    std::size_t built = 0, refused = 0;
    for (const char* file : {"greek_key.svg", "zigzag.svg", "hearts.svg"}) {
        const vp::exemplar raw = fabsynth::test::load_vector_exemplar(file);
        for (const double radius : {10.0, 25.0})
            for (const double offset : {0.0, 300.0})
                for (const double twist : {-270.0, 90.0, 180.0}) {
                    std::vector<vec3> helix;
                    for (int i = 0; i <= 150; ++i) {
                        const double a = 3 * std::numbers::pi * i / 150;
                        helix.push_back({offset + radius * std::cos(a), radius * std::sin(a), 30.0 * i / 150});
                    }
                    const space_curve curve = space_curve::polyline(helix, false, {.twist_degrees = twist});
                    vp::pattern_options opt = options(radius < 20 ? 14.0 : 8.0, 1u);
                    opt.render.width = opt.render.height = 20;
                    INFO(file << " radius " << radius << " offset " << offset << " twist " << twist);
                    try {
                        const vp::pattern_result r = vp::make_pattern(raw, vp::along_space_curve{curve}, opt);
                        CHECK(analyze_topology(r.mesh).is_watertight());
                        ++built;
                    } catch (const invalid_input&) {
                        ++refused;
                    }
                }
    }
    CHECK(built > refused);
}

TEST_CASE("pipeline: a band whose distant parts meet is refused before the synthesis, with where and what to change", "[vector_pattern][pipeline]") {
    // a helix of radius 10 mm rising 6 mm per turn with a half turn of twist: a band 14 mm high
    // crosses the next turn (space_curve::find_self_contact, tested against an analytic gap in
    // tests/geometry); the same helix rising 20 mm per turn is built, and its solid is watertight
    const vp::exemplar raw = fabsynth::test::load_vector_exemplar("greek_key.svg");
    for (const double pitch : {6.0, 20.0}) {
        std::vector<vec3> helix;
        for (int i = 0; i <= 150; ++i) {
            const double a = 3 * std::numbers::pi * i / 150;
            helix.push_back({10 * std::cos(a), 10 * std::sin(a), 1.5 * pitch * i / 150});
        }
        const space_curve curve = space_curve::polyline(helix, false, {.twist_degrees = 180});
        vp::pattern_options opt = options(14.0, 1u);
        opt.render.width = opt.render.height = 20;
        std::vector<std::string> stages;
        const auto run = [&] {
            return vp::make_pattern(raw, vp::along_space_curve{curve}, opt, [&](double, std::string_view stage) {
                stages.emplace_back(stage);
                return true;
            });
        };
        INFO("pitch " << pitch);
        if (pitch < 14.0) {
            CHECK_THROWS_WITH(run(), Catch::Matchers::Contains("meets itself") && Catch::Matchers::Contains("u = ") &&
                                         Catch::Matchers::Contains("band height 14 mm") && Catch::Matchers::Contains("lower the band height or the twist"));
            CHECK(std::find(stages.begin(), stages.end(), "synthesis") == stages.end());  // refused before the work
            // the extrusion, called directly, refuses the same band
            const vp::synthesis_result s = vp::synthesize_along(vp::scaled(raw, 14.0 / raw.height()), {.length = curve.length(), .band_height = 14.0});
            CHECK_THROWS_WITH(extrude_along_space_curve(s.polygons, curve, {.thickness = 1.0}), Catch::Matchers::Contains("meets itself"));
        } else {
            CHECK(analyze_topology(run().mesh).is_watertight());
        }
    }
}

}  // namespace vector_pattern_pipeline_test
