// Tests for geometry/curve.hpp: arc-length parametrisation, the band map (isometric on a line,
// exact on a circle, exact offsets on polylines), fold and overlap detection, bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/curve.hpp"
#include "fabsynth/io/svg.hpp"

using namespace fabsynth;
using Catch::Matchers::Contains;

namespace {
// Brute-force distance from p to an open polyline.
double distance_to_polyline(const std::vector<vec2>& pts, vec2 p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
        const vec2 a = pts[i], d = pts[i + 1] - a;
        const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
        best = std::min(best, glm::length(p - (a + t * d)));
    }
    return best;
}
}  // namespace

TEST_CASE("curve: a straight line maps the band isometrically", "[geometry][curve]") {
    const planar_curve c = planar_curve::line(120.0);
    CHECK(c.length() == 120.0);
    CHECK_FALSE(c.closed());
    CHECK(std::isinf(c.min_radius_of_curvature()));
    for (double u : {0.0, 0.1, 17.25, 60.0, 119.9, 120.0})
        for (double v : {-7.5, -1.0, 0.0, 3.0, 7.5}) {
            const vec2 p = c.band_point(u, v);
            CHECK(p.x == Approx(u).margin(1e-12));
            CHECK(p.y == Approx(v).margin(1e-12));
        }
    CHECK(c.normal(30.0) == vec2(0, 1));
    CHECK(c.tangent(30.0) == vec2(1, 0));
    CHECK_NOTHROW(c.check_band(1e6));  // a straight band never folds
}

TEST_CASE("curve: a circle of radius R maps u to angle -u/R and v to radius R + v", "[geometry][curve]") {
    const double R = 25.0;
    const vec2 centre{3, -4};
    const planar_curve c = planar_curve::circle(R, centre);
    CHECK(c.closed());
    CHECK(c.length() == Approx(2 * std::numbers::pi * R).epsilon(1e-15));
    for (int i = 0; i <= 64; ++i) {
        const double u = c.length() * i / 64.0;
        for (double v : {-10.0, -2.0, 0.0, 4.5, 12.0}) {
            const vec2 p = c.band_point(u, v) - centre;
            CHECK(glm::length(p) == Approx(R + v).epsilon(1e-13));
            const double expected = -u / R;  // angle, wrapped
            CHECK(std::abs(std::remainder(std::atan2(p.y, p.x) - expected, 2 * std::numbers::pi)) < 1e-12);
        }
        // outward unit normal, unit tangent, orientation-preserving frame det[t n] = 1
        const vec2 n = c.normal(u), t = c.tangent(u);
        CHECK(glm::dot(n, c.point(u) - centre) == Approx(R).epsilon(1e-12));
        CHECK(t.x * n.y - t.y * n.x == Approx(1.0).epsilon(1e-12));
    }
    // the seam closes exactly: u = L is evaluated as u = 0
    for (double v : {-3.0, 0.0, 7.0}) CHECK(c.band_point(c.length(), v) == c.band_point(0.0, v));
    CHECK(c.min_radius_of_curvature() == R);
    CHECK_NOTHROW(c.check_band(0.99 * R));
    CHECK_THROWS_WITH(c.check_band(R), Contains("radius of curvature"));
}

TEST_CASE("curve: polyline band map gives exact offsets, continuous normals and no folds", "[geometry][curve]") {
    // An L with a 90 degree corner, a gentle bend and a straight end.
    const std::vector<vec2> pts{{0, 0}, {10, 0}, {10, 10}, {14, 16}, {14, 30}};
    const planar_curve c = planar_curve::polyline(pts, false);
    double expected_length = 0;
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) expected_length += glm::length(pts[i + 1] - pts[i]);
    CHECK(c.length() == Approx(expected_length).epsilon(1e-15));
    const double h = 0.9 * c.min_radius_of_curvature();
    REQUIRE(h > 1.0);
    CHECK_NOTHROW(c.check_band(h));
    // every point of the line v = const lies at signed distance exactly v from the line of the
    // segment it belongs to (the mitred parallel polyline), and on the normal side for v > 0
    const auto& arcs = c.vertex_arc_lengths();
    for (int i = 1; i < 400; ++i) {
        const double u = c.length() * i / 400.0;
        const std::size_t k = static_cast<std::size_t>(std::upper_bound(arcs.begin(), arcs.end(), u) - arcs.begin()) - 1;
        const vec2 a = pts[k], t = glm::normalize(pts[k + 1] - pts[k]);
        for (double v : {-h, -0.5 * h, 0.3 * h, h}) {
            INFO("u " << u << " v " << v);
            const vec2 q = c.band_point(u, v) - a;
            CHECK(t.x * q.y - t.y * q.x == Approx(v).epsilon(1e-9));
        }
        CHECK(distance_to_polyline(pts, c.point(u)) < 1e-12);
    }
    // local injectivity: the Jacobian determinant of (u, v) -> band_point is positive everywhere in
    // the band (finite differences inside each segment), and the unit normal is continuous
    const double du = 1e-4;
    for (int i = 0; i < 2000; ++i) {
        const double u = c.length() * (i + 0.5) / 2000.0;
        for (double v : {-0.99 * h, 0.0, 0.99 * h}) {
            const vec2 pu = (c.band_point(u + du, v) - c.band_point(u - du, v)) / (2 * du);
            const vec2 pv = (c.band_point(u, v + du) - c.band_point(u, v - du)) / (2 * du);
            CHECK(pu.x * pv.y - pu.y * pv.x > 0.0);
        }
        CHECK(glm::length(c.normal(u + 1e-6) - c.normal(u)) < 1e-3);
    }
    CHECK_THROWS_WITH(c.check_band(1.01 * c.min_radius_of_curvature()), Contains("fold"));
}

TEST_CASE("curve: discrete radius of curvature of a fine regular polygon approaches the circle's", "[geometry][curve]") {
    const double R = 10.0;
    std::vector<vec2> pts;
    const int n = 720;
    for (int i = 0; i < n; ++i) pts.push_back({R * std::cos(2 * std::numbers::pi * i / n), R * std::sin(2 * std::numbers::pi * i / n)});
    const planar_curve c = planar_curve::polyline(pts, true);
    CHECK(c.length() == Approx(2 * std::numbers::pi * R).epsilon(1e-4));
    CHECK(c.min_radius_of_curvature() == Approx(R * std::cos(std::numbers::pi / n)).epsilon(1e-9));
    CHECK_NOTHROW(c.check_band(9.0));
    CHECK_THROWS_AS(c.check_band(10.0), invalid_input);
    // closed polyline: u = L is u = 0 exactly
    CHECK(c.band_point(c.length(), 1.5) == c.band_point(0.0, 1.5));
}

TEST_CASE("curve: a band that overlaps itself is rejected", "[geometry][curve]") {
    // an Archimedean spiral: two turns 3 apart, radius of curvature >= 10 everywhere, so a band
    // thicker than the pitch overlaps the next turn without folding anywhere
    std::vector<vec2> pts;
    for (int i = 0; i <= 800; ++i) {
        const double th = 4 * std::numbers::pi * i / 800.0, r = 10.0 + 3.0 * th / (2 * std::numbers::pi);
        pts.push_back({r * std::cos(th), r * std::sin(th)});
    }
    const planar_curve c = planar_curve::polyline(pts, false);
    CHECK_NOTHROW(c.check_band(1.0));
    REQUIRE(c.min_radius_of_curvature() > 2.0);
    CHECK_THROWS_WITH(c.check_band(2.0), Contains("overlaps itself"));
    // a figure eight crosses itself even with a zero-height band
    const planar_curve eight = planar_curve::polyline({{0, 0}, {10, 10}, {20, 0}, {20, 10}, {10, 0}, {0, 10}}, true);
    CHECK_THROWS_WITH(eight.check_band(0.1), Contains("overlaps itself"));
}

TEST_CASE("curve: from SVG paths, lines and circles", "[geometry][curve]") {
    const auto doc = io::parse_svg(R"(<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
        <path d="M 10 50 C 30 10, 70 90, 90 50" fill="none" stroke="black"/></svg>)", "wave.svg", 1e-4);
    const planar_curve c = curve_from_svg(doc);
    CHECK_FALSE(c.closed());
    CHECK(c.point(0.0) == vec2(10, 50));
    CHECK(glm::length(c.point(c.length()) - vec2(90, 50)) < 1e-12);
    CHECK(c.length() > 80.0);
    const auto circle_doc = io::parse_svg(R"(<svg xmlns="http://www.w3.org/2000/svg"><circle cx="0" cy="0" r="30"/></svg>)", "c.svg", 1e-4);
    const planar_curve cc = curve_from_svg(circle_doc);
    CHECK(cc.closed());
    CHECK(cc.length() == Approx(2 * std::numbers::pi * 30).epsilon(1e-5));
    CHECK(cc.min_radius_of_curvature() == Approx(30).epsilon(1e-3));
    const planar_curve forced = curve_from_svg(doc, true);
    CHECK(forced.closed());
}

TEST_CASE("curve: bad input is rejected with a message", "[geometry][curve]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH(planar_curve::polyline({{0, 0}}, false), Contains("at least 2"));
    CHECK_THROWS_WITH(planar_curve::polyline({{1, 1}, {1, 1}, {1, 1}}, false), Contains("at least 2"));
    CHECK_THROWS_WITH(planar_curve::polyline({{0, 0}, {nan, 1}}, false), Contains("not finite"));
    CHECK_THROWS_WITH(planar_curve::polyline({{0, 0}, {1, 0}, {0, 0}}, false), Contains("turns back"));
    CHECK_THROWS_WITH(planar_curve::polyline({{0, 0}, {1, 0}}, true), Contains("at least 3"));
    CHECK_THROWS_AS(planar_curve::line(0.0), invalid_input);
    CHECK_THROWS_AS(planar_curve::line(nan), invalid_input);
    CHECK_THROWS_AS(planar_curve::circle(-1.0), invalid_input);
    CHECK_THROWS_AS(planar_curve::circle(std::numeric_limits<double>::infinity()), invalid_input);
    CHECK_THROWS_AS(planar_curve::line(10).check_band(nan), invalid_input);
    const auto empty = io::parse_svg(R"(<svg xmlns="http://www.w3.org/2000/svg"></svg>)", "e.svg");
    CHECK_THROWS_WITH(curve_from_svg(empty), Contains("no path"));
}

namespace {
// Independent oracle for detail::curve::any_contact: every pair of non-consecutive edges, with a
// plain orientation test (random coordinates make touching and collinear cases measure-zero).
double orient_oracle(vec2 a, vec2 b, vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }
bool crossing_oracle(vec2 a, vec2 b, vec2 c, vec2 d) {
    const double d1 = orient_oracle(a, b, c), d2 = orient_oracle(a, b, d), d3 = orient_oracle(c, d, a), d4 = orient_oracle(c, d, b);
    return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}
bool brute_force_contact(const std::vector<std::vector<vec2>>& lines, const std::vector<bool>& closed) {
    struct seg { std::size_t l, i; vec2 a, b; };
    std::vector<seg> s;
    for (std::size_t l = 0; l < lines.size(); ++l)
        for (std::size_t i = 0; i + (closed[l] ? 0 : 1) < lines[l].size(); ++i) s.push_back({l, i, lines[l][i], lines[l][(i + 1) % lines[l].size()]});
    for (std::size_t x = 0; x < s.size(); ++x)
        for (std::size_t y = x + 1; y < s.size(); ++y) {
            if (s[x].l == s[y].l) {
                const std::size_t n = lines[s[x].l].size(), d = s[y].i - s[x].i;
                if (d == 1 || (closed[s[x].l] && d == n - 1)) continue;
            }
            if (crossing_oracle(s[x].a, s[x].b, s[y].a, s[y].b)) return true;
        }
    return false;
}
}  // namespace

TEST_CASE("curve: the contact test agrees with a brute-force oracle, and long spirals stay linear", "[geometry][curve]") {
    fabsynth::counter_rng r(77);
    int with_contact = 0, without = 0;
    for (int trial = 0; trial < 400; ++trial) {
        // random walks of varying step, so some cross themselves or each other and some do not
        const std::size_t nl = 1 + r.uniform_int(3);
        std::vector<std::vector<vec2>> lines(nl);
        std::vector<bool> closed(nl);
        const double step = r.uniform(0.05, 3.0);
        for (std::size_t l = 0; l < nl; ++l) {
            vec2 p{r.uniform(0, 10), r.uniform(0, 10)};
            const std::size_t n = 3 + r.uniform_int(25);
            double heading = r.uniform(0, 6.283);
            for (std::size_t i = 0; i < n; ++i) {
                lines[l].push_back(p);
                heading += r.uniform(-1.2, 1.2);
                p += step * vec2(std::cos(heading), std::sin(heading)) * r.uniform(0.2, 1.0);
            }
            closed[l] = r.uniform_int(2) == 1;
        }
        const bool expect = brute_force_contact(lines, closed);
        INFO("trial " << trial);
        REQUIRE(fabsynth::detail::curve::any_contact(lines, closed) == expect);
        (expect ? with_contact : without) += 1;
    }
    CHECK(with_contact > 50);
    CHECK(without > 50);
    // a 60 k-edge Archimedean spiral (every edge overlaps many others in x and y): no contact,
    // then one chord across its turns
    std::vector<vec2> spiral;
    for (int i = 0; i < 60000; ++i) {
        const double t = 0.01 * i + 1.0;
        spiral.emplace_back(t * std::cos(t), t * std::sin(t));
    }
    CHECK_FALSE(fabsynth::detail::curve::any_contact({spiral}, {false}));
    CHECK(fabsynth::detail::curve::any_contact({spiral, {{0, 0}, {500, 1}}}, {false, false}));
    CHECK_NOTHROW(fabsynth::planar_curve::polyline(spiral, false).check_band(0.1));
    // is_simple on the same grid: the 120 k-vertex outline of a band along the spiral, out along
    // one side and back along the other, then with one vertex pulled across the next turn
    ring2 outline;
    for (std::size_t i = 0; i < spiral.size(); ++i) outline.push_back(spiral[i] * (1 + 0.5 / glm::length(spiral[i])));
    for (std::size_t i = spiral.size(); i-- > 0;) outline.push_back(spiral[i] * (1 - 0.5 / glm::length(spiral[i])));
    CHECK(fabsynth::is_simple(outline));
    outline[30000] *= 1.3;
    CHECK_FALSE(fabsynth::is_simple(outline));
    // and is_simple against the oracle on random closed walks
    int simple = 0, not_simple = 0;
    for (int trial = 0; trial < 300; ++trial) {
        ring2 ring;
        vec2 p{0, 0};
        double heading = r.uniform(0, 6.283);
        const std::size_t n = 3 + r.uniform_int(12);
        for (std::size_t i = 0; i < n; ++i) {
            ring.push_back(p);
            heading += r.uniform(0.2, 1.4);  // mostly turning one way: many rings are simple
            p += vec2(std::cos(heading), std::sin(heading)) * r.uniform(0.3, 1.0);
        }
        const bool expect = !brute_force_contact({ring}, {true});
        INFO("ring trial " << trial);
        REQUIRE(fabsynth::is_simple(ring) == expect);
        (expect ? simple : not_simple) += 1;
    }
    CHECK(simple > 30);
    CHECK(not_simple > 30);
}
