// surface/curve_region.hpp: on a jittered plane the region of a closed curve holds every face
// whose centroid a point-in-polygon test (written here) puts inside, and nothing outside, both up
// to a band about one face wide along the curve; on a sphere a circle of latitude gives the smaller cap, with the cap's closed-form
// area up to the traced band; one run per orientation and start point gives the same faces; bad
// curves are named.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <numbers>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/surface/curve_region.hpp"
#include "support/sphere_mesh.hpp"

namespace curve_region_test {

using namespace fabsynth;

// Crossing-number test of (x, y) against a closed polygon.
bool inside_polygon(const std::vector<vec3>& poly, double x, double y) {
    bool in = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
        if ((poly[i].y > y) != (poly[j].y > y) && x < (poly[j].x - poly[i].x) * (y - poly[i].y) / (poly[j].y - poly[i].y) + poly[i].x) in = !in;
    return in;
}

double distance_to_polyline(const std::vector<vec3>& poly, const vec3& p) {
    double best = 1e300;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const vec3 a = poly[i], b = poly[(i + 1) % poly.size()];
        const double t = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
        best = std::min(best, glm::length(a + t * (b - a) - p));
    }
    return best;
}

double area_of(const triangle_mesh& m, const std::vector<std::uint32_t>& faces) {
    double a = 0;
    for (const std::uint32_t f : faces) {
        const auto& c = m.faces[f];
        a += 0.5 * glm::length(glm::cross(m.vertices[c[1]] - m.vertices[c[0]], m.vertices[c[2]] - m.vertices[c[0]]));
    }
    return a;
}

TEST_CASE("faces_inside_curve on a plane: the faces the curve encloses, to within one face", "[geometry][curve_region]") {
    const double h = 1.0;
    const triangle_mesh m = test::plane_grid(40, h, 3);
    // an L-shaped outline (not convex), points slightly above the plane
    const std::vector<vec3> curve{{8.3, 7.1, 0.2}, {30.2, 8.4, 0.2}, {29.6, 20.3, 0.2}, {19.1, 19.7, 0.2}, {18.4, 31.5, 0.2}, {7.7, 30.9, 0.2}};
    const std::vector<std::uint32_t> faces = faces_inside_curve(m, curve, 1.0);
    std::vector<std::uint8_t> in(m.faces.size(), 0);
    for (const std::uint32_t f : faces) in[f] = 1;
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
        const auto& c = m.faces[f];
        const vec3 centroid = (m.vertices[c[0]] + m.vertices[c[1]] + m.vertices[c[2]]) / 3.0;
        const bool inside = inside_polygon(curve, centroid.x, centroid.y);
        const double near = distance_to_polyline(curve, vec3(centroid.x, centroid.y, 0.2));
        INFO("face " << f << " centroid (" << centroid.x << ", " << centroid.y << "), " << near << " mm from the curve");
        if (inside && near > 1.5 * h) CHECK(in[f]);    // nothing enclosed is missing, but at the traced band
        if (in[f] && !inside) CHECK(near < 2.0 * h);   // what lies outside is on the traced band
    }
    // the L's area (22 x 12.5 + 11 x 11.5, about 400 mm^2) up to a band one face wide along its 90 mm outline
    double shoelace = 0;
    for (std::size_t i = 0; i < curve.size(); ++i) {
        const vec3 a = curve[i], b = curve[(i + 1) % curve.size()];
        shoelace += a.x * b.y - b.x * a.y;
    }
    const double perimeter = [&] {
        double p = 0;
        for (std::size_t i = 0; i < curve.size(); ++i) p += glm::length(curve[(i + 1) % curve.size()] - curve[i]);
        return p;
    }();
    CHECK(std::abs(area_of(m, faces) - 0.5 * std::abs(shoelace)) < perimeter * 1.5 * h);
    // the same curve reversed and started elsewhere encloses the same faces
    std::vector<vec3> other(curve.rbegin(), curve.rend());
    std::rotate(other.begin(), other.begin() + 2, other.end());
    CHECK(faces_inside_curve(m, other, 1.0) == faces);
}

TEST_CASE("faces_inside_curve on a sphere: a circle of latitude gives the smaller cap", "[geometry][curve_region]") {
    const double r = 20.0;
    const triangle_mesh m = test::sphere_mesh(r, 5);  // 8192 faces, edges about 1.2 mm
    for (const double polar : {0.5, 1.2, 2.4}) {      // the cap around +z for polar < pi/2, around -z beyond
        INFO("polar angle " << polar);
        std::vector<vec3> circle;
        for (int k = 0; k < 24; ++k) {
            const double a = 2 * std::numbers::pi * k / 24;
            circle.push_back(vec3(r * std::sin(polar) * std::cos(a), r * std::sin(polar) * std::sin(a), r * std::cos(polar)));
        }
        const std::vector<std::uint32_t> faces = faces_inside_curve(m, circle, 1.0);
        const double small_polar = std::min(polar, std::numbers::pi - polar);
        const double cap = 2 * std::numbers::pi * r * r * (1 - std::cos(small_polar));
        const double band = 2 * std::numbers::pi * r * std::sin(small_polar) * 2.5;  // the circle's length times a face width and more
        CHECK(std::abs(area_of(m, faces) - cap) < band);
        const double pole_z = polar < std::numbers::pi / 2 ? r : -r;
        for (const std::uint32_t f : faces)  // every face is on the pole's side of the circle, up to the band
            for (const std::uint32_t v : m.faces[f]) CHECK(m.vertices[v].z * pole_z > (r * std::cos(small_polar) - 2.0) * r);
    }
}

TEST_CASE("faces_inside_curve names a bad curve", "[geometry][curve_region][errors]") {
    const triangle_mesh m = test::plane_grid(10, 1.0, 1);
    auto fails = [&](const std::vector<vec3>& c, const std::string& what) {
        INFO(what);
        CHECK_THROWS_WITH(faces_inside_curve(m, c, 0.5), Catch::Contains(what));
    };
    fails({{1, 1, 0}, {5, 1, 0}}, "at least 3 points");
    fails({{1, 1, 0}, {5, 1, 0}, {std::nan(""), 5, 0}}, "point 2 is not finite");
    fails({{1, 1, 0}, {5, 1, 3}, {5, 5, 0}}, "point 1 lies farther than");
    fails({{2.4, 2.4, 0}, {2.5, 2.4, 0}, {2.45, 2.5, 0}}, "does not separate");
    // two squares 3 mm apart: a curve around both crosses the gap
    triangle_mesh two = test::plane_grid(4, 1.0, 1, 0.0);
    const auto n = static_cast<std::uint32_t>(two.vertices.size());
    const triangle_mesh right = test::plane_grid(4, 1.0, 1, 0.0);
    for (const vec3& v : right.vertices) two.vertices.push_back(v + vec3(7, 0, 0));
    for (auto f : right.faces) {
        for (auto& k : f) k += n;
        two.faces.push_back(f);
    }
    CHECK_THROWS_WITH(faces_inside_curve(two, std::vector<vec3>{{1, 1, 0}, {10, 1, 0}, {10, 3, 0}, {1, 3, 0}}, 0.5), Catch::Contains("crosses a gap"));
}

}  // namespace curve_region_test
