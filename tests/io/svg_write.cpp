// Tests for io/svg.hpp: writing and exact round trips.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/io/svg.hpp"
#include "io/io_test_util.hpp"

using fabsynth::vec2;
namespace fio = fabsynth::io;

using io_test::slurp;

namespace {
std::filesystem::path svg_dir() {
    const std::filesystem::path d = io_test::tmp_dir() / "svg";
    std::filesystem::create_directories(d);
    return d;
}
}  // namespace

TEST_CASE("svg: write then read back is exact for hand-made documents", "[io][svg]") {
    fio::svg_document doc;
    doc.width = 210;
    doc.width_unit = "mm";
    doc.height = 0.1;
    doc.height_unit = "in";
    doc.view_box = fio::svg_view_box{-0.1, 1.0 / 3.0, 1e-300, 123456789.123};
    fio::svg_shape a;
    a.id = "tricky <&> \"quoted\" 'id' \xC3\xA9";
    a.fill = "url(#g&1)";
    a.stroke = "#abcdef";
    a.stroke_width = 0.30000000000000004;
    a.rule = fabsynth::fill_rule::evenodd;
    a.subpaths = {{{0.1, 0.2}, {-0.0, 5e-324}, {1.0 / 3.0, -2.0 / 3.0}},
                  {{std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest()}, {1e-310, 7}}};
    a.closed = {true, false};
    fio::svg_shape b;  // default style, no id
    b.subpaths = {{{1, 2}, {3, 4}}};
    b.closed = {false};
    fio::svg_shape c;  // a shape with no geometry survives too
    c.fill = "none";
    c.stroke = "black";
    c.stroke_width = 0;
    doc.shapes = {a, b, c};
    // Random points: 53-bit mantissas exercise the shortest round-trip formatting.
    fio::svg_shape r;
    fabsynth::counter_rng rng(42);
    for (int k = 0; k < 5; ++k) {
        std::vector<vec2> sp;
        for (int i = 0; i < 200; ++i) sp.push_back({rng.uniform(-1e3, 1e3), rng.normal() * std::pow(10.0, rng.uniform(-20, 20))});
        r.subpaths.push_back(sp);
        r.closed.push_back(k % 2 == 0);
    }
    doc.shapes.push_back(r);

    const std::string text = fio::to_svg_string(doc);
    const auto back = fio::parse_svg(text, "roundtrip.svg", {.max_coordinate = std::numeric_limits<double>::infinity()});
    CHECK(back == doc);
    // Through a file, too; writing the read-back document gives identical bytes.
    const auto path = svg_dir() / "roundtrip.svg";
    fio::write_svg(path, doc);
    const auto back2 = fio::read_svg(path, {.max_coordinate = std::numeric_limits<double>::infinity()});
    CHECK(back2 == doc);
    CHECK(slurp(path) == text);
    for (const auto& e : std::filesystem::directory_iterator(svg_dir()))  // no temporary left behind
        CHECK(e.path().filename().string().find("tmp") == std::string::npos);
    // Signed zero survives (operator== would not notice).
    CHECK(std::signbit(back.shapes[0].subpaths[0][1].x));
}

TEST_CASE("svg: bundled data round-trips exactly", "[io][svg]") {
    for (const char* dir : {"vector", "filigree"}) {
        for (const auto& e : std::filesystem::directory_iterator(std::string(FABSYNTH_DATA_DIR) + "/" + dir)) {
            if (e.path().extension() != ".svg") continue;
            INFO(e.path());
            const auto doc = fio::read_svg(e.path());
            const auto back = fio::parse_svg(fio::to_svg_string(doc), "back.svg");
            CHECK(back == doc);
        }
    }
    // A curved document: the flattened polylines round-trip exactly as well.
    const auto curved = fio::parse_svg(
        R"svg(<svg xmlns="http://www.w3.org/2000/svg"><g transform="rotate(17) scale(1.3)"><circle r="3"/>)svg"
        R"svg(<path d="M0 0 C1 2 3 4 5 0 A 2 3 10 1 0 9 9 Q 1 1 0 5 z"/></g></svg>)svg",
        "curved.svg");
    CHECK(fio::parse_svg(fio::to_svg_string(curved), "back.svg") == curved);
}

TEST_CASE("svg: writer rejects documents it cannot represent", "[io][svg]") {
    fio::svg_document doc;
    fio::svg_shape s;
    s.subpaths = {{{0, 0}, {std::nan(""), 1}}};
    s.closed = {false};
    doc.shapes = {s};
    CHECK_THROWS_AS(fio::to_svg_string(doc), fabsynth::invalid_input);
    doc.shapes[0].subpaths[0][1].x = std::numeric_limits<double>::infinity();
    CHECK_THROWS_AS(fio::to_svg_string(doc), fabsynth::invalid_input);
    doc.shapes[0].subpaths[0][1].x = 1;
    doc.shapes[0].closed.clear();
    CHECK_THROWS_WITH(fio::to_svg_string(doc), Catch::Contains("closed.size()"));
    doc.shapes[0].closed = {false};
    doc.shapes[0].id = std::string("a\0b", 3);
    CHECK_THROWS_WITH(fio::to_svg_string(doc), Catch::Contains("control character"));
    doc.shapes[0].id = "ok";
    doc.width = -1;
    CHECK_THROWS_AS(fio::to_svg_string(doc), fabsynth::invalid_input);
    doc.width = 1;
    doc.width_unit = "furlong";
    CHECK_THROWS_AS(fio::to_svg_string(doc), fabsynth::invalid_input);
    doc.width_unit = "";
    CHECK_NOTHROW(fio::to_svg_string(doc));
    CHECK_THROWS_AS(fio::write_svg(svg_dir() / "no_such_dir" / "x.svg", doc), fabsynth::io_error);
}

TEST_CASE("svg: shapes built from polygons and polylines", "[io][svg]") {
    // Read a band, regroup its rings geometrically, write them as one shape: same rings, and the
    // filled area is unchanged.
    const auto doc = fio::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/quatrefoil.svg");
    std::vector<fabsynth::ring2> rings;
    double area = 0;
    for (const auto& s : doc.shapes)
        for (const auto& r : s.rings()) rings.push_back(r), area += fabsynth::signed_area(r);
    const auto polys = fabsynth::group_rings(rings);
    fio::svg_document out;
    out.view_box = doc.view_box;
    out.shapes = {fio::shape_from_polygons(polys)};
    const auto back = fio::parse_svg(fio::to_svg_string(out), "polys.svg");
    REQUIRE(back.shapes.size() == 1);
    CHECK(back.shapes[0].subpaths.size() == rings.size());
    CHECK(back.shapes[0].rule == fabsynth::fill_rule::evenodd);
    double area2 = 0;
    for (const auto& r : back.shapes[0].subpaths) area2 += fabsynth::signed_area(r);
    CHECK(area2 == Approx(area).epsilon(1e-12));
    CHECK(back == out);

    const auto lines = fio::shape_from_polylines({{{0, 0}, {1, 1}, {2, 0}}}, 0.5);
    CHECK(lines.stroked());
    CHECK(!lines.filled());
    CHECK(lines.closed == std::vector<bool>{false});
    CHECK_THROWS_AS(fio::shape_from_polylines({}, -1), fabsynth::invalid_input);
}

TEST_CASE("svg: a coordinate beyond max_coordinate is refused at its element's line, in few digits", "[io][svg]") {
    const std::string text = "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<rect width=\"1\" height=\"1\"/>\n<path d=\"M 0 0 L 1e308 0 L 1 1 Z\"/>\n</svg>\n";
    CHECK_THROWS_WITH(fio::parse_svg(text, "far.svg"), Catch::StartsWith("fabsynth: far.svg:3:") && Catch::Contains("(1e+308, 0) out of range"));
    // a transform can carry a small coordinate out of range too
    const std::string scaled = "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<g transform=\"scale(1e300)\">\n<rect width=\"1\" height=\"1\"/>\n</g>\n</svg>\n";
    CHECK_THROWS_WITH(fio::parse_svg(scaled, "scaled.svg"), Catch::Contains("scaled.svg:3:") && Catch::Contains("out of range"));
    CHECK(fio::parse_svg(text, "far.svg", {.max_coordinate = std::numeric_limits<double>::infinity()}).shapes.size() == 2);
}
