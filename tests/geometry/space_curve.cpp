// geometry/space_curve.hpp: a planar curve gives planar_curve's band map; on a helix the frame is
// rotation-minimising (against the analytic Frenet frame: the normal turns by minus the torsion
// times arc length); the twist turns the frame linearly; closed curves come back to their frame;
// frames are continuous; bad input is refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <tuple>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/geometry/curve.hpp"
#include "fabsynth/geometry/space_curve.hpp"

using namespace fabsynth;

namespace geometry_space_curve_test {

double angle_between(const vec3& a, const vec3& b) { return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)); }

TEST_CASE("space curve: a curve in a plane z = c gives the planar band map", "[geometry][space_curve]") {
    std::vector<vec2> p2;
    for (int i = 0; i <= 60; ++i) p2.push_back({2.0 * i, 15.0 * std::sin(0.11 * i) + 3.0 * std::cos(0.37 * i)});
    for (bool closed : {false, true}) {
        std::vector<vec2> q2 = p2;
        if (closed) {  // a closed loop: the wave and its way back below
            q2.clear();
            for (int i = 0; i < 90; ++i) {
                const double a = 2 * std::numbers::pi * i / 90;
                q2.push_back({40 * std::cos(a) + 4 * std::cos(3 * a), 25 * std::sin(a)});
            }
        }
        std::vector<vec3> p3;
        for (const vec2& q : q2) p3.push_back({q.x, q.y, 3.5});
        const planar_curve flat = planar_curve::polyline(q2, closed);
        const space_curve c = space_curve::polyline(p3, closed);
        INFO((closed ? "closed" : "open"));
        REQUIRE(c.length() == Approx(flat.length()).epsilon(1e-14));
        CHECK(c.min_radius_of_curvature() == Approx(flat.min_radius_of_curvature()).epsilon(1e-9));
        double worst = 0;
        for (int i = 0; i <= 1000; ++i) {
            const double u = c.length() * i / 1000.0;
            for (double v : {-2.0, 0.0, 1.5}) {
                const vec3 a = c.band_point(u, v);
                const vec2 b = flat.band_point(u, v);
                worst = std::max({worst, std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - 3.5)});
            }
            CHECK(glm::length(c.thickness_direction(u) - vec3(0, 0, 1)) < 1e-12);  // the band's thickness is along z
        }
        CHECK(worst < 1e-9);
    }
}

TEST_CASE("space curve: on a helix the frame is rotation-minimising", "[geometry][space_curve]") {
    // x = R cos th, y = R sin th, z = h th; arc length s = th sqrt(R^2 + h^2); torsion tau = h / (R^2 + h^2).
    const double R = 10, h = 3, q = std::sqrt(R * R + h * h), tau = h / (R * R + h * h);
    std::vector<vec3> pts;
    const int n = 4000;
    const double turns = 2;
    for (int i = 0; i <= n; ++i) {
        const double th = 2 * std::numbers::pi * turns * i / n;
        pts.push_back({R * std::cos(th), R * std::sin(th), h * th});
    }
    const space_curve c = space_curve::polyline(pts, false);
    // angle of our normal from the Frenet normal, about the tangent, along the curve
    const auto phi = [&](double s) {
        const double th = s / q;
        const vec3 T = vec3(-R * std::sin(th), R * std::cos(th), h) / q, N(-std::cos(th), -std::sin(th), 0);
        const vec3 nn = c.frame(s).n;
        return std::atan2(glm::dot(glm::cross(N, nn), T), glm::dot(N, nn));
    };
    const double phi0 = phi(0.0);
    double worst = 0, unwrap = 0, prev = 0;
    for (int i = 0; i <= 200; ++i) {
        const double s = c.length() * i / 200.0;
        double d = phi(s) - phi0;
        while (d - prev > std::numbers::pi) d -= 2 * std::numbers::pi;
        while (d - prev < -std::numbers::pi) d += 2 * std::numbers::pi;
        prev = d;
        unwrap = d;
        worst = std::max(worst, std::abs(d + tau * s));
    }
    INFO("normal turned by " << unwrap << " rad about the tangent over " << c.length() << " mm; -tau L = " << -tau * c.length());
    CHECK(worst < 2e-3 * tau * c.length());
    CHECK(std::abs(unwrap) > 1.0);  // the helix twists its Frenet frame: the test is not trivial
    // frames stay orthonormal and continuous
    double jump = 0;
    curve_frame last = c.frame(0);
    for (int i = 1; i <= 20000; ++i) {
        const curve_frame f = c.frame(c.length() * i / 20000.0);
        CHECK(std::abs(glm::dot(f.t, f.n)) < 1e-12);
        CHECK(std::abs(glm::length(f.n) - 1) < 1e-12);
        jump = std::max({jump, angle_between(f.n, last.n), angle_between(f.b, last.b)});
        last = f;
    }
    const double bend = 2 * std::numbers::pi * turns / n * R / q;  // the polyline's turn per vertex
    CHECK(jump < 1.5 * bend);
}

TEST_CASE("space curve: the twist turns the frame linearly about the tangent", "[geometry][space_curve]") {
    std::vector<vec3> line;
    for (int i = 0; i <= 10; ++i) line.push_back({10.0 * i, 0, 0});
    const space_curve c = space_curve::polyline(line, false, {.twist_degrees = 90});
    for (int i = 0; i <= 10; ++i) {
        const double s = 10.0 * i, a = std::numbers::pi / 2 * s / 100;
        const curve_frame f = c.frame(s);
        CHECK(glm::length(f.n - vec3(0, std::cos(a), std::sin(a))) < 1e-12);
        CHECK(glm::length(c.band_point(s, 2.0) - vec3(s, 2 * std::cos(a), 2 * std::sin(a))) < 1e-12);
    }
    // midway along a segment the normal is halfway round
    CHECK(glm::length(c.frame(15).n - vec3(0, std::cos(std::numbers::pi * 0.075), std::sin(std::numbers::pi * 0.075))) < 1e-12);
    // twist 0 on the same line: the normal is up x t = y everywhere
    const space_curve plain = space_curve::polyline(line, false);
    CHECK(glm::length(plain.frame(37).n - vec3(0, 1, 0)) < 1e-15);
}

TEST_CASE("space curve: a closed curve in space comes back to its own frame", "[geometry][space_curve]") {
    std::vector<vec3> saddle;  // a saddle loop: its transported frame has holonomy
    for (int i = 0; i < 240; ++i) {
        const double a = 2 * std::numbers::pi * i / 240;
        saddle.push_back({30 * std::cos(a), 30 * std::sin(a), 12 * std::cos(2 * a) + 5 * std::sin(3 * a)});
    }
    for (double twist : {0.0, 360.0, -720.0}) {
        INFO("twist " << twist);
        const space_curve c = space_curve::polyline(saddle, true, {.twist_degrees = twist});
        const double L = c.length();
        CHECK(glm::length(c.band_point(L, 3.0, 1.0) - c.band_point(0, 3.0, 1.0)) == 0.0);
        CHECK(angle_between(c.frame(L - 1e-6).n, c.frame(1e-6).n) < 0.05);
        CHECK(angle_between(c.frame(L - 1e-6).b, c.frame(1e-6).b) < 0.05);
        double jump = 0;
        curve_frame last = c.frame(0);
        for (int i = 1; i <= 4800; ++i) {
            const curve_frame f = c.frame(L * i / 4800.0);
            jump = std::max(jump, angle_between(f.n, last.n));
            last = f;
        }
        CHECK(jump < 0.1);
    }
}

// A stadium in the plane z = 0: two straight legs 2 r apart, of length `leg`, joined by half
// circles of radius r (counter-clockwise, sampled every ~0.5 mm).
std::vector<vec3> stadium(double r, double leg) {
    std::vector<vec3> p;
    const int nl = static_cast<int>(leg / 0.5), na = static_cast<int>(std::numbers::pi * r / 0.5);
    for (int i = 0; i < nl; ++i) p.push_back({leg * i / nl, -r, 0});
    for (int i = 0; i < na; ++i) {
        const double a = -std::numbers::pi / 2 + std::numbers::pi * i / na;
        p.push_back({leg + r * std::cos(a), r * std::sin(a), 0});
    }
    for (int i = 0; i < nl; ++i) p.push_back({leg - leg * i / nl, r, 0});
    for (int i = 0; i < na; ++i) {
        const double a = std::numbers::pi / 2 + std::numbers::pi * i / na;
        p.push_back({r * std::cos(a), r * std::sin(a), 0});
    }
    return p;
}

TEST_CASE("space curve: distant parts of a band that meet are found, with their distance", "[geometry][space_curve]") {
    // the stadium's band lies in its plane (up = z): the legs' bands face each other across a gap
    // of 2 r - 2 h (the analytic oracle); thickness 1 mm, so samples every 1/8 mm and parts closer
    // than 2.5 / 8 mm count as touching
    const space_curve loop = space_curve::polyline(stadium(10.0, 80.0), true);
    const double t = 1.0;
    for (const double h : {8.0, 9.0}) {  // gaps 4 and 2 mm: clear
        INFO("h " << h);
        CHECK_FALSE(loop.find_self_contact(h, t).has_value());
    }
    const auto tight = loop.find_self_contact(9.9, t);  // gap 0.2 mm: touching
    REQUIRE(tight.has_value());
    CHECK(tight->clearance == Approx(2.5 / 8));
    CHECK(tight->distance <= tight->clearance);
    CHECK(tight->distance >= 0.2 - 1e-9);  // never below the true gap (both samples lie on the band)
    CHECK(std::abs(tight->at.y) < 0.2);     // in the middle of the gap, between the legs
    CHECK(tight->u2 - tight->u1 > std::numbers::pi * 10.0);  // on the two legs, not one
    // a clearance asked for: the 2 mm gap is too narrow for 2.5 mm, wide enough for 1.5 mm
    const auto wide = loop.find_self_contact(9.0, t, 2.5);
    REQUIRE(wide.has_value());
    CHECK(wide->distance >= 2.0 - 1e-9);  // the first pair along the curve: between the gap and the clearance
    CHECK(wide->distance < 2.5);
    CHECK(wide->clearance == 2.5);
    CHECK_FALSE(loop.find_self_contact(9.0, t, 1.5).has_value());

    // a figure eight crossing itself at the origin: the contact is at the crossing, half a loop apart
    std::vector<vec3> eight;
    for (int i = 0; i < 400; ++i) {
        const double a = 2 * std::numbers::pi * i / 400;
        eight.push_back({30 * std::sin(a), 15 * std::sin(2 * a), 0});
    }
    const space_curve e = space_curve::polyline(eight, true);
    const auto x = e.find_self_contact(2.0, t);
    REQUIRE(x.has_value());
    CHECK(glm::length(x->at) < 3.0);
    CHECK(std::abs(x->u2 - x->u1 - 0.5 * e.length()) < 8.0);

    // a helix of radius 10 whose band starts standing along the axis (up = x, so the normal starts
    // along z): turns 20 mm apart keep a band 14 mm high (and 1 mm thick) at least 5 mm apart
    // whatever its turn; turns 6 mm apart do not (the next turn's centre line passes through the
    // first turn's band, 6 mm above its centre)
    for (const double pitch : {20.0, 6.0}) {
        std::vector<vec3> helix;
        for (int i = 0; i <= 240; ++i) {
            const double a = 4 * std::numbers::pi * i / 240;
            helix.push_back({10 * std::cos(a), 10 * std::sin(a), pitch * 2 * i / 240});
        }
        const space_curve c = space_curve::polyline(helix, false, {.up = {1, 0, 0}});
        INFO("pitch " << pitch << ", normal at the start " << c.band_point(0, 1).z - c.band_point(0, 0).z);
        CHECK(c.find_self_contact(7.0, t).has_value() == (pitch < 14.0));
    }
    CHECK_THROWS_AS(loop.find_self_contact(-1.0, t), invalid_input);
    CHECK_THROWS_AS(loop.find_self_contact(1.0, 0.0), invalid_input);
    CHECK_THROWS_AS(loop.find_self_contact(1.0, t, std::nan("")), invalid_input);
}

TEST_CASE("space curve: bad input", "[geometry][space_curve]") {
    const std::vector<vec3> tri{{0, 0, 0}, {10, 0, 0}, {0, 10, 5}};
    CHECK_THROWS_AS(space_curve::polyline({{0, 0, 0}}, false), invalid_input);
    CHECK_THROWS_AS(space_curve::polyline({{0, 0, 0}, {0, 0, 0}}, false), invalid_input);
    CHECK_THROWS_AS(space_curve::polyline({{0, 0, 0}, {1, 0, 0}}, true), invalid_input);
    CHECK_THROWS_AS(space_curve::polyline({{0, 0, 0}, {NAN, 0, 0}}, false), invalid_input);
    CHECK_THROWS_AS(space_curve::polyline({{0, 0, 0}, {10, 0, 0}, {0, 0, 0}}, false), invalid_input);  // turns back
    CHECK_THROWS_AS(space_curve::polyline(tri, true, {.twist_degrees = 90}), invalid_input);          // closed: k * 360 only
    CHECK_THROWS_AS(space_curve::polyline(tri, false, {.twist_degrees = INFINITY}), invalid_input);
    const space_curve c = space_curve::polyline(tri, true);
    CHECK_THROWS_AS(c.check_band(1e6), invalid_input);
    CHECK_THROWS_AS(c.check_band(-1), invalid_input);
    CHECK_NOTHROW(c.check_band(0.1));
    // up along the first tangent: another axis is used, still a unit normal
    const space_curve v = space_curve::polyline({{0, 0, 0}, {0, 0, 10}, {5, 0, 20}}, false);
    CHECK(std::abs(glm::length(v.frame(1).n) - 1) < 1e-12);
}

}  // namespace geometry_space_curve_test

#include "fabsynth/geometry/extrude.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"

namespace geometry_space_curve_extrude_test {

// A band pattern: rectangles across the band with a hole each, v in [-2, 2].
std::vector<polygon_with_holes> band_pattern(double L, int n) {
    std::vector<polygon_with_holes> out;
    for (int i = 0; i < n; ++i) {
        const double u0 = L * (i + 0.1) / n, u1 = L * (i + 0.9) / n, um = 0.5 * (u0 + u1);
        out.push_back({{{u0, -2}, {u1, -2}, {u1, 2}, {u0, 2}}, {{{um - 0.3, -0.5}, {um - 0.3, 0.5}, {um + 0.3, 0.5}, {um + 0.3, -0.5}}}});
    }
    return out;
}

TEST_CASE("space curve extrusion: planar curve and no twist give the planar mesh", "[geometry][space_curve][extrude]") {
    std::vector<vec2> p2;
    std::vector<vec3> p3;
    for (int i = 0; i <= 80; ++i) {
        const vec2 q(1.5 * i, 12.0 * std::sin(0.09 * i));
        p2.push_back(q), p3.push_back({q.x, q.y, -4.0});
    }
    const planar_curve flat = planar_curve::polyline(p2, false);
    const space_curve c = space_curve::polyline(p3, false);
    const auto polys = band_pattern(flat.length(), 9);
    const triangle_mesh a = extrude_along_curve(polys, flat, {.thickness = 1.5});
    const triangle_mesh b = extrude_along_space_curve(polys, c, {.thickness = 1.5});
    REQUIRE(a.faces == b.faces);
    REQUIRE(a.vertices.size() == b.vertices.size());
    double worst = 0;
    for (std::size_t i = 0; i < a.vertices.size(); ++i) worst = std::max(worst, glm::length(a.vertices[i] + vec3(0, 0, -4.0) - b.vertices[i]));
    CHECK(worst < 1e-9);
}

TEST_CASE("space curve extrusion: bands along a helix and a closed saddle are watertight", "[geometry][space_curve][extrude]") {
    std::vector<vec3> helix, saddle;
    for (int i = 0; i <= 600; ++i) {
        const double th = 4 * std::numbers::pi * i / 600;
        helix.push_back({15 * std::cos(th), 15 * std::sin(th), 3 * th});
    }
    for (int i = 0; i < 300; ++i) {
        const double a = 2 * std::numbers::pi * i / 300;
        saddle.push_back({30 * std::cos(a), 30 * std::sin(a), 8 * std::cos(2 * a)});
    }
    for (const auto& [pts, closed, twist] : {std::tuple{helix, false, 180.0}, std::tuple{saddle, true, 360.0}}) {
        const space_curve c = space_curve::polyline(pts, closed, {.twist_degrees = twist});
        // closed: one ring all the way round, cut at the seam (so the two cuts match)
        std::vector<polygon_with_holes> polys = closed ? std::vector<polygon_with_holes>{{{{0, -2}, {c.length(), -2}, {c.length(), 2}, {0, 2}}, {}}}
                                                       : band_pattern(c.length(), 12);
        const triangle_mesh m = extrude_along_space_curve(polys, c, {.thickness = 1.0});
        const mesh_topology_info topo = analyze_topology(m);
        INFO((closed ? "saddle" : "helix") << ": " << m.faces.size() << " faces");
        CHECK(topo.is_watertight());
        CHECK(topo.components == (closed ? 1u : 12u));
        double area = 0;
        for (const auto& p : polys) area += fabsynth::area(p);
        CHECK(signed_volume(m) == Approx(area * 1.0).epsilon(0.02));  // thin band: volume ~ area x thickness
    }
}

TEST_CASE("space curve: given up directions equal to the transport's binormals give the same band", "[geometry][space_curve]") {
    // a curve in the plane z = 2: the rotation-minimising binormal is z everywhere
    std::vector<vec3> p;
    for (int i = 0; i <= 40; ++i) p.push_back({2.0 * i, 12.0 * std::sin(0.15 * i), 2.0});
    const space_curve rmf = space_curve::polyline(p, false);
    const space_curve given = space_curve::with_up_directions(p, std::vector<vec3>(p.size(), vec3(0, 0, 3)), false);
    for (double u = 0; u <= rmf.length(); u += 0.37)
        for (double v : {-4.0, 0.0, 2.5})
            REQUIRE(glm::length(rmf.band_point(u, v, 1.0) - given.band_point(u, v, 1.0)) < 1e-12);
    // a tilted up direction: the band stays orthogonal to it at the vertices
    std::vector<vec3> up(p.size(), glm::normalize(vec3(0.0, -0.3, 1.0)));
    const space_curve tilted = space_curve::with_up_directions(p, up, false);
    for (std::size_t i = 0; i < p.size(); ++i) CHECK(std::abs(glm::dot(tilted.offset_direction(tilted.vertex_arc_lengths()[i]), up[i])) < 1e-12);
    CHECK_THROWS_AS(space_curve::with_up_directions(p, std::vector<vec3>(3, vec3(0, 0, 1)), false), invalid_input);
    CHECK_THROWS_AS(space_curve::with_up_directions(p, std::vector<vec3>(p.size(), vec3(0)), false), invalid_input);
    CHECK_THROWS_AS(space_curve::with_up_directions({{0, 0, 0}, {1, 0, 0}}, {{1, 0, 0}, {1, 0, 0}}, false), invalid_input);  // up along t
}

}  // namespace geometry_space_curve_extrude_test
