// SPDX-License-Identifier: MIT
// Tests of filigree/ffd.hpp and filigree/contact.hpp: the free-form deformation of §8.2 (eqs. 10-14), the
// distortion measure of §4.3.2 and the Fig. 6 contact planner. Geometry oracles (transforms,
// crossings, distances, the distortion by brute force) are written here independently of the
// header.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/filigree/contact.hpp"

namespace ffd_test {

using fabsynth::vec2;
using edge_list = std::vector<std::array<std::uint32_t, 2>>;
constexpr double pi = 3.14159265358979323846;

struct skeleton {
    std::vector<vec2> positions;
    edge_list edges;
};

/// An open polyline through the points.
inline skeleton chain(std::vector<vec2> points) {
    skeleton s{std::move(points), {}};
    for (std::uint32_t i = 1; i < s.positions.size(); ++i) s.edges.push_back({i - 1, i});
    return s;
}

/// n points on the circle (centre c, radius r) from angle a0 to a1 (radians), as a chain.
inline skeleton arc(vec2 c, double r, double a0, double a1, int n) {
    std::vector<vec2> p;
    for (int i = 0; i < n; ++i) {
        const double a = a0 + (a1 - a0) * i / (n - 1);
        p.push_back(c + r * vec2(std::cos(a), std::sin(a)));
    }
    return chain(std::move(p));
}

/// An S-like curve with a junction branch: a test shape of ~20 mm that is not symmetric.
inline skeleton wiggle() {
    std::vector<vec2> p;
    for (int i = 0; i <= 40; ++i) {
        const double t = i / 40.0;
        p.push_back({20.0 * t + 3.0, 6.0 * std::sin(2.0 * pi * t) + 2.0 * t * t + 5.0});
    }
    skeleton s = chain(std::move(p));
    s.positions.push_back({14.0, 15.0});  // a side branch from vertex 20
    s.edges.push_back({20, static_cast<std::uint32_t>(s.positions.size() - 1)});
    return s;
}

/// Deterministic pseudo-random numbers in [0, 1) (a 64-bit LCG).
struct lcg {
    std::uint64_t state = 12345;
    double next() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) / 9007199254740992.0;
    }
};

/// Distortion by brute force: all ordered pairs i != j, mean and std of the distance ratios.
inline double oracle_distortion(const std::vector<vec2>& a, const std::vector<vec2>& b) {
    std::vector<double> ratios;
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < a.size(); ++j) {
            if (i == j) continue;
            const double d = std::hypot(a[i].x - a[j].x, a[i].y - a[j].y);
            if (d == 0.0) continue;
            ratios.push_back(std::hypot(b[i].x - b[j].x, b[i].y - b[j].y) / d);
        }
    double mean = 0.0;
    for (double r : ratios) mean += r;
    mean /= static_cast<double>(ratios.size());
    double var = 0.0;
    for (double r : ratios) var += (r - mean) * (r - mean);
    return std::sqrt(var / static_cast<double>(ratios.size()));
}

inline double cross(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

/// Distance from p to segment [a, b] (written here, not taken from the library).
inline double point_segment(vec2 p, vec2 a, vec2 b) {
    const vec2 ab = b - a;
    double t = ((p.x - a.x) * ab.x + (p.y - a.y) * ab.y) / (ab.x * ab.x + ab.y * ab.y);
    t = std::min(1.0, std::max(0.0, t));
    return std::hypot(p.x - a.x - t * ab.x, p.y - a.y - t * ab.y);
}

/// Points where the edges of s and t cross properly (strictly opposite sides both ways).
inline std::vector<vec2> crossing_points(const skeleton& s, const skeleton& t) {
    std::vector<vec2> out;
    for (const auto& e : s.edges)
        for (const auto& f : t.edges) {
            const vec2 p = s.positions[e[0]], q = s.positions[e[1]], r = t.positions[f[0]], u = t.positions[f[1]];
            const double o1 = cross(q - p, r - p), o2 = cross(q - p, u - p), o3 = cross(u - r, p - r), o4 = cross(u - r, q - r);
            if (o1 * o2 < 0.0 && o3 * o4 < 0.0) out.push_back(r + (u - r) * (o1 / (o1 - o2)));
        }
    return out;
}

/// Number of separate contacts: crossings closer than `merge` mm to an earlier one are the same
/// touching contact (a vertex lying on the other curve is found as two crossings in one point).
inline std::size_t contacts(const std::vector<vec2>& crossings, double merge) {
    std::vector<vec2> kept;
    for (const vec2& c : crossings) {
        bool near = false;
        for (const vec2& k : kept) near = near || std::hypot(c.x - k.x, c.y - k.y) < merge;
        if (!near) kept.push_back(c);
    }
    return kept.size();
}

/// Smallest distance between the edges of s and t (0 if they cross).
inline double min_distance(const skeleton& s, const skeleton& t) {
    if (!crossing_points(s, t).empty()) return 0.0;
    double m = 1e300;
    for (const auto& e : s.edges)
        for (const auto& f : t.edges) {
            const vec2 p = s.positions[e[0]], q = s.positions[e[1]], r = t.positions[f[0]], u = t.positions[f[1]];
            m = std::min({m, point_segment(p, r, u), point_segment(q, r, u), point_segment(r, p, q), point_segment(u, p, q)});
        }
    return m;
}

/// How far the points go inside the circle (centre c, radius r), or outside it if `outside`: the
/// depth by which a curve crosses an arc of that circle (0 if it stays on its side).
inline double depth_across_circle(const std::vector<vec2>& pts, vec2 c, double r, bool outside) {
    double d = 0.0;
    for (const vec2& p : pts) {
        const double signed_distance = std::hypot(p.x - c.x, p.y - c.y) - r;
        d = std::max(d, outside ? signed_distance : -signed_distance);
    }
    return d;
}

/// Largest distance of the points from the line through a with direction dir.
inline double max_off_line(const std::vector<vec2>& pts, vec2 a, vec2 dir) {
    double m = 0.0;
    for (const vec2& p : pts) m = std::max(m, std::abs(cross(dir, p - a)) / std::hypot(dir.x, dir.y));
    return m;
}

inline double max_move(const std::vector<vec2>& a, const std::vector<vec2>& b) {
    double m = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::hypot(a[i].x - b[i].x, a[i].y - b[i].y));
    return m;
}

/// The points of the polyline of data/filigree/spiral.svg (its `points` attribute, parsed here).
inline std::vector<vec2> spiral_points() {
#ifdef FABSYNTH_DATA_DIR
    const std::string dir = FABSYNTH_DATA_DIR;
#else
    const std::string dir = "data";  // run from the repository root
#endif
    std::ifstream in(dir + "/filigree/spiral.svg");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string key = "points=\"";
    const std::size_t begin = text.find(key);
    if (begin == std::string::npos) return {};
    const std::string list = text.substr(begin + key.size(), text.find('"', begin + key.size()) - begin - key.size());
    std::vector<double> numbers;
    std::string token;
    for (const char ch : list + " ") {
        if (ch == ',' || ch == ' ' || ch == '\n' || ch == '\t') {
            if (!token.empty()) numbers.push_back(std::stod(token));
            token.clear();
        } else {
            token += ch;
        }
    }
    std::vector<vec2> p;
    for (std::size_t i = 0; i + 1 < numbers.size(); i += 2) p.push_back({numbers[i], numbers[i + 1]});
    return p;
}

}  // namespace ffd_test

using namespace fabsynth::filigree;
using fabsynth::vec2;

TEST_CASE("ffd: no hard constraints leaves the skeleton unchanged", "[filigree][deformation]") {
    const auto s = ffd_test::wiggle();
    const ffd_result r = ffd_deform(s.positions, s.edges, {});
    REQUIRE(r.positions.size() == s.positions.size());
    CHECK(ffd_test::max_move(r.positions, s.positions) <= 1e-12 * 25.0);
    CHECK(r.distortion <= 1e-12);
    CHECK(r.max_constraint_error == 0.0);
    // Also with other weights and a wide margin, and with no edges at all.
    const ffd_result r2 = ffd_deform(s.positions, s.edges, {}, {.lambda1 = 0.0, .lambda2 = 1.0, .lambda3 = 0.0}, 0.5);
    CHECK(ffd_test::max_move(r2.positions, s.positions) <= 1e-12 * 25.0);
    const ffd_result r3 = ffd_deform(s.positions, {}, {});
    CHECK(ffd_test::max_move(r3.positions, s.positions) <= 1e-12 * 25.0);
}

TEST_CASE("ffd: hard constraints are met and fixed vertices stay put", "[filigree][deformation]") {
    const auto s = ffd_test::wiggle();
    const std::vector<point_constraint> hard{{0, s.positions[0]},                        // fixed
                                             {40, s.positions[40]},                      // fixed
                                             {41, s.positions[41]},                      // fixed (side branch tip)
                                             {10, s.positions[10] + vec2(0.4, -0.3)},    // moved
                                             {30, s.positions[30] + vec2(-0.2, 0.5)}};   // moved
    const ffd_result r = ffd_deform(s.positions, s.edges, hard);
    for (const point_constraint& c : hard) {
        INFO("vertex " << c.vertex);
        CHECK(glm::distance(r.positions[c.vertex], c.target) <= 1e-9);
    }
    CHECK(r.max_constraint_error <= 1e-9);
    CHECK(ffd_test::max_move(r.positions, s.positions) > 0.3);  // the shape did move
    CHECK(r.distortion > 0.0);

    SECTION("16 independent constraints determine the grid: an affine pull is reproduced exactly") {
        // Targets from a mild shear + stretch: the control grid that meets all 16 is the affine
        // image of the rest grid, and so every vertex follows the affine map.
        auto affine = [](vec2 v) { return vec2(1.02 * v.x + 0.03 * v.y + 0.2, -0.01 * v.x + 0.98 * v.y - 0.1); };
        std::vector<point_constraint> many;
        for (std::uint32_t v = 0; v <= 40; v += 3) many.push_back({v, affine(s.positions[v])});
        many.push_back({41, affine(s.positions[41])});
        many.push_back({1, affine(s.positions[1])});
        REQUIRE(many.size() == 16);
        const ffd_result m = ffd_deform(s.positions, s.edges, many);
        CHECK(m.max_constraint_error <= 1e-9);
        for (const point_constraint& c : many) CHECK(glm::distance(m.positions[c.vertex], c.target) <= 1e-9);
        double off = 0.0;
        for (std::size_t v = 0; v < s.positions.size(); ++v) off = std::max(off, glm::distance(m.positions[v], affine(s.positions[v])));
        CHECK(off <= 1e-6);
    }
}

TEST_CASE("ffd: distortion is invariant to rigid motions and zero for uniform scales", "[filigree][deformation]") {
    const auto s = ffd_test::wiggle();
    const std::vector<vec2> before = sample_edges(s.positions, s.edges, 0.5);
    const double a = 0.7, c = std::cos(a), sn = std::sin(a);
    std::vector<vec2> rigid, scaled, rigid_scaled, stretched;
    for (const vec2& p : before) {
        const vec2 q{c * p.x - sn * p.y + 13.0, sn * p.x + c * p.y - 4.0};
        rigid.push_back(q);
        scaled.push_back(2.5 * p - vec2(1.0, 7.0));
        rigid_scaled.push_back(0.6 * q);
        stretched.push_back({1.1 * p.x, p.y});
    }
    CHECK(distortion(before, before) <= 1e-12);
    CHECK(distortion(before, rigid) <= 1e-12);
    CHECK(distortion(before, scaled) <= 1e-12);
    CHECK(distortion(before, rigid_scaled) <= 1e-12);
    CHECK(distortion(before, stretched) > 1e-3);
    // The value depends only on the distance matrices: moving `before` rigidly changes nothing.
    CHECK(distortion(rigid, stretched) == Approx(distortion(before, stretched)).epsilon(1e-10));
}

TEST_CASE("ffd: distortion matches a brute-force oracle", "[filigree][deformation]") {
    ffd_test::lcg rng;
    std::vector<vec2> a, b;
    for (int i = 0; i < 120; ++i) {
        a.push_back({30.0 * rng.next(), 20.0 * rng.next()});
        b.push_back(a.back() + vec2(rng.next() - 0.5, rng.next() - 0.5));
    }
    CHECK(distortion(a, b) == Approx(ffd_test::oracle_distortion(a, b)).epsilon(1e-12));

    SECTION("more points than the cap: the documented even subsample") {
        std::vector<vec2> big_a, big_b;
        for (int i = 0; i < 1000; ++i) {
            big_a.push_back({30.0 * rng.next(), 20.0 * rng.next()});
            big_b.push_back(big_a.back() * vec2(1.0, 1.0 + 0.1 * rng.next()));
        }
        std::vector<vec2> sub_a, sub_b;
        for (std::size_t k = 0; k < distortion_sample_cap; ++k) {
            const std::size_t i = k * (big_a.size() - 1) / (distortion_sample_cap - 1);
            sub_a.push_back(big_a[i]), sub_b.push_back(big_b[i]);
        }
        CHECK(distortion(big_a, big_b) == Approx(ffd_test::oracle_distortion(sub_a, sub_b)).epsilon(1e-12));
    }
}

TEST_CASE("ffd: distortion is positive and grows with a stronger pull", "[filigree][deformation]") {
    const auto s = ffd_test::arc({0.0, 0.0}, 10.0, 0.0, ffd_test::pi * 0.9, 61);
    double previous = 0.0;
    for (const double pull : {0.25, 0.5, 1.0, 2.0}) {
        const std::vector<point_constraint> hard{{0, s.positions[0]}, {60, s.positions[60]}, {30, s.positions[30] * (1.0 + pull / 10.0)}};
        const ffd_result r = ffd_deform(s.positions, s.edges, hard);
        INFO("pull " << pull << " mm: distortion " << r.distortion);
        CHECK(r.max_constraint_error <= 1e-9);
        CHECK(r.distortion > previous);
        previous = r.distortion;
    }
    CHECK(previous > 1e-3);
}

TEST_CASE("ffd: a straight skeleton pulled along itself stays straight", "[filigree][deformation]") {
    const vec2 start{2.0, 3.0}, dir{std::cos(0.5), std::sin(0.5)};
    std::vector<vec2> p;
    for (int i = 0; i <= 20; ++i) p.push_back(start + static_cast<double>(i) * dir);
    const auto s = ffd_test::chain(p);
    SECTION("other end fixed: a uniform stretch about it") {
        // The stretch costs nothing in eq. 14 (tau = 1.025 on every edge), so it is the minimiser.
        const ffd_result r = ffd_deform(s.positions, s.edges, std::vector<point_constraint>{{0, start}, {20, p[20] + 0.5 * dir}});
        CHECK(r.max_constraint_error <= 1e-9);
        CHECK(ffd_test::max_off_line(r.positions, start, dir) <= 1e-6);
        for (int i = 0; i <= 20; ++i) CHECK(glm::distance(r.positions[i], start + 1.025 * (p[i] - start)) <= 1e-4);
        CHECK(r.distortion <= 1e-4);
    }
    SECTION("only the end vertex constrained") {
        const ffd_result r = ffd_deform(s.positions, s.edges, std::vector<point_constraint>{{20, p[20] + 0.5 * dir}});
        CHECK(r.max_constraint_error <= 1e-9);
        CHECK(ffd_test::max_off_line(r.positions, start, dir) <= 1e-6);
        CHECK(r.distortion <= 1e-4);
    }
}

TEST_CASE("ffd: sample_edges lists the vertices then points at most `spacing` apart", "[filigree][deformation]") {
    const auto s = ffd_test::chain({{0.0, 0.0}, {1.0, 0.0}, {1.0, 2.5}});
    const std::vector<vec2> pts = sample_edges(s.positions, s.edges, 0.5);
    REQUIRE(pts.size() == 3 + 1 + 4);  // edge 1 mm -> 2 parts, edge 2.5 mm -> 5 parts
    for (std::size_t i = 0; i < 3; ++i) CHECK(pts[i] == s.positions[i]);
    CHECK(glm::distance(pts[3], vec2(0.5, 0.0)) <= 1e-15);
    for (std::size_t i = 4; i < 8; ++i) CHECK(glm::distance(pts[i], vec2(1.0, 0.5 * static_cast<double>(i - 3))) <= 1e-15);
    CHECK(sample_edges(s.positions, s.edges, 10.0).size() == 3);
}

TEST_CASE("ffd: case 1, two close crossings become a tangential contact", "[filigree][deformation]") {
    // Q: a gentle arc (radius 30) with its top at the origin; P: a small arc (radius 6) whose top
    // pokes 0.05 mm above Q, so P crosses Q twice about 1.7 mm apart. Off-centre, not symmetric.
    const double radius_q = 30.0;
    const auto q = ffd_test::arc({0.0, -radius_q}, radius_q, ffd_test::pi / 2 - 0.4, ffd_test::pi / 2 + 0.4, 201);
    const auto p = ffd_test::arc({0.4, -5.95}, 6.0, ffd_test::pi / 6 + 0.2, 5 * ffd_test::pi / 6, 121);
    REQUIRE(ffd_test::contacts(ffd_test::crossing_points(p, q), 1e-6) == 2);

    const std::vector<std::uint32_t> junctions{0};  // P's first vertex meets another element
    const auto plan = plan_tangent_contact(p.positions, p.edges, q.positions, q.edges, junctions);
    REQUIRE(plan);
    CHECK(plan->kind == contact_case::close_intersections);
    REQUIRE(plan->constraints.size() == 3);  // moving, the junction, the far end
    CHECK(plan->constraints[0].vertex == plan->moving_vertex);
    CHECK(plan->constraints[1].vertex == 0);
    CHECK(plan->constraints[1].target == p.positions[0]);
    CHECK(plan->constraints[2].vertex == 120);  // the far end of P from the contact
    const std::vector<vec2> xs = ffd_test::crossing_points(p, q);
    CHECK(plan->gap == Approx(glm::distance(xs.front(), xs.back())).epsilon(1e-9));
    // The target is on the line through the crossings.
    CHECK(ffd_test::max_off_line({plan->contact}, xs.front(), xs.back() - xs.front()) <= 1e-9);

    const ffd_result r = ffd_deform(p.positions, p.edges, plan->constraints);
    CHECK(r.max_constraint_error <= 1e-9);
    CHECK(glm::distance(r.positions[0], p.positions[0]) <= 1e-9);
    CHECK(glm::distance(r.positions[120], p.positions[120]) <= 1e-9);
    CHECK(r.distortion < default_sigma_d);
    const ffd_test::skeleton moved{r.positions, p.edges};
    // P now touches the chord: no crossing left, and Q is only its sagitta over the chord away.
    CHECK(ffd_test::crossing_points(moved, q).empty());
    const double sagitta = plan->gap * plan->gap / (8.0 * radius_q);
    CHECK(ffd_test::min_distance(moved, q) <= 1.05 * sagitta);

    // That remaining sliver is a narrow gap (case 2): a second pass closes it. P pokes out of Q
    // by a tiny fraction of the first lens; with keep_tangent not at all (one touching contact).
    const double lens = ffd_test::depth_across_circle(p.positions, {0.0, -radius_q}, radius_q, true);
    REQUIRE(lens > 0.04);
    for (const bool keep_tangent : {false, true}) {
        INFO("keep_tangent " << keep_tangent);
        const auto second_plan = plan_tangent_contact(moved.positions, moved.edges, q.positions, q.edges, junctions, {.keep_tangent = keep_tangent});
        REQUIRE(second_plan);
        CHECK(second_plan->kind == contact_case::narrow_gap);
        const auto second = smooth_connection(moved.positions, moved.edges, q.positions, q.edges, junctions, {.keep_tangent = keep_tangent});
        REQUIRE(second);
        const ffd_test::skeleton touching{second->positions, p.edges};
        CHECK(ffd_test::min_distance(touching, q) <= 1e-9);
        CHECK(ffd_test::depth_across_circle(touching.positions, {0.0, -radius_q}, radius_q, true) <= 0.01 * lens);
        if (keep_tangent) CHECK(ffd_test::contacts(ffd_test::crossing_points(touching, q), 1e-6) <= 1);
    }
}

TEST_CASE("ffd: case 2, a narrow gap closes", "[filigree][deformation]") {
    const auto q = ffd_test::arc({0.0, -30.0}, 30.0, ffd_test::pi / 2 - 0.4, ffd_test::pi / 2 + 0.4, 201);
    const auto p = ffd_test::arc({0.5, 6.3}, 6.0, ffd_test::pi + ffd_test::pi / 6, 2 * ffd_test::pi - ffd_test::pi / 6 - 0.3, 101);  // bottom of a circle above Q
    const double before = ffd_test::min_distance(p, q);
    REQUIRE(before == Approx(0.3).margin(0.01));

    const auto plan = plan_tangent_contact(p.positions, p.edges, q.positions, q.edges, {});
    REQUIRE(plan);
    CHECK(plan->kind == contact_case::narrow_gap);
    CHECK(plan->gap == Approx(before).margin(1e-3));
    CHECK(plan->constraints.size() == 2);  // the moving vertex and the far end
    const ffd_result r = ffd_deform(p.positions, p.edges, plan->constraints);
    CHECK(r.max_constraint_error <= 1e-9);
    const ffd_test::skeleton moved{r.positions, p.edges};
    CHECK(ffd_test::min_distance(moved, q) < 1e-6);
    // The paper's single moving point: P may dip into Q by a sliver next to the contact (the
    // deformation turns P's tangent there a little), far below the gap that was closed.
    CHECK(ffd_test::depth_across_circle(moved.positions, {0.0, -30.0}, 30.0, false) <= 0.01 * before);

    SECTION("keep_tangent: the neighbours move along, one touching contact and no crossing") {
        const auto tangent_plan = plan_tangent_contact(p.positions, p.edges, q.positions, q.edges, {}, {.keep_tangent = true});
        REQUIRE(tangent_plan);
        REQUIRE(tangent_plan->constraints.size() == 4);
        CHECK(tangent_plan->moving_vertex == plan->moving_vertex);
        const vec2 shift = tangent_plan->contact - p.positions[plan->moving_vertex];
        for (std::size_t k = 1; k < 3; ++k) {
            const auto v = tangent_plan->constraints[k].vertex;
            CHECK((v + 1 == plan->moving_vertex || v == plan->moving_vertex + 1));
            CHECK(glm::distance(tangent_plan->constraints[k].target, p.positions[v] + shift) <= 1e-12);
        }
        const ffd_result t = ffd_deform(p.positions, p.edges, tangent_plan->constraints);
        const ffd_test::skeleton touching{t.positions, p.edges};
        CHECK(ffd_test::min_distance(touching, q) < 1e-6);
        CHECK(ffd_test::contacts(ffd_test::crossing_points(touching, q), 1e-6) <= 1);
        INFO("depth " << ffd_test::depth_across_circle(touching.positions, {0.0, -30.0}, 30.0, false));
        CHECK(ffd_test::depth_across_circle(touching.positions, {0.0, -30.0}, 30.0, false) <= 1e-4);
    }

    // smooth_connection gives the same deformation when accepted, nothing when sigma_d is tiny.
    const auto accepted = smooth_connection(p.positions, p.edges, q.positions, q.edges, {});
    REQUIRE(accepted);
    CHECK(ffd_test::max_move(accepted->positions, r.positions) == 0.0);
    CHECK_FALSE(smooth_connection(p.positions, p.edges, q.positions, q.edges, {}, {}, {}, r.distortion * 0.5));
}

TEST_CASE("ffd: case 1 on a closed loop whose crossings straddle its first vertex", "[filigree][deformation]") {
    const auto q = ffd_test::arc({0.0, -30.0}, 30.0, ffd_test::pi / 2 - 0.4, ffd_test::pi / 2 + 0.4, 201);
    const int n = 120;  // a full circle starting at its top, which pokes 0.05 mm above Q
    std::vector<vec2> ring;
    for (int k = 0; k < n; ++k) {
        const double angle = ffd_test::pi / 2 + 2 * ffd_test::pi * k / n;
        ring.push_back(vec2(0.4, -5.95) + 6.0 * vec2(std::cos(angle), std::sin(angle)));
    }
    ffd_test::skeleton p = ffd_test::chain(ring);
    p.edges.push_back({n - 1, 0});
    REQUIRE(ffd_test::crossing_points(p, q).size() == 2);
    const auto plan = plan_tangent_contact(p.positions, p.edges, q.positions, q.edges, {});
    REQUIRE(plan);
    CHECK(plan->kind == contact_case::close_intersections);
    CHECK((plan->moving_vertex == 0 || plan->moving_vertex == 1 || plan->moving_vertex == n - 1));
    CHECK(plan->constraints.size() == 2);
    CHECK(plan->constraints[1].vertex == 60);  // the bottom of the loop, farthest from the contact
    const ffd_result r = ffd_deform(p.positions, p.edges, plan->constraints);
    CHECK(r.max_constraint_error <= 1e-9);
    CHECK(ffd_test::crossing_points({r.positions, p.edges}, q).empty());
}

TEST_CASE("ffd: the planner finds nothing without a close contact and respects fixed vertices", "[filigree][deformation]") {
    const auto q = ffd_test::arc({0.0, -30.0}, 30.0, ffd_test::pi / 2 - 0.4, ffd_test::pi / 2 + 0.4, 201);
    // Far away: no contact.
    const auto far = ffd_test::arc({0.0, 10.0}, 6.0, ffd_test::pi + 0.5, 2 * ffd_test::pi - 0.5, 61);
    CHECK_FALSE(plan_tangent_contact(far.positions, far.edges, q.positions, q.edges, {}));
    // One crossing only: neither case.
    const auto once = ffd_test::chain({{-1.0, -2.0}, {0.0, 0.0}, {1.0, 2.0}});
    CHECK_FALSE(plan_tangent_contact(once.positions, once.edges, q.positions, q.edges, {}));
    // Crossings farther apart than max_intersection_gap: no case 1.
    const auto p = ffd_test::arc({0.4, -5.95}, 6.0, ffd_test::pi / 6 + 0.2, 5 * ffd_test::pi / 6, 121);
    CHECK_FALSE(plan_tangent_contact(p.positions, p.edges, q.positions, q.edges, {}, {.max_intersection_gap = 1.0}));
    // Fixed vertices never move: fixing the natural choice makes the planner take another vertex.
    const auto plan = plan_tangent_contact(p.positions, p.edges, q.positions, q.edges, {});
    REQUIRE(plan);
    const std::vector<std::uint32_t> fixed{plan->moving_vertex};
    const auto other = plan_tangent_contact(p.positions, p.edges, q.positions, q.edges, fixed, {.pin_far_end = false});
    REQUIRE(other);
    CHECK(other->moving_vertex != plan->moving_vertex);
    REQUIRE(other->constraints.size() == 2);
    CHECK(other->constraints[1].vertex == plan->moving_vertex);
    CHECK(other->constraints[1].target == p.positions[plan->moving_vertex]);
}

TEST_CASE("ffd: pulling the outer end of spiral.svg", "[filigree][deformation]") {
    const std::vector<vec2> pts = ffd_test::spiral_points();
    REQUIRE(pts.size() > 100);
    const auto s = ffd_test::chain(pts);
    const auto last = static_cast<std::uint32_t>(pts.size() - 1);
    // Pull the outer end 0.5 mm along the curve's normal, keeping the inner end still.
    const vec2 t = glm::normalize(pts[last] - pts[last - 1]);
    const vec2 target = pts[last] + 0.5 * vec2(-t.y, t.x);
    const ffd_result r = ffd_deform(s.positions, s.edges, std::vector<point_constraint>{{0, pts[0]}, {last, target}});
    CHECK(glm::distance(r.positions[last], target) <= 1e-9);
    CHECK(glm::distance(r.positions[0], pts[0]) <= 1e-9);
    CHECK(r.max_constraint_error <= 1e-9);
    INFO("distortion " << r.distortion);
    CHECK(r.distortion > 0.0);
    CHECK(r.distortion < 0.15);
}

TEST_CASE("ffd: bad input throws, naming the culprit", "[filigree][deformation]") {
    using Catch::Matchers::Contains;
    using fabsynth::invalid_input;
    using fabsynth::solver_error;
    const auto s = ffd_test::wiggle();
    const auto& x = s.positions;
    using hard_list = std::vector<point_constraint>;
    CHECK_THROWS_MATCHES(ffd_deform(x, s.edges, hard_list{{99, {0.0, 0.0}}}), invalid_input, Catch::Matchers::Message(
        "fabsynth: ffd_deform: hard[0] constrains vertex 99, out of range for 42 vertices"));
    CHECK_THROWS_WITH(ffd_deform(x, s.edges, hard_list{{1, x[1]}, {5, x[5]}, {1, x[1]}}), Contains("hard[0] and hard[2]") && Contains("duplicate"));
    CHECK_THROWS_WITH(ffd_deform(x, s.edges, hard_list{{3, x[3]}, {3, x[4]}}), Contains("vertex 3") && Contains("contradictory"));
    CHECK_THROWS_AS(ffd_deform(x, s.edges, hard_list{{3, x[3]}, {3, x[4]}}), invalid_input);
    CHECK_THROWS_WITH(ffd_deform(x, s.edges, hard_list{{2, {std::nan(""), 0.0}}}), Contains("hard[0]") && Contains("non-finite"));
    std::vector<vec2> bad = x;
    bad[7].y = INFINITY;
    CHECK_THROWS_WITH(ffd_deform(bad, s.edges, {}), Contains("positions[7]"));
    CHECK_THROWS_AS(ffd_deform(std::vector<vec2>{}, ffd_test::edge_list{}, {}), invalid_input);
    ffd_test::edge_list loops = s.edges;
    loops.push_back({4, 4});
    CHECK_THROWS_WITH(ffd_deform(x, loops, {}), Contains("edges[41]") && Contains("self loop"));
    loops.back() = {4, 400};
    CHECK_THROWS_WITH(ffd_deform(x, loops, {}), Contains("edges[41]") && Contains("vertex 400"));
    CHECK_THROWS_WITH(ffd_deform(x, s.edges, {}, {.lambda2 = -1.0}), Contains("lambda2"));
    CHECK_THROWS_WITH(ffd_deform(x, s.edges, {}, {}, 0.0), Contains("margin"));

    // More than 16 constraints: the 17th is dependent on the others.
    hard_list many;
    for (std::uint32_t v = 0; v < 17; ++v) many.push_back({2 * v, x[2 * v]});
    CHECK_THROWS_AS(ffd_deform(x, s.edges, many), solver_error);
    CHECK_THROWS_WITH(ffd_deform(x, s.edges, many), Contains("hard[16] (vertex 32)"));
    // Two vertices in one place pulled apart: contradictory, singular.
    std::vector<vec2> twin = x;
    twin[41] = twin[20];
    const hard_list apart{{20, x[20]}, {41, x[20] + vec2(1.0, 0.0)}};
    CHECK_THROWS_AS(ffd_deform(twin, s.edges, apart), solver_error);
    CHECK_THROWS_WITH(ffd_deform(twin, s.edges, apart), Contains("hard[1] (vertex 41)"));

    CHECK_THROWS_WITH(distortion(std::vector<vec2>(3), std::vector<vec2>(4)), Contains("before has 3 points, after 4"));
    CHECK_THROWS_AS(distortion(std::vector<vec2>(3), bad), invalid_input);
    CHECK_THROWS_WITH(sample_edges(x, s.edges, 0.0), Contains("spacing"));
    CHECK_THROWS_WITH(sample_edges(x, s.edges, 1e-12), Contains("2^26"));
    CHECK_THROWS_WITH(plan_tangent_contact(x, s.edges, x, s.edges, std::vector<std::uint32_t>{50}), Contains("fixed_vertices[0] = 50"));
    CHECK_THROWS_WITH(plan_tangent_contact(x, s.edges, x, s.edges, {}, {.max_gap = -1.0}), Contains("max_gap"));
    CHECK_THROWS_WITH(plan_tangent_contact(x, s.edges, bad, s.edges, {}), Contains("q_positions[7]"));
    CHECK_THROWS_WITH(smooth_connection(x, s.edges, x, s.edges, {}, {}, {}, 0.0), Contains("sigma_d"));
}
