// surface/disk_parameterization.hpp and surface/curve.hpp: a planar disk maps by a
// similarity (cotangent weights reproduce linear functions); the vase maps bijectively onto the
// circle and the square; on a plane mesh the surface curve is the planar spline (against a
// Hermite-form centripetal Catmull-Rom written here) with every mesh edge it crosses (against a
// brute-force count); on the vase every vertex and every segment lies on the mesh, the control
// points are interpolated and the smoothed frames are continuous; bad input is refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/surface/disk_parameterization.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/segment.hpp"
#include "fabsynth/surface/curve.hpp"
#include "fabsynth/io/mesh.hpp"
#include "support/sphere_mesh.hpp"

using namespace fabsynth;

namespace geometry_surface_curve_test {

// A flat n x n grid of cell h in z = 0 with its interior vertices jittered (the border straight).
triangle_mesh flat_disk(int n, double h, std::uint64_t seed, double jitter = 0.2) { return fabsynth::test::plane_grid(n, h, seed, jitter, false); }

triangle_mesh vase() { return io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/vase.obj"); }

// Points on the vase's profile r(z) = 20 + 9 sin(pi z / 70) (scripts/make_vase.py).
vec3 on_vase(double angle, double z) {
    const double r = 20 + 9 * std::sin(std::numbers::pi * z / 70);
    return {r * std::cos(angle), r * std::sin(angle), z};
}

// Proper crossing of segments ab and cd (strict signs: the oracle of the crossing count).
bool cross(vec2 a, vec2 b, vec2 c, vec2 d) {
    const auto side = [](vec2 p, vec2 q, vec2 r) { return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x); };
    const double s1 = side(a, b, c), s2 = side(a, b, d), s3 = side(c, d, a), s4 = side(c, d, b);
    return ((s1 > 0 && s2 < 0) || (s1 < 0 && s2 > 0)) && ((s3 > 0 && s4 < 0) || (s3 < 0 && s4 > 0));
}

double angle_between(const vec3& a, const vec3& b) { return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)); }

// Centripetal Catmull-Rom in Hermite form (the tangents of Yuksel, Schaefer & Keyser 2011), open
// ends by reflection: the oracle for the planar case, independent of the library's pyramid form.
struct hermite_spline {
    std::vector<vec2> c;
    [[nodiscard]] vec2 at(std::size_t k, double a) const {
        const auto p = [&](long i) -> vec2 {
            const long n = static_cast<long>(c.size());
            if (i < 0) return 2.0 * c[0] - c[1];
            if (i >= n) return 2.0 * c[static_cast<std::size_t>(n - 1)] - c[static_cast<std::size_t>(n - 2)];
            return c[static_cast<std::size_t>(i)];
        };
        const vec2 p0 = p(static_cast<long>(k) - 1), p1 = p(static_cast<long>(k)), p2 = p(static_cast<long>(k) + 1), p3 = p(static_cast<long>(k) + 2);
        const double d0 = std::sqrt(glm::length(p1 - p0)), d1 = std::sqrt(glm::length(p2 - p1)), d2 = std::sqrt(glm::length(p3 - p2));
        const vec2 m1 = ((p1 - p0) / d0 - (p2 - p0) / (d0 + d1) + (p2 - p1) / d1) * d1;
        const vec2 m2 = ((p2 - p1) / d1 - (p3 - p1) / (d1 + d2) + (p3 - p2) / d2) * d1;
        const double a2 = a * a, a3 = a2 * a;
        return (2 * a3 - 3 * a2 + 1) * p1 + (a3 - 2 * a2 + a) * m1 + (-2 * a3 + 3 * a2) * p2 + (a3 - a2) * m2;
    }
};

// A flat 60 mm square grid graded in x and y (x = 60 (t + 0.1 sin 2 pi t), t = i / n): every
// triangle has a right angle, so the cotangent weights of the diagonals are exactly 0 and none is
// clamped; linear precision then makes the map a similarity.
triangle_mesh graded_square(int n) {
    triangle_mesh m = flat_disk(n, 60.0 / n, 0, 0.0);
    const auto grade = [](double x) { const double t = x / 60.0; return 60.0 * (t + 0.1 * std::sin(2 * std::numbers::pi * t)); };
    for (vec3& p : m.vertices) p = {grade(p.x), grade(p.y), 0.0};
    return m;
}

TEST_CASE("disk parameterization: a planar disk maps onto the square by a similarity", "[geometry][surface_curve]") {
    const triangle_mesh m = graded_square(12);
    const disk_parameterization phi(m, {.border = parameterization_border::square});
    const auto& uv = phi.domain_vertices();
    // corner vertex 0 starts the loop at (1, -1); the bottom side runs up the right side: a quarter turn
    for (std::size_t v = 0; v < uv.size(); ++v) {
        const vec3& p = m.vertices[v];
        const vec2 expect{1.0 - 2.0 * p.y / 60.0, -1.0 + 2.0 * p.x / 60.0};
        REQUIRE(glm::length(uv[v] - expect) < 1e-12);
    }
    CHECK(phi.boundary().size() == 48);
}

TEST_CASE("disk parameterization: the vase onto the circle and the square is bijective", "[geometry][surface_curve]") {
    const triangle_mesh m = vase();
    for (auto border : {parameterization_border::circle, parameterization_border::square}) {
        const disk_parameterization phi(m, {.border = border});
        const auto& uv = phi.domain_vertices();
        double faces_area = 0.0, loop_area = 0.0;
        for (const auto& t : m.faces) {
            const double a = orient2d(uv[t[0]], uv[t[1]], uv[t[2]]) / 2;
            REQUIRE(a > 0.0);
            faces_area += a;
        }
        const auto& b = phi.boundary();
        for (std::size_t i = 0; i < b.size(); ++i) loop_area += (uv[b[i]].x * uv[b[(i + 1) % b.size()]].y - uv[b[(i + 1) % b.size()]].x * uv[b[i]].y) / 2;
        for (std::uint32_t v : b) CHECK((border == parameterization_border::circle ? std::abs(glm::length(uv[v]) - 1.0) : std::abs(std::max(std::abs(uv[v].x), std::abs(uv[v].y)) - 1.0)) < 1e-12);
        // counter-clockwise faces covering the loop's area exactly: no fold, no overlap
        CHECK(faces_area == Approx(loop_area).epsilon(1e-12));
        // round trip: face + barycentrics -> domain -> locate -> the same surface point
        counter_rng rng(11);
        for (int k = 0; k < 2000; ++k) {
            const auto f = static_cast<std::uint32_t>(rng.uniform(0.0, static_cast<double>(m.faces.size()) - 1e-9));
            vec3 bc{rng.uniform(0.01, 1.0), rng.uniform(0.01, 1.0), rng.uniform(0.01, 1.0)};
            bc /= bc.x + bc.y + bc.z;
            const auto at = phi.locate(phi.domain_point(f, bc));
            REQUIRE(at);
            REQUIRE(glm::length(phi.surface_point(at->face, at->bary) - phi.surface_point(f, bc)) < 1e-9);
        }
        CHECK_FALSE(phi.locate({1.01, 1.01}));
    }
}

TEST_CASE("disk parameterization: meshes that are not disks are refused", "[geometry][surface_curve]") {
    CHECK_THROWS_AS(disk_parameterization(fabsynth::test::sphere_mesh(10, 2)), invalid_input);        // closed
    CHECK_THROWS_AS(disk_parameterization(fabsynth::test::cylinder(10, 20, 24, 2)), invalid_input);  // two boundary loops
    triangle_mesh two = flat_disk(3, 1.0, 1);
    const triangle_mesh other = flat_disk(3, 1.0, 2);
    const auto off = static_cast<std::uint32_t>(two.vertices.size());
    for (vec3 p : other.vertices) two.vertices.push_back(p + vec3(10, 0, 0));
    for (auto t : other.faces) two.faces.push_back({t[0] + off, t[1] + off, t[2] + off});
    CHECK_THROWS_AS(disk_parameterization(two), invalid_input);
    CHECK_THROWS_AS(disk_parameterization(triangle_mesh{}), invalid_input);
    // a closed sphere cut open at a vertex: a disk whose border is the vertex's link
    const triangle_mesh sphere = fabsynth::test::sphere_mesh(10, 3);
    const triangle_mesh opened = cut_open(sphere, 7);
    const mesh_topology_info info = analyze_topology(opened);
    CHECK(info.boundary_loops == 1);
    CHECK(info.euler == 1);
    CHECK(opened.vertices.size() == sphere.vertices.size() - 1);
    const disk_parameterization phi(opened);
    std::size_t valence = 0;
    for (const auto& t : sphere.faces) valence += t[0] == 7 || t[1] == 7 || t[2] == 7;
    CHECK(phi.boundary().size() == valence);
    CHECK_THROWS_AS(cut_open(sphere, static_cast<std::uint32_t>(sphere.vertices.size())), invalid_input);
}

TEST_CASE("surface curve: on a plane mesh the curve is the planar spline with every edge crossing", "[geometry][surface_curve]") {
    const triangle_mesh m = graded_square(25);  // Phi is a similarity (the test above)
    const disk_parameterization phi(m, {.border = parameterization_border::square});
    const std::vector<vec3> control{{6.3, 7.1, 0}, {24.2, 18.5, 0}, {33.0, 42.3, 0}, {48.1, 36.2, 0}, {53.7, 12.4, 0}};
    const surface_curve s = trace_surface_curve(phi, control, false, {.spacing = 1.5});
    REQUIRE(s.points.size() == s.segment_faces.size() + 1);
    // the control points are on the curve (interpolating spline)
    for (const vec3& c : control) {
        double best = 1e9;
        for (const vec3& p : s.points) best = std::min(best, glm::length(p - c));
        CHECK(best < 1e-9);
    }
    hermite_spline oracle{{}};
    for (const vec3& c : control) oracle.c.push_back({c.x, c.y});
    std::vector<vec2> dense;
    for (std::size_t k = 0; k + 1 < oracle.c.size(); ++k)
        for (int i = 0; i <= 20000; ++i) dense.push_back(oracle.at(k, i / 20000.0));
    for (const vec3& p : s.points) REQUIRE(p.z == 0.0);
    // every segment is inside its face (its midpoint's barycentrics are >= 0)
    for (std::size_t k = 0; k < s.segment_faces.size(); ++k) {
        const auto& t = m.faces[s.segment_faces[k]];
        const vec3 mid = 0.5 * (s.points[k] + s.points[k + 1]);
        const vec3 b = barycentric(mid, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
        REQUIRE(std::min({b.x, b.y, b.z}) > -1e-9);
    }
    // the crossings are exactly the intersections of the non-crossing points' polyline with the edges
    std::vector<vec2> samples;
    std::size_t on_edges = 0;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const auto& t : m.faces)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>((e + 1) % 3)];
            if (a < b || phi.neighbour(static_cast<std::uint32_t>(&t - m.faces.data()), e) == disk_parameterization::no_face) edges.push_back({a, b});
        }
    for (const vec3& p : s.points) {
        bool on_edge = false;
        for (auto [a, b] : edges)
            if (segment_distance(p, m.vertices[a], m.vertices[b]) < 1e-9) on_edge = true;
        if (on_edge) ++on_edges;
        else samples.push_back({p.x, p.y});
    }
    std::size_t brute = 0;
    for (std::size_t i = 0; i + 1 < samples.size(); ++i)
        for (auto [a, b] : edges) brute += cross(samples[i], samples[i + 1], vec2(m.vertices[a]), vec2(m.vertices[b]));
    CHECK(s.edge_crossings == on_edges);
    CHECK(on_edges == brute);
    // the other points are samples of the spline: on the oracle within its dense sampling's sag
    double worst = 0.0;
    for (const vec2& p : samples) {
        double best = 1e9;
        for (std::size_t i = 0; i + 1 < dense.size(); ++i) best = std::min(best, segment_distance(p, dense[i], dense[i + 1]));
        worst = std::max(worst, best);
    }
    CHECK(worst < 1e-6);
    CHECK(samples.size() > 40);
    CHECK(brute > 50);
}

TEST_CASE("surface curve: on the vase every vertex and segment is on the mesh, frames are smooth", "[geometry][surface_curve]") {
    const triangle_mesh m = vase();
    const disk_parameterization phi(m);
    const mesh_distance md(m);
    const double size = glm::length(bounding_box(m).size());
    std::vector<vec3> loop, climb;
    for (int i = 0; i < 8; ++i) loop.push_back(on_vase(2 * std::numbers::pi * i / 8, 45 + 6 * std::sin(4 * std::numbers::pi * i / 8)));
    for (int i = 0; i < 6; ++i) climb.push_back(on_vase(0.3 * i, 10 + 13 * i));
    for (bool closed : {true, false}) {
        INFO((closed ? "closed loop" : "open climb"));
        const surface_curve s = trace_surface_curve(phi, closed ? loop : climb, closed);
        const std::size_t n = s.points.size();
        REQUIRE(s.segment_faces.size() == (closed ? n : n - 1));
        REQUIRE(s.normals.size() == n);
        CHECK(s.edge_crossings > 100);
        double far = 0.0, mid_far = 0.0, step = 0.0, facet_step = 0.0, off_surface = 0.0;
        for (std::size_t i = 0; i < n; ++i) far = std::max(far, std::sqrt(md.closest(s.points[i]).dist2));
        for (std::size_t k = 0; k < s.segment_faces.size(); ++k) {
            const vec3 a = s.points[k], b = s.points[(k + 1) % n];
            for (double t : {0.25, 0.5, 0.75}) mid_far = std::max(mid_far, std::sqrt(md.closest(a + t * (b - a)).dist2));
            off_surface = std::max(off_surface, angle_between(s.normals[k], face_normal_area2(m, s.segment_faces[k])));
            if (k > 0) facet_step = std::max(facet_step, angle_between(face_normal_area2(m, s.segment_faces[k]), face_normal_area2(m, s.segment_faces[k - 1])));
        }
        for (std::size_t i = 0; i + 1 < n; ++i) step = std::max(step, angle_between(s.normals[i], s.normals[i + 1]));
        CHECK(far < 1e-9 * size);
        CHECK(mid_far < 1e-9 * size);
        CHECK(off_surface < 8.0 * std::numbers::pi / 180);  // the smoothed normal stays near the surface's
        // continuity: between consecutive points the normal turns at most as the surface bends
        // (principal radii of the vase >= 20 mm), plus a little for the kinks of the polyline
        double worst_rate = 0.0;
        for (std::size_t i = 0; i + 1 < n; ++i) {
            const double len = glm::length(s.points[i + 1] - s.points[i]);
            worst_rate = std::max(worst_rate, angle_between(s.normals[i], s.normals[i + 1]) - len / 20.0);
        }
        INFO("largest normal step " << step * 180 / std::numbers::pi << " deg, facets " << facet_step * 180 / std::numbers::pi << ", excess " << worst_rate);
        CHECK(worst_rate < 0.2 * std::numbers::pi / 180);
        CHECK(step < 3.0 * std::numbers::pi / 180);
        // normals are unit and orthogonal to the curve
        for (std::size_t i = 0; i + 1 < n; ++i) {
            REQUIRE(std::abs(glm::length(s.normals[i]) - 1.0) < 1e-12);
            REQUIRE(std::abs(glm::dot(s.normals[i], glm::normalize(s.points[i + 1] - s.points[i]))) < 0.1);
        }
        // the control points are on the curve
        for (const vec3& c : closed ? loop : climb) {
            double best = 1e9;
            for (const vec3& p : s.points) best = std::min(best, glm::length(p - md.closest(c).point));
            CHECK(best < 1e-9 * size);
        }
        // the band at its own scale: thinned points give a band whose radius is the curve's
        const space_curve band = s.band_curve(1.0);
        CHECK(band.min_radius_of_curvature() > 6.0);
        CHECK(band.length() == Approx(s.band_curve().length()).epsilon(2e-3));
        for (const vec3& p : band.vertices()) REQUIRE(std::sqrt(md.closest(p).dist2) < 1e-9 * size);
    }
}

TEST_CASE("surface curve: bad input is refused", "[geometry][surface_curve]") {
    const triangle_mesh m = flat_disk(10, 10.0, 5);
    const disk_parameterization phi(m);
    const std::vector<vec3> ok{{20, 20, 0}, {50, 60, 0}, {80, 30, 0}};
    CHECK_THROWS_AS(trace_surface_curve(phi, std::vector<vec3>{{20, 20, 0}}, false), invalid_input);
    CHECK_THROWS_AS(trace_surface_curve(phi, std::vector<vec3>{{20, 20, 0}, {30, 30, 0}}, true), invalid_input);
    CHECK_THROWS_AS(trace_surface_curve(phi, std::vector<vec3>{{20, 20, 0}, {50, 60, 30}}, false), invalid_input);  // 30 mm off the mesh
    CHECK_THROWS_AS(trace_surface_curve(phi, std::vector<vec3>{{20, 20, 0}, {NAN, 60, 0}}, false), invalid_input);
    CHECK_THROWS_AS(trace_surface_curve(phi, ok, false, {.spacing = -1}), invalid_input);
    // a sharp turn next to the border: the spline overshoots past the corner and leaves the mesh
    CHECK_THROWS_AS(trace_surface_curve(phi, std::vector<vec3>{{5, 50, 0}, {99.5, 0.5, 0}, {50, 5, 0}}, false), invalid_input);
    CHECK_NOTHROW(trace_surface_curve(phi, ok, false));
}

}  // namespace geometry_surface_curve_test
