// Tests for io/svg.hpp: reading (data files, grammar, transforms, flattening accuracy, styles).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/io/svg.hpp"

using fabsynth::vec2;
namespace fio = fabsynth::io;

namespace {

std::string wrap(const std::string& body) {
    return "<svg xmlns=\"http://www.w3.org/2000/svg\">" + body + "</svg>";
}
fio::svg_document parse(const std::string& body, double tol = 0.01) { return fio::parse_svg(wrap(body), "t.svg", tol); }

// Distance from p to segment [a, b].
double seg_dist(vec2 p, vec2 a, vec2 b) {
    const vec2 ab = b - a;
    const double l2 = glm::dot(ab, ab);
    const double t = l2 > 0 ? std::clamp(glm::dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}
double polyline_dist(vec2 p, const std::vector<vec2>& pl, bool closed) {
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < pl.size(); ++i) d = std::min(d, seg_dist(p, pl[i], pl[i + 1]));
    if (closed && pl.size() > 1) d = std::min(d, seg_dist(p, pl.back(), pl.front()));
    return d;
}

}  // namespace

TEST_CASE("svg: bundled vector and filigree files parse with the documented counts", "[io][svg]") {
    struct row {
        const char* file;
        std::size_t components, holes, vertices;
        double w, h;
    };
    // data/README.md, tables vector/ and filigree/ (holes = subpaths after the first).
    const row vector_rows[] = {
        {"lace_scallop.svg", 1, 78, 3464, 480, 100}, {"greek_key.svg", 1, 6, 100, 480, 90},
        {"pearls.svg", 44, 11, 2244, 484, 60},       {"vine.svg", 1, 20, 1989, 480, 100},
        {"quatrefoil.svg", 7, 35, 1922, 480, 80},    {"hearts.svg", 1, 12, 1377, 480, 100},
        {"zigzag.svg", 1, 0, 50, 480, 60},
    };
    for (const row& r : vector_rows) {
        INFO(r.file);
        const auto doc = fio::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/" + r.file);
        std::size_t holes = 0, verts = 0;
        for (const auto& s : doc.shapes) {
            REQUIRE(!s.subpaths.empty());
            holes += s.subpaths.size() - 1;
            CHECK(s.rule == fabsynth::fill_rule::evenodd);
            CHECK(s.fill == "#000000");
            CHECK(!s.stroked());
            for (std::size_t i = 0; i < s.subpaths.size(); ++i) {
                CHECK(s.closed[i]);
                verts += s.subpaths[i].size();
                // README: outer rings positive shoelace area (SVG coordinates), holes negative.
                const double a = fabsynth::signed_area(s.subpaths[i]);
                CHECK((i == 0 ? a > 0 : a < 0));
            }
        }
        CHECK(doc.shapes.size() == r.components);
        CHECK(holes == r.holes);
        CHECK(verts == r.vertices);
        REQUIRE(doc.view_box);
        CHECK(doc.view_box->width == r.w);
        CHECK(doc.view_box->height == r.h);
        CHECK(doc.width == r.w);
        CHECK(doc.width_unit.empty());
    }
    struct frow {
        const char* file;
        std::vector<std::size_t> points;
        double w, h;
    };
    const frow filigree_rows[] = {
        {"spiral.svg", {241}, 35.62, 33.04},           {"s_curl.svg", {301}, 49.069, 19.995},
        {"c_scroll.svg", {301}, 47.611, 27.533},       {"heart_curls.svg", {251, 251}, 45.716, 41.013},
        {"leaf.svg", {61, 61, 55, 81}, 27.3, 61.337},
    };
    for (const frow& r : filigree_rows) {
        INFO(r.file);
        const auto doc = fio::read_svg(std::string(FABSYNTH_DATA_DIR) + "/filigree/" + r.file);
        REQUIRE(doc.shapes.size() == r.points.size());
        for (std::size_t i = 0; i < r.points.size(); ++i) {
            const auto& s = doc.shapes[i];
            REQUIRE(s.subpaths.size() == 1);
            CHECK(!s.closed[0]);
            CHECK(s.subpaths[0].size() == r.points[i]);
            CHECK(!s.filled());
            CHECK(s.stroked());
            CHECK(s.stroke_width == 1.0);
        }
        REQUIRE(doc.view_box);
        CHECK(doc.view_box->width == r.w);
        CHECK(doc.view_box->height == r.h);
        // README: the viewBox is the bounding box plus a margin of 2 units.
        const auto b = doc.bounds();
        CHECK(b.lo.x - doc.view_box->min_x == Approx(2.0).margin(1e-3));
        CHECK(doc.view_box->min_x + doc.view_box->width - b.hi.x == Approx(2.0).margin(1e-3));
    }
}

TEST_CASE("svg: number grammar and path-data separators", "[io][svg]") {
    // "1.5.5" is 1.5 then .5; "-.5"; exponents; "+" signs; no separators before '-'.
    auto d = parse(R"svg(<path d="M1.5.5L-.5-1e-3l+2E1,0.25e+1Z"/>)svg");
    REQUIRE(d.shapes.size() == 1);
    const auto& p = d.shapes[0].subpaths[0];
    REQUIRE(p.size() == 3);
    CHECK(p[0] == vec2(1.5, 0.5));
    CHECK(p[1] == vec2(-0.5, -1e-3));
    CHECK(p[2] == vec2(-0.5 + 20.0, -1e-3 + 2.5));
    CHECK(d.shapes[0].closed[0]);
    // Arc flags written without separators: "a1 1 0 00 1 1" == "a 1 1 0 0 0 1 1".
    auto a = parse(R"svg(<path d="M0 0a1 1 0 00 1 1"/>)svg");
    auto b = parse(R"svg(<path d="M 0,0 a 1,1 0 0,0 1,1"/>)svg");
    CHECK(a.shapes == b.shapes);
    CHECK(a.shapes[0].subpaths[0].back() == vec2(1, 1));
    // Implicit repetition: M pairs become L; tiny values underflow to 0 instead of failing.
    auto c = parse(R"svg(<path d="M0 0 1 0 1 1e-400"/>)svg");
    REQUIRE(c.shapes[0].subpaths[0].size() == 3);
    CHECK(c.shapes[0].subpaths[0][2] == vec2(1, 0));
}

TEST_CASE("svg: relative and absolute path forms give identical geometry", "[io][svg]") {
    // All numbers dyadic, so relative sums are exact and the comparison can be exact.
    const std::string abs_d =
        "M 10 10 L 20 10 H 30 V 20 C 30 30 20 30 20 20 S 10 10 10 20 Q 5 25 0 20 T 0 10 "
        "A 5 2.5 30 0 1 5 5 A 4 4 0 1 0 10 10 Z M 40 40 L 50 40 L 50 50 Z L 60 60";
    const std::string rel_d =
        "m 10 10 l 10 0 h 10 v 10 c 0 10 -10 10 -10 0 s -10 -10 -10 0 q -5 5 -10 0 t 0 -10 "
        "a 5 2.5 30 0 1 5 -5 a 4 4 0 1 0 5 5 z m 30 30 l 10 0 l 0 10 z l 20 20";
    const auto a = parse("<path d=\"" + abs_d + "\"/>");
    const auto r = parse("<path d=\"" + rel_d + "\"/>");
    REQUIRE(a.shapes.size() == 1);
    CHECK(a.shapes[0].subpaths.size() == 3);  // the L after the last Z starts a new subpath at (40, 40)
    CHECK(a.shapes[0].closed == std::vector<bool>{true, true, false});
    CHECK(a.shapes[0].subpaths[2] == std::vector<vec2>{{40, 40}, {60, 60}});
    CHECK(a.shapes == r.shapes);
}

TEST_CASE("svg: transforms compose like hand-computed matrices", "[io][svg]") {
    const double c30 = std::cos(std::numbers::pi / 6), s30 = std::sin(std::numbers::pi / 6);
    // M = translate(10 20) * scale(2 3) * rotate(30) * matrix(1 2 3 4 5 6) * skewX(45); p' = M p.
    auto apply = [&](vec2 p) {
        p = {p.x + 1.0 * p.y, p.y};                                   // skewX(45): tan 45 = 1
        p = {1 * p.x + 3 * p.y + 5, 2 * p.x + 4 * p.y + 6};           // matrix(1 2 3 4 5 6)
        p = {c30 * p.x - s30 * p.y, s30 * p.x + c30 * p.y};           // rotate(30)
        p = {2 * p.x, 3 * p.y};                                       // scale(2 3)
        return vec2(p.x + 10, p.y + 20);                               // translate(10 20)
    };
    const auto d = parse(R"svg(<g transform="translate(10 20)"><g transform=" scale(2,3)rotate(30) ">)svg"
                         R"svg(<path transform="matrix(1,2,3,4,5,6), skewX(45)" d="M1 2 L-3 4.5"/></g></g>)svg");
    const auto& p = d.shapes.at(0).subpaths.at(0);
    CHECK(p[0].x == Approx(apply({1, 2}).x).margin(1e-12));
    CHECK(p[0].y == Approx(apply({1, 2}).y).margin(1e-12));
    CHECK(p[1].x == Approx(apply({-3, 4.5}).x).margin(1e-12));
    CHECK(p[1].y == Approx(apply({-3, 4.5}).y).margin(1e-12));

    // rotate(90 10 0): (20, 0) -> (10, 10); skewY(45): (2, 3) -> (2, 5); translate(7) = (7, 0).
    const auto e = parse(R"svg(<path transform="rotate(90 10 0)" d="M20 0"/><line transform="skewY(45)" x1="2" y1="3"/>)svg"
                         R"svg(<line transform="translate(7)" x2="1"/>)svg");
    CHECK(e.shapes[0].subpaths.empty());  // a lone moveto draws nothing
    const auto f = parse(R"svg(<polyline transform="rotate(90 10 0)" points="20 0 10 0"/><line transform="skewY(45)" x1="2" y1="3"/>)svg"
                         R"svg(<line transform="translate(7)" x2="1"/>)svg");
    CHECK(f.shapes[0].subpaths[0][0].x == Approx(10).margin(1e-12));
    CHECK(f.shapes[0].subpaths[0][0].y == Approx(10).margin(1e-12));
    CHECK(f.shapes[0].subpaths[0][1].x == Approx(10).margin(1e-12));
    CHECK(f.shapes[0].subpaths[0][1].y == Approx(0).margin(1e-12));
    CHECK(f.shapes[1].subpaths[0][0].x == Approx(2));
    CHECK(f.shapes[1].subpaths[0][0].y == Approx(5));
    CHECK(f.shapes[2].subpaths[0] == std::vector<vec2>{{7, 0}, {8, 0}});
    // Nested <svg x y> translates its content.
    const auto g = parse(R"svg(<svg x="5" y="6"><line x1="1" y1="1" x2="2" y2="2"/></svg>)svg");
    CHECK(g.shapes[0].subpaths[0] == std::vector<vec2>{{6, 7}, {7, 8}});
}

TEST_CASE("svg: circles and ellipses are flattened within tolerance of the analytic curve", "[io][svg]") {
    for (double tol : {0.1, 0.01, 0.001}) {
        INFO("tolerance " << tol);
        const double r = 10;
        const auto d = parse(R"svg(<circle cx="3" cy="-4" r="10"/>)svg", tol);
        const auto& ring = d.shapes.at(0).subpaths.at(0);
        REQUIRE(d.shapes[0].closed[0]);
        CHECK(ring[0] == vec2(13, -4));  // starts at (cx + r, cy)
        double max_sag = 0;
        for (std::size_t i = 0; i < ring.size(); ++i) {
            CHECK(glm::length(ring[i] - vec2(3, -4)) == Approx(r).epsilon(1e-14));
            const vec2 mid = 0.5 * (ring[i] + ring[(i + 1) % ring.size()]);
            max_sag = std::max(max_sag, r - glm::length(mid - vec2(3, -4)));
        }
        CHECK(max_sag <= tol);
        CHECK(max_sag >= 0.25 * tol);  // not needlessly dense
        const double area = fabsynth::signed_area(ring);
        CHECK(area > 0);  // increasing angle: positive shoelace area
        const double deficit = std::numbers::pi * r * r - area;
        CHECK(deficit >= 0);
        CHECK(deficit <= 2 * std::numbers::pi * r * tol);
    }
    // Ellipse under a rotation and non-uniform scale: points satisfy the mapped ellipse equation
    // and the chord error (checked densely) stays below the tolerance.
    const double tol = 0.005;
    const auto d = parse(R"svg(<g transform="scale(2 0.5)"><ellipse transform="rotate(20)" rx="6" ry="3"/></g>)svg", tol);
    const auto& ring = d.shapes.at(0).subpaths.at(0);
    const double c = std::cos(std::numbers::pi / 9), s = std::sin(std::numbers::pi / 9);
    auto curve = [&](double t) {
        const vec2 q{6 * std::cos(t), 3 * std::sin(t)};
        return vec2(2 * (c * q.x - s * q.y), 0.5 * (s * q.x + c * q.y));
    };
    for (const vec2& p : ring) {
        // invert: p -> rotate(-20) * scale(1/2, 2) p must lie on x^2/36 + y^2/9 = 1
        const vec2 u{p.x / 2, p.y * 2};
        const vec2 v{c * u.x + s * u.y, -s * u.x + c * u.y};
        CHECK(v.x * v.x / 36 + v.y * v.y / 9 == Approx(1).epsilon(1e-12));
    }
    double worst = 0;
    for (int k = 0; k < 20000; ++k) worst = std::max(worst, polyline_dist(curve(2 * std::numbers::pi * k / 20000), ring, true));
    CHECK(worst <= tol);
}

TEST_CASE("svg: arcs follow the SVG endpoint-to-center conversion", "[io][svg]") {
    const double h = std::sqrt(75.0);  // centers of radius-10 circles through (0,0) and (10,0): (5, +-h)
    struct row {
        int large, sweep;
        double cy, extreme_y;  // center y, and the y extreme reached by the arc
        bool min;              // extreme is a minimum (else maximum)
    };
    const row rows[] = {{0, 1, h, h - 10, true}, {1, 1, -h, -h - 10, true}, {0, 0, -h, -h + 10, false}, {1, 0, h, h + 10, false}};
    for (const row& r : rows) {
        INFO("large " << r.large << " sweep " << r.sweep);
        const auto d = parse("<path d=\"M0 0 A10 10 0 " + std::to_string(r.large) + " " + std::to_string(r.sweep) + " 10 0\"/>", 0.001);
        const auto& p = d.shapes.at(0).subpaths.at(0);
        CHECK(p.front() == vec2(0, 0));
        CHECK(p.back() == vec2(10, 0));
        double ext = r.min ? 1e9 : -1e9;
        for (const vec2& q : p) {
            CHECK(glm::length(q - vec2(5, r.cy)) == Approx(10).epsilon(1e-12));
            ext = r.min ? std::min(ext, q.y) : std::max(ext, q.y);
        }
        CHECK(ext == Approx(r.extreme_y).margin(0.001));
    }
    // Radii too small are scaled up (F.6.6): "A1 1" between points 10 apart is the half circle
    // of radius 5 centred at (5, 0).
    const auto d = parse(R"svg(<path d="M0 0 A1 1 0 0 1 10 0"/>)svg", 0.001);
    const auto& p = d.shapes[0].subpaths[0];
    for (const vec2& q : p) CHECK(glm::length(q - vec2(5, 0)) == Approx(5).epsilon(1e-12));
    double miny = 0;
    for (const vec2& q : p) miny = std::min(miny, q.y);
    CHECK(miny == Approx(-5).margin(0.001));
    // Zero radius: a straight line. Identical endpoints: nothing.
    const auto z = parse(R"svg(<path d="M0 0 A0 3 0 0 1 10 0 A 5 5 0 0 0 10 0"/>)svg");
    CHECK(z.shapes[0].subpaths[0] == std::vector<vec2>{{0, 0}, {10, 0}});
    // Rotated ellipse arc: points satisfy the rotated ellipse equation around the computed center.
    const auto e = parse(R"svg(<path d="M0 0 A8 4 45 1 1 6 2"/>)svg", 0.001);
    const auto& q = e.shapes[0].subpaths[0];
    // Center by the textbook F.6.5 formulas (unnormalised form), large == sweep: minus sign.
    const double phi = std::numbers::pi / 4, cs = std::cos(phi), sn = std::sin(phi);
    const double dx2 = (0.0 - 6.0) / 2, dy2 = (0.0 - 2.0) / 2;
    const double x1p = cs * dx2 + sn * dy2, y1p = -sn * dx2 + cs * dy2;
    REQUIRE(x1p * x1p / 64 + y1p * y1p / 16 <= 1);  // radii large enough: no scaling
    const double coef = -std::sqrt((64.0 * 16 - 64 * y1p * y1p - 16 * x1p * x1p) / (64 * y1p * y1p + 16 * x1p * x1p));
    const double cxp = coef * 8 * y1p / 4, cyp = -coef * 4 * x1p / 8;
    const vec2 c1{cs * cxp - sn * cyp + 3, sn * cxp + cs * cyp + 1};
    for (const vec2& u : q) {
        const vec2 v{cs * (u.x - c1.x) + sn * (u.y - c1.y), -sn * (u.x - c1.x) + cs * (u.y - c1.y)};
        CHECK(v.x * v.x / 64 + v.y * v.y / 16 == Approx(1).epsilon(1e-10));
    }
    CHECK(q.back() == vec2(6, 2));
}

TEST_CASE("svg: Bezier flattening error measured against dense evaluation", "[io][svg]") {
    const vec2 P[4] = {{0, 0}, {30, 80}, {70, -60}, {100, 10}};
    auto cubic = [&](double t) {
        const double s = 1 - t;
        return s * s * s * P[0] + 3 * s * s * t * P[1] + 3 * s * t * t * P[2] + t * t * t * P[3];
    };
    auto quad = [&](double t) {  // Q 50 90 100 0 from (0, 0)
        const double s = 1 - t;
        return s * s * vec2(0, 0) + 2 * s * t * vec2(50, 90) + t * t * vec2(100, 0);
    };
    for (double tol : {0.1, 0.01, 0.001}) {
        INFO("tolerance " << tol);
        const auto d = parse(R"svg(<path d="M0 0 C30 80 70 -60 100 10"/><path d="M0 0 Q50 90 100 0"/>)svg", tol);
        const auto& pc = d.shapes.at(0).subpaths.at(0);
        const auto& pq = d.shapes.at(1).subpaths.at(0);
        CHECK(pc.back() == P[3]);
        double wc = 0, wq = 0;
        for (int k = 0; k <= 20000; ++k) {
            wc = std::max(wc, polyline_dist(cubic(k / 20000.0), pc, false));
            wq = std::max(wq, polyline_dist(quad(k / 20000.0), pq, false));
        }
        CHECK(wc <= tol);
        CHECK(wq <= tol);
        // Uniform parameter steps: Wang's bound n = ceil(sqrt(d(d-1) L / (8 tol))) pieces.
        const double Lc = std::max(glm::length(P[2] - 2.0 * P[1] + P[0]), glm::length(P[3] - 2.0 * P[2] + P[1]));
        CHECK(pc.size() == 1 + static_cast<std::size_t>(std::ceil(std::sqrt(6 * Lc / (8 * tol)))));
        CHECK(wc >= 0.1 * tol);  // and not needlessly dense
    }
    // S reflects the previous C's second control point; T reflects the previous Q's control point.
    const auto s = parse(R"svg(<path d="M0 0 C10 10 20 10 30 0 S50 -10 60 0"/><path d="M0 0 C10 10 20 10 30 0 C40 -10 50 -10 60 0"/>)svg");
    CHECK(s.shapes[0].subpaths == s.shapes[1].subpaths);
    const auto t = parse(R"svg(<path d="M0 0 Q10 10 20 0 T40 0"/><path d="M0 0 Q10 10 20 0 Q30 -10 40 0"/>)svg");
    CHECK(t.shapes[0].subpaths == t.shapes[1].subpaths);
    // S without a preceding C uses the current point as first control point.
    const auto u = parse(R"svg(<path d="M0 0 S20 10 30 0"/><path d="M0 0 C0 0 20 10 30 0"/>)svg");
    CHECK(u.shapes[0].subpaths == u.shapes[1].subpaths);
}

TEST_CASE("svg: rect, polygon, polyline, line, ellipse elements", "[io][svg]") {
    const auto d = parse(R"svg(<rect x="1" y="2" width="3" height="4"/><polygon points="0,0 1,0 1,1"/>)svg"
                         R"svg(<polyline points="0 0 1 0 1 1 0 0"/><line x1="1" y1="2" x2="3" y2="4"/>)svg"
                         R"svg(<rect width="0" height="5"/><circle r="0"/>)svg");
    REQUIRE(d.shapes.size() == 6);
    CHECK(d.shapes[0].subpaths[0] == std::vector<vec2>{{1, 2}, {4, 2}, {4, 6}, {1, 6}});
    CHECK(d.shapes[0].closed[0]);
    CHECK(d.shapes[1].subpaths[0] == std::vector<vec2>{{0, 0}, {1, 0}, {1, 1}});
    CHECK(d.shapes[1].closed[0]);
    CHECK(d.shapes[2].subpaths[0].size() == 4);  // open: the last point is kept
    CHECK(!d.shapes[2].closed[0]);
    CHECK(d.shapes[3].subpaths[0] == std::vector<vec2>{{1, 2}, {3, 4}});
    CHECK(d.shapes[4].subpaths.empty());  // zero size: not rendered
    CHECK(d.shapes[5].subpaths.empty());
    // Rounded rect: area = w h - (4 - pi) rx ry, minus at most perimeter * tol for the flattening.
    const double tol = 0.001;
    const auto r = parse(R"svg(<rect width="20" height="10" rx="4" ry="3"/><rect width="20" height="10" rx="30"/>)svg", tol);
    const double exact = 200 - (4 - std::numbers::pi) * 12;
    const double a = fabsynth::signed_area(r.shapes[0].subpaths[0]);
    CHECK(a <= exact + 1e-9);
    CHECK(a >= exact - 60 * tol);
    // rx alone sets ry = rx, both clamp to half the size: a 20 x 10 stadium-like ellipse (rx 10, ry 5).
    const double a2 = fabsynth::signed_area(r.shapes[1].subpaths[0]);
    CHECK(a2 == Approx(std::numbers::pi * 50).margin(60 * tol));
    CHECK(fabsynth::is_simple(r.shapes[0].subpaths[0]));
    CHECK(fabsynth::is_simple(r.shapes[1].subpaths[0]));
}

TEST_CASE("svg: styles, inheritance, ids and skipped elements", "[io][svg]") {
    const std::string text = R"svg(<?xml version="1.0" standalone="no"?>
<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN" "http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd" [ <!ENTITY x "y"> ]>
<!-- a comment with <path d="M0 0 L1 1"/> inside -->
<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="50.5%" viewBox="-1 -2 200 101">
  <title>t</title><desc>x &lt; y</desc>
  <metadata><rdf:RDF xmlns:rdf="r"><rdf:li/></rdf:RDF></metadata>
  <style><![CDATA[ path { fill: red } <not a tag> ]]></style>
  <defs><path id="hidden" d="M0 0 L5 5"/></defs>
  <text x="0" y="0">hello <tspan>world</tspan></text>
  <g fill="red" stroke="blue" style="fill-rule: evenodd; stroke-width: 2 !important" transform="scale(3)">
    <path id="a&amp;b" d="M0 0 L1 0 L1 1 Z"/>
    <g fill="inherit" style="fill:green;stroke:none">
      <polygon fill="#123" fill-rule="nonzero" points="0 0 1 0 0 1"/>
      <polygon style="fill-rule:inherit" points="0 0 1 0 0 1"/>
    </g>
    <g display="none"><path d="M0 0 L9 9"/></g>
    <path style="display:none" d="M0 0 L9 9"/>
    <path stroke-width="1mm" d="M0 0 L2 0"/>
  </g>
  <use href="#hidden"/>
</svg>
<!-- trailing comment -->
)svg";
    const auto d = fio::parse_svg(text, "style.svg");
    CHECK(d.width == 100);
    CHECK(d.width_unit == "mm");
    CHECK(d.height == 50.5);
    CHECK(d.height_unit == "%");
    REQUIRE(d.view_box);
    CHECK(*d.view_box == fio::svg_view_box{-1, -2, 200, 101});
    REQUIRE(d.shapes.size() == 4);
    const auto& a = d.shapes[0];
    CHECK(a.id == "a&b");
    CHECK(a.fill == "red");
    CHECK(a.stroke == "blue");
    CHECK(a.rule == fabsynth::fill_rule::evenodd);
    CHECK(a.stroke_width == Approx(6));  // 2 user units under scale(3)
    CHECK(a.subpaths[0] == std::vector<vec2>{{0, 0}, {3, 0}, {3, 3}});
    CHECK(d.shapes[1].fill == "#123");  // attribute on the element beats inherited style
    CHECK(d.shapes[1].stroke == "none");
    CHECK(!d.shapes[1].stroked());
    CHECK(d.shapes[1].rule == fabsynth::fill_rule::nonzero);
    CHECK(d.shapes[2].fill == "green");
    CHECK(d.shapes[2].rule == fabsynth::fill_rule::evenodd);
    CHECK(d.shapes[3].stroke_width == Approx(3 * 96 / 25.4));
    // Style attribute wins over the presentation attribute on the same element.
    const auto s = parse(R"svg(<path fill="red" style="fill: blue" d="M0 0 L1 1"/>)svg");
    CHECK(s.shapes[0].fill == "blue");
    CHECK(s.shapes[0].rule == fabsynth::fill_rule::nonzero);
    CHECK(s.shapes[0].stroke_width == 1);
}

TEST_CASE("svg: malformed inputs raise io_error with the location", "[io][svg]") {
    struct row {
        std::string text;
        std::string where;  // expected "name:line:column"
        std::string what;   // expected fragment of the message
    };
    const std::string h = "<svg xmlns=\"http://www.w3.org/2000/svg\">\n";  // body starts on line 2
    const row rows[] = {
        {"", "bad.svg:1:1", "empty file"},
        {"  \n\t ", "bad.svg:1:1", "empty file"},
        {"<!-- only a comment -->", "bad.svg:1:24", "no root element"},
        {"<html></html>", "bad.svg:1:1", "root element is <html>"},
        {"<svg", "bad.svg:1:1", "unterminated tag"},
        {h + "<path d=\"M0 0\"", "bad.svg:2:1", "unterminated tag <path>"},
        {h + "<path d=\"M0 0/>\n</svg>", "bad.svg:3:1", "'<' in the value"},
        {h + "<!-- open", "bad.svg:2:1", "unterminated comment"},
        {h + "<g></svg>", "bad.svg:2:4", "does not match <g>"},
        {h + "<g>", "bad.svg:2:1", "<g> is not closed"},
        {h + "</svg><svg/>", "bad.svg:2:7", "second root element"},
        {"x<svg/>", "bad.svg:1:1", "text outside the root element"},
        {h + "<path d=\"M0 0\" d=\"M1 1\"/></svg>", "bad.svg:2:19", "duplicate attribute d"},
        {h + "<path d=\"L0 0\"/></svg>", "bad.svg:2:10", "must start with M"},
        {h + "<path d=\"M0 0 L1 x\"/></svg>", "bad.svg:2:18", "expected a number"},
        {h + "<path d=\"M0 0 L1 1e\"/></svg>", "bad.svg:2:19", "unknown path command 'e'"},
        {h + "<path d=\"M0 0 L NaN 1\"/></svg>", "bad.svg:2:17", "expected a number after 'L'"},
        {h + "<path d=\"M0 0 L inf 1\"/></svg>", "bad.svg:2:17", "expected a number after 'L'"},
        {h + "<path d=\"M0 0 L 1e999 1\"/></svg>", "bad.svg:2:17", "out of the double range"},
        {h + "<path d=\"M0 0 L 1 2 3\"/></svg>", "bad.svg:2:22", "coordinates come in pairs"},
        {h + "<path d=\"M0 0 X 1 2\"/></svg>", "bad.svg:2:15", "unknown path command 'X'"},
        {h + "<path d=\"M0 0 A 1 1 0 2 0 3 3\"/></svg>", "bad.svg:2:23", "arc flag must be 0 or 1"},
        {h + "<path d=\"M0 0 Z 1\"/></svg>", "bad.svg:2:17", "number after Z"},
        {h + "<path d=\"M0 0, L1 1\"/></svg>", "bad.svg:2:16", "expected a number after ','"},
        {h + "<path/></svg>", "bad.svg:2:1", "missing the required attribute d"},
        {h + "<polygon/></svg>", "bad.svg:2:1", "missing the required attribute points"},
        {h + "<polyline points=\"1 2 3\"/></svg>", "bad.svg:2:24", "even number of coordinates"},
        {h + "<rect width=\"1\"/></svg>", "bad.svg:2:1", "missing the required attribute height"},
        {h + "<rect width=\"-1\" height=\"1\"/></svg>", "bad.svg:2:14", "must not be negative"},
        {h + "<circle cx=\"1\"/></svg>", "bad.svg:2:1", "missing the required attribute r"},
        {h + "<ellipse rx=\"1\"/></svg>", "bad.svg:2:1", "missing the required attribute ry"},
        {h + "<circle r=\"5%\"/></svg>", "bad.svg:2:12", "relative unit '%'"},
        {h + "<circle r=\"5 furlongs\"/></svg>", "bad.svg:2:14", "unexpected text"},
        {h + "<circle r=\"1.2.3\"/></svg>", "bad.svg:2:15", "unexpected text"},
        {h + "<g transform=\"rotate(1 2)\"/></svg>", "bad.svg:2:25", "rotate takes 1 or 3 arguments"},
        {h + "<g transform=\"spin(1)\"/></svg>", "bad.svg:2:15", "unknown transform 'spin'"},
        {h + "<g transform=\"scale(1\"/></svg>", "bad.svg:2:22", "unterminated scale("},
        {h + "<g transform=\"scale(1e200) scale(1e200)\"/></svg>", "bad.svg:2:28", "overflows"},
        {h + "<path fill-rule=\"odd\" d=\"M0 0\"/></svg>", "bad.svg:2:18", "fill-rule must be"},
        {h + "<path id=\"a&b\" d=\"M0 0\"/></svg>", "bad.svg:2:12", "does not start a reference"},
        {h + "<path id=\"&nbsp;\" d=\"M0 0\"/></svg>", "bad.svg:2:11", "unknown entity &nbsp;"},
        {"<svg width=\"-3\"/>", "bad.svg:1:13", "width must not be negative"},
        {"<svg viewBox=\"0 0 1\"/>", "bad.svg:1:20", "expected 4 numbers"},
        {h + "<path d=\"M1e300 1e300 L-1e300 -1e300\" transform=\"scale(1e10)\"/></svg>", "bad.svg:2:10", "overflows"},
        {h + "<circle r=\"1e300\"/></svg>", "bad.svg:2:1", "more than 50000000 points"},
        {h + "<path d=\"M0 0 A1e-300 1e-300 0 0 1 1e300 0\"/></svg>", "bad.svg:2:15", "points"},
        {h + "<path d=\"M0 0 C1e300 -1e300 -1e300 1e300 1 1\"/></svg>", "bad.svg:2:15", "points"},
    };
    for (const row& r : rows) {
        INFO(r.text);
        try {
            (void)fio::parse_svg(r.text, "bad.svg");
            FAIL("no exception");
        } catch (const fabsynth::io_error& e) {
            const std::string msg = e.what();
            INFO(msg);
            CHECK(msg.rfind("fabsynth: " + r.where + ": ", 0) == 0);
            CHECK(msg.find(r.what) != std::string::npos);
        }
    }
    // Point limit is configurable and counts the whole document.
    CHECK_THROWS_AS(fio::parse_svg(wrap("<circle r=\"100\"/>"), "x", {.tolerance = 0.01, .max_points = 100}), fabsynth::io_error);
    CHECK_NOTHROW(fio::parse_svg(wrap("<circle r=\"100\"/>"), "x", {.tolerance = 0.01, .max_points = 1000}));
    CHECK_THROWS_AS(fio::parse_svg(wrap("<polygon points=\"0 0 1 1 2 2\"/><line x2=\"1\"/>"), "x", {.tolerance = 0.01, .max_points = 4}),
                    fabsynth::io_error);
    CHECK_THROWS_AS(fio::parse_svg(wrap(""), "x", 0.0), fabsynth::invalid_input);
    CHECK_THROWS_AS(fio::parse_svg(wrap(""), "x", std::nan("")), fabsynth::invalid_input);
    // Deep nesting is bounded.
    std::string deep = "<svg>";
    for (int i = 0; i < 2000; ++i) deep += "<g>";
    CHECK_THROWS_WITH(fio::parse_svg(deep, "deep.svg"), Catch::Contains("nested deeper"));
    // Missing file names the file.
    CHECK_THROWS_WITH(fio::read_svg("/nonexistent/dir/x.svg"), Catch::Contains("/nonexistent/dir/x.svg"));
}
