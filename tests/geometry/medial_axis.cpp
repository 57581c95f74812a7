// Tests of geometry/medial_axis.hpp against analytic skeletons and a brute-force distance to the
// boundary (oracles written here; they share no code with the header).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <vector>

#include <polyclipping/clipper.hpp>

#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/medial_axis.hpp"
#include "fabsynth/io/svg.hpp"

namespace {

using fabsynth::polygon_with_holes;
using fabsynth::ring2;
using fabsynth::vec2;

double seg_dist(vec2 p, vec2 a, vec2 b) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double l2 = dx * dx + dy * dy;
    double t = ((p.x - a.x) * dx + (p.y - a.y) * dy) / l2;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

double boundary_dist(const polygon_with_holes& poly, vec2 p) {
    double d = 1e300;
    auto ring = [&](const ring2& r) {
        for (std::size_t i = 0; i < r.size(); ++i) d = std::min(d, seg_dist(p, r[i], r[(i + 1) % r.size()]));
    };
    ring(poly.outer);
    for (const auto& h : poly.holes) ring(h);
    return d;
}

double extent(const polygon_with_holes& poly) {
    double lo = 1e300, hi = -1e300;
    for (const vec2& p : poly.outer) lo = std::min({lo, p.x, p.y}), hi = std::max({hi, p.x, p.y});
    return hi - lo;
}

// Every vertex: half-width = brute-force distance to the boundary (1e-9 of the polygon's size),
// inside the polygon; edges valid and distinct.
void check_skeleton_basics(const polygon_with_holes& poly, const fabsynth::medial_skeleton& sk) {
    REQUIRE(sk.positions.size() == sk.half_widths.size());
    const double scale = extent(poly);
    for (std::size_t i = 0; i < sk.positions.size(); ++i) {
        INFO("vertex " << i << " at " << sk.positions[i].x << ", " << sk.positions[i].y);
        REQUIRE(std::abs(sk.half_widths[i] - boundary_dist(poly, sk.positions[i])) <= 1e-9 * scale);
        REQUIRE(fabsynth::point_in_polygon(poly, sk.positions[i]));
    }
    std::set<std::pair<std::size_t, std::size_t>> seen;
    for (const auto& e : sk.edges) {
        REQUIRE(e[0] != e[1]);
        REQUIRE(e[0] < sk.positions.size());
        REQUIRE(e[1] < sk.positions.size());
        REQUIRE(seen.insert({std::min(e[0], e[1]), std::max(e[0], e[1])}).second);
    }
}

std::vector<int> degrees(const fabsynth::medial_skeleton& sk) {
    std::vector<int> d(sk.positions.size(), 0);
    for (const auto& e : sk.edges) ++d[e[0]], ++d[e[1]];
    return d;
}

// Segments of the skeleton as a canonical sorted set of rounded end points.
using seg_key = std::array<long long, 4>;
std::set<seg_key> segment_set(const fabsynth::medial_skeleton& sk) {
    std::set<seg_key> s;
    auto q = [](double v) { return std::llround(v * 1e6); };
    for (const auto& e : sk.edges) {
        vec2 a = sk.positions[e[0]], b = sk.positions[e[1]];
        if (std::make_pair(a.x, a.y) > std::make_pair(b.x, b.y)) std::swap(a, b);
        s.insert({q(a.x), q(a.y), q(b.x), q(b.y)});
    }
    return s;
}
seg_key key(vec2 a, vec2 b) {
    if (std::make_pair(a.x, a.y) > std::make_pair(b.x, b.y)) std::swap(a, b);
    auto q = [](double v) { return std::llround(v * 1e6); };
    return {q(a.x), q(a.y), q(b.x), q(b.y)};
}

double point_polyline_dist(vec2 p, const fabsynth::medial_skeleton& sk) {
    double d = 1e300;
    for (const auto& e : sk.edges) d = std::min(d, seg_dist(p, sk.positions[e[0]], sk.positions[e[1]]));
    return d;
}

ring2 regular(int n, double r, bool ccw) {
    ring2 out;
    for (int k = 0; k < n; ++k) {
        const double t = 2 * std::numbers::pi * (ccw ? k : -k) / n;
        out.push_back({r * std::cos(t), r * std::sin(t)});
    }
    return out;
}

}  // namespace

TEST_CASE("medial axis of a rectangle: middle segment and four corner branches", "[geometry][medial_axis]") {
    const double w = 10, h = 4;
    const polygon_with_holes rect{{{0, 0}, {w, 0}, {w, h}, {0, h}}, {}};
    const auto full = fabsynth::medial_axis(rect, {.flattening_tolerance = 0.01});
    check_skeleton_basics(rect, full);
    const vec2 m0(h / 2, h / 2), m1(w - h / 2, h / 2);
    const std::set<seg_key> expected{key(m0, m1), key({0, 0}, m0), key({0, h}, m0), key({w, 0}, m1), key({w, h}, m1)};
    CHECK(segment_set(full) == expected);
    // Half-widths: h/2 on the middle segment, 0 at the corners (linear in between: no inner vertices).
    for (std::size_t i = 0; i < full.positions.size(); ++i) {
        const vec2 p = full.positions[i];
        if (std::abs(p.y - h / 2) < 1e-9) CHECK(full.half_widths[i] == Approx(h / 2).margin(1e-12));
        else CHECK(full.half_widths[i] == Approx(0.0).margin(1e-12));
    }

    const auto pruned = fabsynth::medial_axis(rect, {.flattening_tolerance = 0.01, .prune_length = 3.0});
    check_skeleton_basics(rect, pruned);
    CHECK(segment_set(pruned) == std::set<seg_key>{key(m0, m1)});
    // Branches longer than prune_length stay.
    const auto kept = fabsynth::medial_axis(rect, {.flattening_tolerance = 0.01, .prune_length = 2.0});
    CHECK(segment_set(kept) == expected);
}

TEST_CASE("medial axis of a rotated, off-grid rectangle", "[geometry][medial_axis]") {
    const double w = 7.3, h = 2.9, c = std::cos(0.5), s = std::sin(0.5);
    auto at = [&](double u, double v) { return vec2(1.37 + c * u - s * v, -2.11 + s * u + c * v); };
    const polygon_with_holes rect{{at(0, 0), at(w, 0), at(w, h), at(0, h)}, {}};
    const double tol = 1e-3;
    const auto sk = fabsynth::medial_axis(rect, {.flattening_tolerance = tol, .prune_length = 0.5 * h * 1.5});
    check_skeleton_basics(rect, sk);
    REQUIRE(sk.edges.size() == 1);
    const vec2 a = sk.positions[sk.edges[0][0]], b = sk.positions[sk.edges[0][1]];
    const vec2 m0 = at(h / 2, h / 2), m1 = at(w - h / 2, h / 2);
    const double err = std::min(glm::distance(a, m0) + glm::distance(b, m1), glm::distance(a, m1) + glm::distance(b, m0));
    CHECK(err <= tol);
    CHECK(sk.half_widths[0] == Approx(h / 2).margin(tol));
}

TEST_CASE("medial axis of an annulus: the mid circle with half-width (R - r) / 2", "[geometry][medial_axis]") {
    const int n = 128;
    const double R = 10, r = 5, tol = 0.005;
    const polygon_with_holes ring{regular(n, R, true), {regular(n, r, false)}};
    // Circle-vs-polygon error: the sagittas of the two polygons.
    const double sag = R * (1 - std::cos(std::numbers::pi / n)) + r * (1 - std::cos(std::numbers::pi / n));
    const auto sk = fabsynth::medial_axis(ring, {.flattening_tolerance = tol, .prune_length = 0.75 * (R - r)});
    check_skeleton_basics(ring, sk);
    REQUIRE(sk.positions.size() >= static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < sk.positions.size(); ++i) {
        CHECK(std::abs(glm::length(sk.positions[i]) - (R + r) / 2) <= sag + tol);
        CHECK(std::abs(sk.half_widths[i] - (R - r) / 2) <= sag + tol);
    }
    // One closed loop: every vertex has degree 2.
    for (int d : degrees(sk)) CHECK(d == 2);
    CHECK(sk.edges.size() == sk.positions.size());
    // Without pruning, every convex outer vertex adds a branch.
    const auto full = fabsynth::medial_axis(ring, {.flattening_tolerance = tol});
    check_skeleton_basics(ring, full);
    const auto d = degrees(full);
    CHECK(std::count(d.begin(), d.end(), 1) == n);
}

TEST_CASE("medial axis of an L-shape against its analytic skeleton", "[geometry][medial_axis]") {
    const polygon_with_holes L{{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, {}};
    const double a = 2 - std::sqrt(2.0);  // where the two parabolas meet the corner bisector
    // Analytic skeleton, densely sampled: straight pieces and the two parabolas of the reflex
    // vertex (1, 1) with the lines y = 0 and x = 0.
    auto sample = [](vec2 p, vec2 q, std::vector<vec2>& out) {
        for (int k = 0; k <= 200; ++k) out.push_back(p + (q - p) * (k / 200.0));
    };
    std::vector<vec2> core, corners;
    sample({1.5, 0.5}, {1, 0.5}, core);
    sample({0.5, 1.5}, {0.5, 1}, core);
    for (int k = 0; k <= 400; ++k) {
        const double x = a + (1 - a) * k / 400.0;
        core.push_back({x, ((x - 1) * (x - 1) + 1) / 2});
        core.push_back({((x - 1) * (x - 1) + 1) / 2, x});
    }
    sample({0, 0}, {a, a}, corners);
    sample({2, 0}, {1.5, 0.5}, corners);
    sample({2, 1}, {1.5, 0.5}, corners);
    sample({0, 2}, {0.5, 1.5}, corners);
    sample({1, 2}, {0.5, 1.5}, corners);
    auto dist_to = [](vec2 p, const std::vector<vec2>& s) {
        double d = 1e300;
        for (const vec2& q : s) d = std::min(d, glm::distance(p, q));
        return d;
    };
    const double tol = 0.002, sampling_gap = 0.01;  // the analytic samples are <= 0.0036 apart
    std::vector<vec2> all = core;
    all.insert(all.end(), corners.begin(), corners.end());

    const auto full = fabsynth::medial_axis(L, {.flattening_tolerance = tol});
    check_skeleton_basics(L, full);
    for (const vec2& p : full.positions) CHECK(dist_to(p, all) <= sampling_gap);
    for (const vec2& p : all) CHECK(point_polyline_dist(p, full) <= tol * 1.01);
    // Half-widths on the parabola: the distance to the line y = 0 (x in [a, 1]).
    for (std::size_t i = 0; i < full.positions.size(); ++i) {
        const vec2 p = full.positions[i];
        if (p.x > a + 1e-9 && p.x < 1 - 1e-9 && p.y < 0.75) CHECK(full.half_widths[i] == Approx(p.y).margin(1e-12));
    }
    // Edges between flattening points of an arc stay within the tolerance of the arc.
    for (const auto& e : full.edges) {
        const vec2 m = 0.5 * (full.positions[e[0]] + full.positions[e[1]]);
        CHECK(dist_to(m, all) <= tol + 0.004);
    }

    // Pruning at 0.9 removes the five corner branches (0.71 and 0.83 long) and keeps the path.
    const auto pruned = fabsynth::medial_axis(L, {.flattening_tolerance = tol, .prune_length = 0.9});
    check_skeleton_basics(L, pruned);
    for (const vec2& p : pruned.positions) CHECK(dist_to(p, core) <= sampling_gap);
    for (const vec2& p : core) CHECK(point_polyline_dist(p, pruned) <= tol * 1.01);
    const auto d = degrees(pruned);
    CHECK(std::count(d.begin(), d.end(), 1) == 2);
    CHECK(pruned.edges.size() + 1 == pruned.positions.size());
}

TEST_CASE("medial axis of a wavy strip with a hole: half-widths are the boundary distance", "[geometry][medial_axis]") {
    // A closed band around a wobbly circle (a filigree-like strip), sampled densely.
    ring2 outer, inner;
    const int n = 300;
    for (int k = 0; k < n; ++k) {
        const double t = 2 * std::numbers::pi * k / n;
        const double c = 20 + 2 * std::sin(5 * t), wdt = 1.0 + 0.4 * std::cos(3 * t);
        outer.push_back({(c + wdt) * std::cos(t), (c + wdt) * std::sin(t)});
        inner.push_back({(c - wdt) * std::cos(t), (c - wdt) * std::sin(t)});
    }
    const polygon_with_holes band{outer, {inner}};  // orientation is fixed by the function
    const auto sk = fabsynth::medial_axis(band, {.flattening_tolerance = 0.01, .prune_length = 2.0});
    check_skeleton_basics(band, sk);
    for (int d : degrees(sk)) CHECK(d == 2);  // one loop once the spikes are pruned
    for (double hw : sk.half_widths) CHECK((hw > 0.5 && hw < 1.5));
}

TEST_CASE("medial axis of the bundled filigree elements (stroke outlines)", "[geometry][medial_axis]") {
    for (const char* name : {"c_scroll", "heart_curls", "leaf", "s_curl", "spiral"}) {
        INFO(name);
        // Outline of the strokes: a round offset of the open polylines by half the width.
        const auto doc = fabsynth::io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/filigree/" + name + ".svg", {.tolerance = 0.01});
        double half = 0.5;
        std::vector<std::vector<vec2>> lines;
        for (const auto& s : doc.shapes) {
            half = 0.5 * s.stroke_width;
            lines.insert(lines.end(), s.subpaths.begin(), s.subpaths.end());
        }
        const auto polys = fabsynth::stroke_outline(lines, half, 0.01);
        REQUIRE_FALSE(polys.empty());
        for (const auto& poly : polys) {
            const auto sk = fabsynth::medial_axis(poly, {.flattening_tolerance = 0.01, .prune_length = 1.0});
            check_skeleton_basics(poly, sk);
            // Strips of constant width: the median half-width is the stroke's half-width (up to
            // the offset's arc tolerance; discs grow only where strokes meet), and pruning leaves
            // no spikes into the rounded outline.
            auto hw = sk.half_widths;
            std::nth_element(hw.begin(), hw.begin() + hw.size() / 2, hw.end());
            CHECK(hw[hw.size() / 2] == Approx(half).margin(0.02));
            for (double h : hw) CHECK(h <= 2 * half);
            const auto d = degrees(sk);
            CHECK(std::count(d.begin(), d.end(), 0) == 0);
            CHECK(std::count(d.begin(), d.end(), 1) <= 2 * static_cast<long>(doc.shapes.size()) + 2);
        }
    }
}

TEST_CASE("medial axis rejects bad input", "[geometry][medial_axis][errors]") {
    using fabsynth::invalid_input;
    using Catch::Matchers::Contains;
    using Catch::Matchers::StartsWith;
    const polygon_with_holes bowtie{{{0, 0}, {2, 2}, {2, 0}, {0, 2}}, {}};
    CHECK_THROWS_AS(fabsynth::medial_axis(bowtie), invalid_input);
    CHECK_THROWS_WITH(fabsynth::medial_axis(bowtie), StartsWith("fabsynth:") && Contains("outer ring is not simple"));
    CHECK_THROWS_WITH(fabsynth::medial_axis({{{0, 0}, {1, 0}}, {}}), Contains("2 vertices"));
    CHECK_THROWS_WITH(fabsynth::medial_axis({{{0, 0}, {1, 0}, {std::nan(""), 1}}, {}}), Contains("not finite"));
    const ring2 sq{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
    CHECK_THROWS_WITH(fabsynth::medial_axis({sq, {{{20, 20}, {21, 20}, {21, 21}}}}), Contains("hole 0 is not inside"));
    CHECK_THROWS_WITH(fabsynth::medial_axis({sq, {{{5, 5}, {12, 5}, {5, 7}}}}), Contains("intersect"));
    CHECK_THROWS_WITH(fabsynth::medial_axis({sq, {{{1, 1}, {2, 1}, {3, 3}, {2, 2}, {3, 1}, {1, 2}}}}), Contains("hole 0 is not simple"));
    CHECK_THROWS_WITH(fabsynth::medial_axis({sq, {}}, {.flattening_tolerance = 0}), Contains("flattening_tolerance"));
    CHECK_THROWS_WITH(fabsynth::medial_axis({sq, {}}, {.flattening_tolerance = std::nan("")}), Contains("flattening_tolerance"));
    CHECK_THROWS_WITH(fabsynth::medial_axis({sq, {}}, {.prune_length = -1}), Contains("prune_length"));
    CHECK_THROWS_WITH(fabsynth::medial_axis({sq, {}}, {.flattening_tolerance = 1e-7}), Contains("grid steps"));
    // A feature below the grid step collapses.
    CHECK_THROWS_WITH(fabsynth::medial_axis({{{0, 0}, {1e-4, 0}, {0, 1e-4}}, {}}, {.flattening_tolerance = 0.1}), Contains("collapses"));
}
