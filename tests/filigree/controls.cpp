// The designer's controls of the filigree pipeline (issue: "a designer's controls"): materials by
// name, where the flat piece is held (a side, a box, a hanging eyelet) and which way its weight
// pulls (checked against the axial stress of a hanging bar, sigma(y) = rho g (L - y)), the bound on
// phase 2's thickness, the orientation picture, and the two figures of §5 (Fig. 10, Fig. 21).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <functional>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fabsynth/filigree/field.hpp"
#include "fabsynth/filigree/figures.hpp"
#include "fabsynth/filigree/reinforcement.hpp"
#include "fabsynth/filigree/structure.hpp"
#include "fabsynth/filigree/synthesis.hpp"
#include "fabsynth/io/svg.hpp"

namespace controls_test {

using namespace fabsynth;

inline polygon_with_holes box_outline(double x0, double y0, double x1, double y1) {
    polygon_with_holes p;
    p.outer = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    return p;
}

// An analysis whose weak fraction is 0.5 below `strong_at` mm and 0 from there on (phase 2 alone).
inline filigree::structural_report fake_report(double t, double strong_at) {
    filigree::structural_report r;
    r.thickness = t;
    r.yield = 40;
    r.node_von_mises = {t < strong_at ? 50.0 : 10.0, 10.0};
    r.node_positions = {{0, 0}, {1, 0}};
    if (t < strong_at) r.weak_nodes = {0};
    r.weak_fraction = t < strong_at ? 0.5 : 0.0;
    r.max_von_mises = r.node_von_mises[0];
    r.histogram = {0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    return r;
}

}  // namespace controls_test

TEST_CASE("filigree controls: materials by name, with their yield stresses", "[filigree][structure]") {
    using namespace fabsynth::filigree;
    for (const material_preset p : {material_preset::abs, material_preset::pla, material_preset::petg, material_preset::pa12,
                                    material_preset::steel_316l, material_preset::ti64}) {
        CHECK(parse_material(material_name(p)) == p);
        const structure_material m = preset_material(p);
        CHECK_NOTHROW(m.elastic.validate());
        CHECK(m.yield_mpa > 0);
    }
    // the paper's ABS (§8.3.1: 40 MPa), and the metals far stiffer and stronger than the plastics
    CHECK(preset_material(material_preset::abs).yield_mpa == 40.0);
    CHECK(preset_material(material_preset::steel_316l).elastic.E == 193000.0);
    CHECK(preset_material(material_preset::steel_316l).yield_mpa == 170.0);
    CHECK(preset_material(material_preset::ti64).yield_mpa == 880.0);
    CHECK(preset_material(material_preset::pa12).elastic.density == 0.93e-9);
    CHECK_THROWS_WITH(parse_material("gold"), Catch::Contains("gold") && Catch::Contains("316l"));
}

TEST_CASE("filigree controls: a bar hanging upright carries its weight as axial stress rho g (L - y)", "[filigree][structure]") {
    using namespace controls_test;
    // 10 x 100 mm bar clamped along its top edge (y = 0, as drawn), gravity toward +y (the drawing's
    // bottom), no pressure; nu = 0 so the clamp adds no lateral restraint: sigma_yy(y) = rho g (L - y).
    const double b = 10, L = 100, rho = 1e-6, g = 9.81;
    const filigree::fem_triangulation tri = filigree::make_fem_triangulation({box_outline(0, 0, b, L)}, 2.0);
    filigree::structure_options opt;
    opt.material = {{2000.0, 0.0, rho}, 40.0};
    opt.pressure_pa = 0;
    opt.gravity_down = {0.0, 1.0, 0.0};
    opt.support_fraction = 0;  // the top edge only
    const filigree::structural_report rep = filigree::analyse_structure(tri, 1.0, opt);
    double mid = 0;
    int n = 0;
    for (std::size_t i = 0; i < rep.node_positions.size(); ++i)
        if (std::abs(rep.node_positions[i].y - L / 2) < 1e-9) mid += rep.node_von_mises[i], ++n;
    REQUIRE(n >= 2);
    mid /= n;
    const double oracle = rho * g * 1e3 * (L / 2);  // t/mm^3 x mm/s^2 x mm = MPa
    INFO("mid-height stress " << mid << " MPa, oracle " << oracle);
    CHECK(std::abs(mid - oracle) / oracle < 0.02);
    CHECK(rep.max_deflection < 1e-9);                                        // nothing out of the plane
    CHECK(rep.support_reaction.y == Approx(-rho * g * 1e3 * b * L).epsilon(1e-6));  // the supports hold the weight up
    CHECK(std::abs(rep.support_reaction.z) < 1e-9);
}

TEST_CASE("filigree controls: supports on a chosen side, in a box or at a hanging eyelet", "[filigree][structure]") {
    using namespace controls_test;
    const filigree::fem_triangulation tri = filigree::make_fem_triangulation({box_outline(0, 0, 40, 20)}, 2.0);
    auto nodes_where = [&](auto pred) {
        std::size_t k = 0;
        for (const vec2& v : tri.mesh.vertices) k += pred(v) ? 1 : 0;
        return k;
    };
    filigree::structure_options so;
    for (const auto& [side, pred] : std::vector<std::pair<filigree::support_side, std::function<bool(vec2)>>>{
             {filigree::support_side::top, [](vec2 p) { return p.y <= 1.0 + 1e-6; }},
             {filigree::support_side::bottom, [](vec2 p) { return p.y >= 19.0 - 1e-6; }},
             {filigree::support_side::left, [](vec2 p) { return p.x <= 2.0 + 1e-6; }},
             {filigree::support_side::right, [](vec2 p) { return p.x >= 38.0 - 1e-6; }}}) {
        so.side = side;
        const auto ids = filigree::support_nodes(tri, so);
        CHECK(ids.size() == nodes_where(pred));
        for (const std::uint32_t i : ids) CHECK(pred(tri.mesh.vertices[i]));
    }
    // the planar form's options: a box, an eyelet (radius defaults to the median strip width), upright
    filigree::reinforcement_options ro;
    ro.support.box = box2(vec2(10, 5), vec2(20, 15));
    const auto in_box = filigree::support_nodes(tri, filigree::detail::reinforce::planar_structure_options(ro, 1.0));
    CHECK(in_box.size() == nodes_where([](vec2 p) { return p.x >= 10 && p.x <= 20 && p.y >= 5 && p.y <= 15; }));
    ro.support.box.reset();
    ro.support.hang = vec2(20, 0);
    const filigree::structure_options hung = filigree::detail::reinforce::planar_structure_options(ro, 3.0);
    CHECK(hung.gravity_down == vec3(0, 0, -1));  // hanging point alone: still lying flat
    CHECK(filigree::support_nodes(tri, hung).size() == nodes_where([](vec2 p) { return glm::distance(p, vec2(20, 0)) <= 3.0; }));
    ro.support.upright = true;
    CHECK(filigree::detail::reinforce::planar_structure_options(ro, 3.0).gravity_down == vec3(0, 1, 0));
    // refused by name
    ro.support.box = box2(vec2(0, 0), vec2(1, 1));
    CHECK_THROWS_WITH(filigree::detail::reinforce::planar_structure_options(ro, 1.0), Catch::Contains("box and hang"));
    ro.support.box.reset();
    ro.support.hang_radius = -1;
    CHECK_THROWS_WITH(filigree::detail::reinforce::planar_structure_options(ro, 1.0), Catch::Contains("hang_radius"));
    ro.support.hang_radius = 0;
    ro.support.hang = vec2(1e3, 1e3);  // no node within reach: nothing holds the piece
    CHECK_THROWS_WITH(filigree::support_nodes(tri, filigree::detail::reinforce::planar_structure_options(ro, 1.0)),
                      Catch::Contains("no node lies in the support region"));
}

TEST_CASE("filigree controls: max_thickness stops phase 2 and reports the weak nodes instead of failing", "[filigree][structure]") {
    using namespace controls_test;
    auto analyse = [](double t) { return fake_report(t, 1.5); };
    // unbounded: 1.0 x 1.1^k >= 1.5 first at k = 5 (1.61)
    const filigree::thickening_result free = filigree::thicken_with(analyse, 1.0, {});
    CHECK(free.converged);
    CHECK(free.iterations == 5);
    // bounded at 1.4 mm: the last step <= 1.4 is 1.1^3 = 1.331, still weak
    const filigree::thickening_result capped = filigree::thicken_with(analyse, 1.0, {.max_thickness = 1.4});
    CHECK_FALSE(capped.converged);
    CHECK(capped.thickness == Approx(1.331).epsilon(1e-12));
    CHECK(capped.thickness_history.size() == 4);
    CHECK_THROWS_WITH(filigree::thicken_with(analyse, 2.0, {.max_thickness = 1.4}), Catch::Contains("exceeds the maximum thickness"));
    // through the reinforcement loop: solver_error without a bound, a weak record with one
    struct nothing {};
    auto run = [&](double max_t, double strong_at) {
        auto an = [strong_at](double t) { return fake_report(t, strong_at); };
        filigree::structural_record r;
        r.thickness = 1.0;
        filigree::reinforcement_options ro;
        ro.max_thickness = max_t;
        nothing layout;
        filigree::reinforcement_loop(
            layout, r, ro, [&](const nothing&, double t) { return an(t); },
            [](const nothing&, const filigree::structural_report&, int, std::size_t&, const progress_span&) { return std::optional<nothing>(); },
            [&](const nothing&, double t, const progress_span& p) { return filigree::thicken_with(an, t, {.max_thickness = ro.max_thickness}, p); });
        return r;
    };
    const filigree::structural_record weak = run(1.4, 1.5);
    CHECK_FALSE(weak.strong);
    CHECK(weak.weak_nodes_final == 1);
    CHECK(weak.thickness == Approx(1.331).epsilon(1e-12));
    const filigree::structural_record strong = run(2.0, 1.5);
    CHECK(strong.strong);
    CHECK(strong.weak_nodes_final == 0);
    CHECK(strong.thickness == Approx(1.61051).epsilon(1e-12));
    CHECK_THROWS_AS(run(0.0, 100.0), fabsynth::solver_error);  // 30 steps reach 17.4 mm, never strong, no bound: an error
    CHECK_FALSE(run(20.0, 100.0).strong);                       // with a bound: a record that says so
}

TEST_CASE("filigree controls: an orientation picture turns the elements; combined with a scale picture", "[filigree][field]") {
    using namespace fabsynth::filigree;
    fabsynth::image8 g(2, 1, 1);
    g.at(0, 0) = 0, g.at(1, 0) = 255;
    const fabsynth::box2 extent(fabsynth::vec2(0, 0), fabsynth::vec2(2, 1));
    const image_rotation_field rot(g, extent, 0.0, 1.0, 1.5);
    CHECK(rot({0.5, 0.5}).rotation == Approx(0.0).margin(1e-12));  // pixel centres
    CHECK(rot({1.5, 0.5}).rotation == Approx(1.0).epsilon(1e-12));
    CHECK(rot({1.0, 0.5}).rotation == Approx(0.5).epsilon(1e-12));  // bilinear between them
    CHECK(rot({-5.0, 0.5}).rotation == Approx(0.0).margin(1e-12));  // clamped outside
    CHECK(rot({1.0, 0.5}).scale == 1.5);
    const image_field size(g, extent, 0.5, 2.0, 0.3);
    const combined_field<image_rotation_field, image_field> both{rot, size};
    CHECK(both({1.5, 0.5}).rotation == Approx(1.0).epsilon(1e-12));
    CHECK(both({1.5, 0.5}).scale == Approx(2.0).epsilon(1e-12));
    CHECK_THROWS_WITH(image_rotation_field(g, extent, 0.0, std::nan(""), 1.0), Catch::Contains("rotations must be finite"));
    CHECK_THROWS_WITH(image_rotation_field(fabsynth::image8(2, 1, 3), extent, 0.0, 1.0), Catch::Contains("grayscale"));
}

TEST_CASE("filigree controls: the stress map colours each node by its stress over the yield (Fig. 10), the histogram plots both (Fig. 21)",
          "[filigree][structure]") {
    using namespace controls_test;
    const filigree::fem_triangulation tri = filigree::make_fem_triangulation({box_outline(0, 0, 40, 20)}, 4.0);
    filigree::structural_report rep;
    rep.yield = 40;
    rep.thickness = 1.0;
    rep.node_von_mises.assign(tri.mesh.vertices.size(), 0.0);
    const box2 view(vec2(-10, -10), vec2(50, 30));  // 60 x 40 mm over 600 x 400 pixels: 10 px / mm
    auto pixel = [](const image8& im, int x, int y) { return std::array<int, 3>{im.at(x, y, 0), im.at(x, y, 1), im.at(x, y, 2)}; };
    image8 unstressed = filigree::stress_map_image(tri, rep, view, 600);
    CHECK(unstressed.channels == 3);
    CHECK(pixel(unstressed, 300, 200) == std::array<int, 3>{40, 60, 200});  // inside: blue (0 MPa)
    CHECK(pixel(unstressed, 20, 20) == std::array<int, 3>{255, 255, 255});   // outside the piece: white
    std::fill(rep.node_von_mises.begin(), rep.node_von_mises.end(), 80.0);  // twice the yield everywhere: weak
    CHECK(pixel(filigree::stress_map_image(tri, rep, view, 600), 300, 200) == std::array<int, 3>{200, 0, 200});
    std::fill(rep.node_von_mises.begin(), rep.node_von_mises.end(), 40.0);  // at the yield: red, not weak
    CHECK(pixel(filigree::stress_map_image(tri, rep, view, 600), 300, 200) == std::array<int, 3>{220, 30, 20});
    rep.node_von_mises.pop_back();
    CHECK_THROWS_WITH(filigree::stress_map_image(tri, rep, view, 600), Catch::Contains("nodal stresses"));

    filigree::structural_record r;
    CHECK_THROWS_WITH(filigree::stress_histogram_plot(r), Catch::Contains("no structural analysis"));
    r.analysed = true;
    r.yield_mpa = 40;
    r.histogram_before = {100, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};  // 17 bins of 5 MPa: the last open
    r.histogram_after = r.histogram_before;
    r.histogram_after[0] = 50, r.histogram_after[1] = 50;  // percentages of the nodes: 100% before, 50% after
    const image8 plot = filigree::stress_histogram_plot(r);
    REQUIRE(plot.width == 1000);
    // the first bin's bars: before (grey) 100% of the nodes on an axis to 100%, after (orange) 50%
    auto column_height = [&](std::array<int, 3> colour) {
        int best = 0;
        for (int x = 0; x < plot.width; ++x) {
            int h = 0;
            for (int y = 0; y < plot.height; ++y) h += pixel(plot, x, y) == colour ? 1 : 0;
            best = std::max(best, h);
        }
        return best;
    };
    const int grey = column_height({150, 150, 150}), orange = column_height({255, 127, 14});
    INFO("bar heights " << grey << " " << orange);
    CHECK(grey == Approx(440.0).margin(2));  // the data box is 440 px tall
    CHECK(orange == Approx(220.0).margin(2));
}

TEST_CASE("filigree controls: element sets per region hold through initialization, placement and boosting", "[filigree][synthesis]") {
    using namespace fabsynth;
    using namespace fabsynth::filigree;
    const std::string data = FABSYNTH_DATA_DIR;
    const std::vector<element> classes{element_from_svg(io::read_svg(data + "/filigree/spiral.svg", 0.01), {.size_mm = 16, .width_mm = 0.8}),
                                       element_from_svg(io::read_svg(data + "/filigree/leaf.svg", 0.01), {.size_mm = 16, .width_mm = 0.8})};
    const std::vector<double> weights{1.0, 1.0};
    synthesis_options so;
    so.seed = 3;
    so.max_rounds = 3;
    planar_domain domain = planar_domain::rectangle(90, 50);
    // without regions both classes spread over both halves
    auto sides = [](const synthesis_result& r, std::uint32_t cls) {
        std::array<std::size_t, 2> n{};
        for (const instance& in : r.instances)
            if (in.cls == cls) ++n[in.position.x < 45 ? 0 : 1];
        return n;
    };
    const synthesis_result mixed = synthesize_pattern(classes, weights, domain, constant_field{}, so);
    CHECK(sides(mixed, 0)[1] > 0);
    CHECK(sides(mixed, 1)[0] > 0);
    // spirals on the left half, leaves on the right: every instance stays on its side
    domain.class_allowed = [](std::uint32_t cls, vec2 p) { return cls == 0 ? p.x < 45 : p.x >= 45; };
    const synthesis_result split = synthesize_pattern(classes, weights, domain, constant_field{}, so);
    INFO("spirals left/right " << sides(split, 0)[0] << "/" << sides(split, 0)[1] << ", leaves " << sides(split, 1)[0] << "/" << sides(split, 1)[1]
                               << "; boosted " << split.boosted);
    CHECK(sides(split, 0)[0] >= 5);
    CHECK(sides(split, 0)[1] == 0);
    CHECK(sides(split, 1)[1] >= 5);
    CHECK(sides(split, 1)[0] == 0);
    double moved = 0;
    for (const round_record& r : split.per_round) moved += r.translation_mm;
    CHECK(moved > 1.0);  // the instances did move (mm summed over the rounds), and kept to their sides
}

TEST_CASE("filigree controls: a label picture gives each class its regions", "[filigree][synthesis]") {
    using namespace fabsynth;
    image8 g(2, 1, 1);
    g.at(0, 0) = 0, g.at(1, 0) = 255;
    const box2 extent(vec2(0, 0), vec2(20, 10));  // 10 mm per pixel
    const auto allowed = filigree::label_regions(g, extent, {{0}, {}, {255, 0}});
    CHECK(allowed(0, {5, 5}));
    CHECK_FALSE(allowed(0, {15, 5}));
    CHECK(allowed(1, {15, 5}));  // no labels: everywhere
    CHECK(allowed(2, {5, 5}));
    CHECK(allowed(2, {15, 5}));
    CHECK_FALSE(allowed(0, {50, 5}));  // clamped: the right column
    CHECK_FALSE(allowed(3, {5, 5}));   // no such class
    CHECK_THROWS_WITH(filigree::label_regions(g, extent, {{7}}, "L.png"), Catch::Contains("L.png") && Catch::Contains("grey level 7"));
    CHECK_THROWS_WITH(filigree::label_regions(image8(2, 1, 3), extent, {{0}}), Catch::Contains("grayscale"));
}
