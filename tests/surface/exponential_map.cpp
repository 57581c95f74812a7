// surface/exponential_map.hpp: the discrete exponential map against closed forms: an isometry on
// a tilted, jittered plane (exact), the unrolled cylinder (developable), great-circle distances on
// a sphere, no mirrored face where the discrete map folds (a lens's rim, past a sphere's equator),
// point location round trips, determinism and bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/surface/exponential_map.hpp"
#include "support/sphere_mesh.hpp"

namespace expmap_test {

using fabsynth::local_patch;
using fabsynth::surface_patcher;
using fabsynth::surface_point;
using fabsynth::triangle_mesh;
using fabsynth::vec2;
using fabsynth::vec3;
using fabsynth::test::cylinder;
using fabsynth::test::plane_grid;
using fabsynth::test::sphere_mesh;

inline vec3 rotate(vec3 p) {  // a fixed rotation: 0.7 rad about z, then 1.1 rad about (1, 1, 0)/sqrt2
    const double c = std::cos(0.7), s = std::sin(0.7);
    p = {c * p.x - s * p.y, s * p.x + c * p.y, p.z};
    const vec3 a = glm::normalize(vec3(1, 1, 0));
    const double c2 = std::cos(1.1), s2 = std::sin(1.1);
    return p * c2 + glm::cross(a, p) * s2 + a * glm::dot(a, p) * (1 - c2);
}

TEST_CASE("exponential map: an isometry on a tilted, jittered plane", "[geometry][exponential_map]") {
    triangle_mesh m = plane_grid(60, 0.5, 3);
    for (vec3& v : m.vertices) v = rotate(v + vec3(-15, -15, 0)) + vec3(4, -2, 7);
    const surface_patcher patcher(m);
    const surface_point o{3660, {0.2, 0.3, 0.5}};  // quad (30, 30), the middle
    const vec3 dir(0.3, -1.0, 0.4);
    const local_patch p = patcher.patch(o, dir, 8.0);
    // independent frame: the plane's normal is the rotated +z
    const vec3 n = rotate(vec3(0, 0, 1));
    const vec3 e1 = glm::normalize(dir - glm::dot(dir, n) * n), e2 = glm::cross(n, e1);
    const vec3 x0 = patcher.position(o);
    REQUIRE(p.vertices.size() > 500);
    double worst = 0;
    for (std::size_t k = 0; k < p.vertices.size(); ++k) {
        const vec3 d = m.vertices[p.vertices[k]] - x0;
        worst = std::max(worst, glm::distance(p.uv[k], vec2(glm::dot(d, e1), glm::dot(d, e2))));
    }
    CHECK(worst < 1e-9);
    CHECK(glm::length(*p.uv_of(o)) < 1e-12);
    // 2D -> surface -> 2D
    fabsynth::counter_rng rng(9);
    for (int t = 0; t < 500; ++t) {
        const vec2 q(rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0));
        const auto s = p.locate(q);
        INFO("q " << q.x << " " << q.y);
        REQUIRE(s.has_value());
        CHECK(glm::distance(patcher.position(*s), x0 + q.x * e1 + q.y * e2) < 1e-9);
        CHECK(glm::distance(*p.uv_of(*s), q) < 1e-9);
    }
    CHECK_FALSE(p.locate({50, 50}).has_value());
    // every vertex within 8 mm of the origin is in the patch, and so is every face around it
    for (std::size_t v = 0; v < m.num_vertices(); ++v)
        if (glm::distance(m.vertices[v], x0) <= 8.0) CHECK(std::find(p.vertices.begin(), p.vertices.end(), v) != p.vertices.end());
}

TEST_CASE("exponential map: the unrolled cylinder", "[geometry][exponential_map]") {
    const double r = 20.0;
    const triangle_mesh m = cylinder(r, 60.0, 400, 0.5);
    const surface_patcher patcher(m);
    const std::uint32_t face = 2 * (60 * 400 + 100);  // ring 60 (z = 30), segment 100
    const surface_point o{face, {1.0 / 3, 1.0 / 3, 1.0 / 3}};
    const vec3 x0 = patcher.position(o);
    const double phi0 = std::atan2(x0.y, x0.x), rho0 = std::hypot(x0.x, x0.y);
    const local_patch p = patcher.patch(o, vec3(0, 0, 1), 15.0);  // u along the axis
    double worst = 0, worst_rel = 0;
    std::size_t checked = 0;
    for (std::size_t k = 0; k < p.vertices.size(); ++k) {
        const vec3 v = m.vertices[p.vertices[k]];
        const double dphi = std::remainder(std::atan2(v.y, v.x) - phi0, 2 * std::numbers::pi);
        const vec2 unrolled(v.z - x0.z, -rho0 * dphi);  // e2 = n x e1 = (outward) x (+z) points to -phi
        const double geodesic = glm::length(unrolled);
        if (geodesic > 15.0) continue;
        ++checked;
        worst = std::max(worst, glm::distance(p.uv[k], unrolled));
        if (geodesic > 1.0) worst_rel = std::max(worst_rel, std::abs(glm::length(p.uv[k]) - geodesic) / geodesic);
    }
    REQUIRE(checked > 1000);
    INFO("worst deviation from the unrolled cylinder " << worst << " mm, distance error " << worst_rel);
    CHECK(worst < 2e-3);      // mm over a 15 mm patch (measured: 0.27 um)
    CHECK(worst_rel < 1e-4);  // measured: 1.3e-5
}

TEST_CASE("exponential map: great-circle distances on a sphere", "[geometry][exponential_map]") {
    const double r = 20.0;
    const triangle_mesh m = sphere_mesh(r, 5);  // 8192 faces, edges about 1 mm
    const surface_patcher patcher(m);
    const surface_point o{1234, {0.25, 0.25, 0.5}};
    const vec3 x0 = patcher.position(o);
    const local_patch p = patcher.patch(o, vec3(0, 0, 1), 10.0);     // half a radian
    double worst_rel = 0;
    for (std::size_t k = 0; k < p.vertices.size(); ++k) {
        const vec3 v = m.vertices[p.vertices[k]];
        const double geodesic = r * std::acos(std::clamp(glm::dot(glm::normalize(v), glm::normalize(x0)), -1.0, 1.0));
        if (geodesic < 1.0 || geodesic > 10.0) continue;
        worst_rel = std::max(worst_rel, std::abs(glm::length(p.uv[k]) - geodesic) / geodesic);
    }
    INFO("worst relative error of |uv| against the great-circle distance: " << worst_rel);
    CHECK(worst_rel < 5e-3);  // measured: 0.09% at half a radian
}

TEST_CASE("exponential map: no mirrored face past a sharp rim or beyond the equator", "[geometry][exponential_map]") {
    // A lens (a sphere of radius 10 squashed to 1 mm thickness: a rim far sharper than its
    // edges) and the round sphere with a disk past its equator: the discrete map mirrors faces
    // there (51 and 89 before the fold check); a patch keeps only faces whose (u, v) triangle turns
    // the way the face turns about its vertex normals, and its disk still reaches past the rim.
    for (const double squash : {0.05, 1.0}) {
        triangle_mesh m = sphere_mesh(10.0, 4);
        for (vec3& v : m.vertices) v.z *= squash;
        const surface_patcher patcher(m);
        std::uint32_t top = 0;
        for (std::uint32_t f = 0; f < m.num_faces(); ++f)
            if (patcher.position({f, {1.0 / 3, 1.0 / 3, 1.0 / 3}}).z > patcher.position({top, {1.0 / 3, 1.0 / 3, 1.0 / 3}}).z) top = f;
        const double radius = squash < 1 ? 16.0 : 25.0;
        const local_patch p = patcher.patch({top, {1.0 / 3, 1.0 / 3, 1.0 / 3}}, vec3(1, 0, 0), radius);
        const auto normals = fabsynth::vertex_normals(m);
        std::size_t below = 0;
        for (std::size_t t = 0; t < p.faces.size(); ++t) {
            const auto& c = m.faces[p.faces[t]];
            const double turn_2d = fabsynth::orient2d(p.uv[p.corners[t][0]], p.uv[p.corners[t][1]], p.uv[p.corners[t][2]]);
            const vec3 n3 = glm::cross(m.vertices[c[1]] - m.vertices[c[0]], m.vertices[c[2]] - m.vertices[c[0]]);
            INFO("squash " << squash << " face " << p.faces[t]);
            CHECK(turn_2d * glm::dot(n3, normals[c[0]] + normals[c[1]] + normals[c[2]]) > 0);
            below += n3.z < 0;
        }
        CHECK(below > 100);  // the disk wraps past the rim (the equator) onto the lower side
    }
}

TEST_CASE("exponential map: same input, same patch; bad input named", "[geometry][exponential_map]") {
    const triangle_mesh m = cylinder(10.0, 20.0, 64, 1.0);
    const surface_patcher patcher(m);
    const surface_point o{100, {0.5, 0.25, 0.25}};
    const local_patch a = patcher.patch(o, vec3(0, 0, 1), 6.0), b = patcher.patch(o, vec3(0, 0, 1), 6.0);
    CHECK(a.vertices == b.vertices);
    CHECK(a.uv == b.uv);
    CHECK(a.faces == b.faces);
    using fabsynth::invalid_input;
    CHECK_THROWS_AS(patcher.patch({static_cast<std::uint32_t>(m.num_faces()), {1, 0, 0}}, vec3(0, 0, 1), 6.0), invalid_input);
    CHECK_THROWS_AS(patcher.patch({0, {0.5, 0.6, 0.0}}, vec3(0, 0, 1), 6.0), invalid_input);
    CHECK_THROWS_AS(patcher.patch({0, {NAN, 0.5, 0.5}}, vec3(0, 0, 1), 6.0), invalid_input);
    CHECK_THROWS_AS(patcher.patch(o, vec3(0, 0, 1), 0.0), invalid_input);
    CHECK_THROWS_AS(patcher.patch(o, vec3(0, 0, 1), NAN), invalid_input);
    CHECK_THROWS_AS(patcher.patch(o, patcher.face_normal(o.face), 6.0), invalid_input);  // along the normal
    CHECK_THROWS_AS(patcher.patch(o, vec3(0, 0, 0), 6.0), invalid_input);
    triangle_mesh bad = m;
    bad.faces[3][1] = static_cast<std::uint32_t>(bad.vertices.size());
    CHECK_THROWS_AS(surface_patcher(bad), invalid_input);
    bad = m;
    bad.vertices[5].y = NAN;
    CHECK_THROWS_AS(surface_patcher(bad), invalid_input);
}

}  // namespace expmap_test
