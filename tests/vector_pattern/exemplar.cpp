// Tests for vector_pattern/exemplar.hpp and geometry/clip.hpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"

using namespace fabsynth;
using fabsynth::vector_pattern::exemplar;

namespace {

struct bundled {
    const char* file;
    std::size_t components, holes;
};
// Counts from data/README.md (vector/ table).
constexpr bundled bundled_exemplars[] = {
    {"lace_scallop.svg", 1, 78}, {"greek_key.svg", 1, 6}, {"pearls.svg", 44, 11}, {"vine.svg", 1, 20},
    {"quatrefoil.svg", 7, 35},   {"hearts.svg", 1, 12},   {"zigzag.svg", 1, 0},      {"disks.svg", 8, 0},
    {"leaves.svg", 10, 0},
};

std::string vector_path(const char* f) { return std::string(FABSYNTH_DATA_DIR) + "/vector/" + f; }

vector_pattern::exemplar_shape square(double x0, double y0, double s, bool ccw = true) {
    ring2 r{{x0, y0}, {x0 + s, y0}, {x0 + s, y0 + s}, {x0, y0 + s}};
    if (!ccw) orient(r, false);
    return {{r}, {true}, fill_rule::nonzero, ""};
}

}  // namespace

TEST_CASE("every bundled vector exemplar loads with the documented components and holes", "[pattern][exemplar]") {
    for (const bundled& b : bundled_exemplars) {
        INFO(b.file);
        const io::svg_document doc = io::read_svg(vector_path(b.file));
        const exemplar ex = vector_pattern::exemplar_from_svg(doc);
        CHECK(ex.components() == b.components);
        CHECK(ex.holes() == b.holes);
        CHECK_FALSE(ex.repaired);
        // Independent area: the files' rings are oriented (outer positive, holes negative), so the
        // shoelace sum over every subpath is the filled area.
        double raw = 0.0;
        for (const auto& s : doc.shapes)
            for (const auto& sp : s.subpaths) raw += signed_area(sp);
        CHECK(ex.area() == Approx(raw).epsilon(1e-12));
        for (const auto& p : ex.polygons) {
            CHECK(signed_area(p.outer) > 0.0);
            for (const auto& h : p.holes) CHECK(signed_area(h) < 0.0);
        }
        CHECK(ex.bounds.lo.x >= -1e-9);
        CHECK(ex.bounds.hi.x <= doc.view_box->width + 1e-9);
    }
}

TEST_CASE("exemplar orientation is recovered from nesting", "[pattern][exemplar]") {
    // Outer clockwise, hole counter-clockwise, in one even-odd shape.
    vector_pattern::exemplar_shape s;
    ring2 outer{{0, 0}, {0, 10}, {10, 10}, {10, 0}}, hole{{2, 2}, {8, 2}, {8, 8}, {2, 8}};
    s.subpaths = {outer, hole};
    s.closed = {true, true};
    s.rule = fill_rule::evenodd;
    const exemplar ex = vector_pattern::make_exemplar({s});
    REQUIRE(ex.components() == 1);
    REQUIRE(ex.holes() == 1);
    CHECK(signed_area(ex.polygons[0].outer) == Approx(100.0));
    CHECK(signed_area(ex.polygons[0].holes[0]) == Approx(-36.0));
    CHECK_FALSE(ex.repaired);
}

TEST_CASE("invalid exemplar geometry is repaired by a union or rejected", "[pattern][exemplar]") {
    SECTION("self-intersecting bow tie") {
        // Two triangles meeting at (5,5), each of area 25.
        vector_pattern::exemplar_shape s{{{{0, 0}, {10, 10}, {10, 0}, {0, 10}}}, {true}, fill_rule::nonzero, "bowtie"};
        const exemplar ex = vector_pattern::make_exemplar({s});
        CHECK(ex.repaired);
        CHECK(ex.components() == 2);
        CHECK(ex.area() == Approx(50.0));
        for (const auto& p : ex.polygons) CHECK(is_simple(p.outer));
        CHECK_THROWS_AS(vector_pattern::make_exemplar({s}, {.repair = false}), invalid_input);
    }
    SECTION("overlapping shapes merge") {
        const exemplar ex = vector_pattern::make_exemplar({square(0, 0, 10), square(5, 5, 10)});
        CHECK(ex.repaired);
        CHECK(ex.components() == 1);
        CHECK(ex.holes() == 0);
        CHECK(ex.area() == Approx(175.0));
        CHECK_THROWS_AS(vector_pattern::make_exemplar({square(0, 0, 10), square(5, 5, 10)}, {.repair = false}), invalid_input);
    }
    SECTION("nonzero rule with a same-orientation inner ring fills it") {
        vector_pattern::exemplar_shape s;
        s.subpaths = {ring2{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, ring2{{2, 2}, {8, 2}, {8, 8}, {2, 8}}};
        s.closed = {true, true};
        s.rule = fill_rule::nonzero;
        const exemplar ex = vector_pattern::make_exemplar({s});
        CHECK(ex.holes() == 0);
        CHECK(ex.area() == Approx(100.0));
        s.rule = fill_rule::evenodd;
        CHECK(vector_pattern::make_exemplar({s}).holes() == 1);
    }
}

TEST_CASE("bad exemplar input gives a clear fabsynth::error", "[pattern][exemplar]") {
    const std::string head = R"(<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">)";
    SECTION("empty SVG") {
        const auto doc = io::parse_svg(head + "</svg>", "empty.svg");
        REQUIRE_THROWS_AS(vector_pattern::exemplar_from_svg(doc), invalid_input);
        REQUIRE_THROWS_WITH(vector_pattern::exemplar_from_svg(doc), Catch::Contains("no filled shape"));
        CHECK_THROWS_AS(vector_pattern::make_exemplar({}), invalid_input);
    }
    SECTION("only a zero-area shape") {
        const auto doc = io::parse_svg(head + R"(<path d="M 0 0 L 5 5 L 10 10 Z"/></svg>)", "flat.svg");
        CHECK_THROWS_WITH(vector_pattern::exemplar_from_svg(doc), Catch::Contains("fill no area"));
    }
    SECTION("open path") {
        const auto doc = io::parse_svg(head + R"(<path id="p1" d="M 0 0 L 10 0 L 10 10"/></svg>)", "open.svg");
        REQUIRE_THROWS_AS(vector_pattern::exemplar_from_svg(doc), invalid_input);
        CHECK_THROWS_WITH(vector_pattern::exemplar_from_svg(doc), Catch::Contains("open path") && Catch::Contains("p1"));
        const exemplar ex = vector_pattern::exemplar_from_svg(doc, {.open_paths = vector_pattern::open_path_policy::close});
        CHECK(ex.area() == Approx(50.0));
    }
    SECTION("NaN coordinates") {
        CHECK_THROWS_AS(io::parse_svg(head + R"(<path d="M 0 0 L NaN 0 L 10 10 Z"/></svg>)", "nan.svg"), fabsynth::error);
        const double nan = std::numeric_limits<double>::quiet_NaN();
        vector_pattern::exemplar_shape s{{{{0, 0}, {nan, 0}, {10, 10}}}, {true}, fill_rule::nonzero, ""};
        CHECK_THROWS_WITH(vector_pattern::make_exemplar({s}), Catch::Contains("non-finite"));
        CHECK_THROWS_AS(polygon_union({ring2{{0, 0}, {nan, 1}, {1, 1}}}, fill_rule::nonzero), invalid_input);
    }
}

TEST_CASE("clip wrapper: booleans against analytic areas", "[geometry][clip]") {
    const std::vector<polygon_with_holes> a{{{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {}}};
    const std::vector<polygon_with_holes> b{{{{5, 5}, {15, 5}, {15, 15}, {5, 15}}, {}}};
    CHECK(area(polygon_union(a, b)) == Approx(175.0));
    CHECK(area(polygon_intersection(a, b)) == Approx(25.0));
    CHECK(area(polygon_difference(a, b)) == Approx(75.0));
    CHECK(area(polygon_xor(a, b)) == Approx(150.0));
    // A strip of a disc-like polygon: a regular 64-gon of radius 10; the strip |x| <= 3 area from
    // the polygon itself is checked by summing two complementary strips back to the whole.
    ring2 circle;
    for (int i = 0; i < 64; ++i) circle.push_back({10 * std::cos(i * 2 * M_PI / 64), 10 * std::sin(i * 2 * M_PI / 64)});
    const std::vector<polygon_with_holes> disc{{circle, {}}};
    const auto left = clip_strip(disc, -20, 0.3), right = clip_strip(disc, 0.3, 20);
    CHECK(area(left) + area(right) == Approx(signed_area(circle)).epsilon(1e-13));
    for (const auto& p : left)
        for (const vec2& v : p.outer) CHECK(v.x <= 0.3 + 1e-12);
    // Vertices representable on the grid come back bit-identical.
    const auto same = polygon_union(to_rings(a), fill_rule::nonzero);
    REQUIRE(same.size() == 1);
    CHECK(area(same) == 100.0);
    CHECK_THROWS_AS(clip_strip(disc, 1.0, 1.0), invalid_input);
}

TEST_CASE("scaled exemplars keep their shape, orientation and topology", "[pattern][exemplar]") {
    const exemplar ex = vector_pattern::exemplar_from_svg(io::read_svg(vector_path("greek_key.svg")));
    for (double s : {0.25, 1.0, 3.0}) {
        INFO("s = " << s);
        const exemplar sc = vector_pattern::scaled(ex, s);
        CHECK(sc.components() == ex.components());
        CHECK(sc.holes() == ex.holes());
        CHECK(sc.repaired == ex.repaired);
        CHECK(sc.height() == Approx(s * ex.height()));
        CHECK(sc.width() == Approx(s * ex.width()));
        CHECK(sc.area() == Approx(s * s * ex.area()));
        // The bounds are the scaled bounds, and still the bounding box of the outer rings.
        box2 b;
        for (const auto& p : sc.polygons) {
            CHECK(signed_area(p.outer) > 0.0);
            for (const ring2& h : p.holes) CHECK(signed_area(h) < 0.0);
            b.extend(bounding_box(p.outer));
        }
        CHECK(b.lo.x == Approx(sc.bounds.lo.x));
        CHECK(b.hi.y == Approx(sc.bounds.hi.y));
    }
    // To a band height, as the curve_patterns driver does.
    CHECK(vector_pattern::scaled(ex, 10.0 / ex.height()).height() == Approx(10.0));
    CHECK_THROWS_AS(vector_pattern::scaled(ex, 0.0), invalid_input);
    CHECK_THROWS_AS(vector_pattern::scaled(ex, -1.0), invalid_input);
    CHECK_THROWS_AS(vector_pattern::scaled(ex, std::nan("")), invalid_input);
}
