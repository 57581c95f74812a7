// filigree/surface/field.hpp: the up-vector field against the meridians of a sphere and the axis of
// a cylinder, the pole fallback, directions interpolated from constraints (constant and linear
// fields reproduced on a plane), scale fields, bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/filigree/surface/field.hpp"
#include "support/sphere_mesh.hpp"

namespace surface_field_test {

using namespace fabsynth;
using namespace fabsynth::filigree;

inline vec3 centroid(const triangle_mesh& m, std::size_t f) {
    return (m.vertices[m.faces[f][0]] + m.vertices[m.faces[f][1]] + m.vertices[m.faces[f][2]]) / 3.0;
}

TEST_CASE("surface field: the up vector follows a cylinder's axis and a sphere's meridians", "[filigree][surface_field]") {
    const triangle_mesh cyl = test::cylinder(10.0, 20.0, 64, 1.0);
    const surface_patcher pc(cyl);
    const auto up = surface_direction_field::from_up_vector(pc, {0, 0, 3});
    for (std::uint32_t f = 0; f < cyl.num_faces(); f += 7) CHECK(glm::distance(up({f, {0.2, 0.3, 0.5}}), vec3(0, 0, 1)) < 1e-12);

    const triangle_mesh sph = test::sphere_mesh(20.0, 4);
    const surface_patcher ps(sph);
    const auto north = surface_direction_field::from_up_vector(ps, {0, 0, 1});
    double worst = 0;
    std::size_t poles = 0;
    for (std::uint32_t f = 0; f < sph.num_faces(); ++f) {
        const vec3 c = centroid(sph, f), d = north({f, {1.0 / 3, 1.0 / 3, 1.0 / 3}});
        CHECK(std::abs(glm::length(d) - 1) < 1e-12);
        CHECK(std::abs(glm::dot(d, ps.face_normal(f))) < 1e-12);  // tangent to the face
        const double rho = std::hypot(c.x, c.y);
        if (rho < 0.2 * 20.0) {
            ++poles;
            continue;  // near the poles the facet normals, not the sphere's, decide
        }
        // the meridian direction towards the north pole at the centroid (-theta hat), up to the
        // facet: a face normal off the sphere's by delta turns the projected up vector by at most
        // about delta / sin(theta)
        const vec3 n = glm::normalize(c);
        const vec3 meridian = glm::normalize(vec3(0, 0, 1) - n.z * n);
        const double angle = std::acos(std::clamp(glm::dot(d, meridian), -1.0, 1.0));
        const double delta = std::acos(std::clamp(glm::dot(ps.face_normal(f), n), -1.0, 1.0));
        CHECK(angle <= 1.5 * delta / (rho / glm::length(c)) + 1e-7);  // acos resolves 1e-8 near 1
        worst = std::max(worst, angle);
    }
    INFO("worst angle to the meridian " << worst << " rad");
    CHECK(worst < 0.1);
    CHECK(poles > 0);
}

TEST_CASE("surface field: the pole fallback gives every face a direction", "[filigree][surface_field]") {
    const triangle_mesh plane = test::plane_grid(4, 1.0, 1, 0.0);  // normal +z everywhere
    const surface_patcher p(plane);
    const auto up = surface_direction_field::from_up_vector(p, {0, 0, 1});  // along every normal
    for (std::uint32_t f = 0; f < plane.num_faces(); ++f) {
        const vec3 d = up({f, {1.0 / 3, 1.0 / 3, 1.0 / 3}});
        CHECK(std::abs(glm::length(d) - 1) < 1e-12);
        CHECK(std::abs(d.z) < 1e-12);
    }
}

TEST_CASE("surface field: directions interpolated from constraints", "[filigree][surface_field]") {
    const int n = 10;
    const triangle_mesh m = test::plane_grid(n, 1.0, 3, 0.0);
    const surface_patcher p(m);
    SECTION("one direction everywhere from two constraints") {
        const std::vector<direction_constraint> c{{0, {1, 1, 0.7}}, {static_cast<std::uint32_t>(m.num_vertices() - 1), {2, 2, -3}}};
        const auto f = surface_direction_field::from_constraints(p, c, {0, 1, 0});
        const vec3 want = glm::normalize(vec3(1, 1, 0));
        for (std::uint32_t face = 0; face < m.num_faces(); ++face) CHECK(glm::distance(f({face, {0.3, 0.3, 0.4}}), want) < 1e-9);
    }
    SECTION("x on the left column, y on the right: the per-vertex vectors blend linearly across") {
        std::vector<direction_constraint> c;
        for (int j = 0; j <= n; ++j) {
            c.push_back({static_cast<std::uint32_t>(j * (n + 1)), {1, 0, 0}});
            c.push_back({static_cast<std::uint32_t>(j * (n + 1) + n), {0, 1, 0}});
        }
        const auto f = surface_direction_field::from_constraints(p, c, {0, 0, 1});
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const double t = static_cast<double>(i) / n;
                CHECK(glm::distance(f.per_vertex()[static_cast<std::size_t>(j * (n + 1) + i)], vec3(1 - t, t, 0)) < 1e-9);
            }
    }
}

TEST_CASE("surface field: scale fields and bad input", "[filigree][surface_field]") {
    const triangle_mesh m = test::plane_grid(2, 1.0, 1, 0.0);
    const surface_patcher p(m);
    std::vector<double> s(m.num_vertices(), 1.0);
    s[m.faces[0][1]] = 3.0;
    const auto scale = surface_scale_field::per_vertex(m, s);
    CHECK(scale({0, {0.5, 0.5, 0.0}}) == Approx(2.0));
    const auto dir = surface_direction_field::from_up_vector(p, {1, 0, 0});
    const surface_control ctl{&dir, &scale};
    CHECK(ctl({0, {0.5, 0.5, 0.0}}).scale == Approx(2.0));
    CHECK(glm::distance(ctl({0, {0.5, 0.5, 0.0}}).direction, vec3(1, 0, 0)) < 1e-12);
    CHECK(surface_scale_field::constant(m, 1.5)({3, {0.2, 0.2, 0.6}}) == Approx(1.5));
    CHECK_THROWS_AS(surface_scale_field::constant(m, 0.0), invalid_input);
    CHECK_THROWS_AS(surface_scale_field::per_vertex(m, {1.0, 2.0}), invalid_input);
    CHECK_THROWS_AS(surface_direction_field::from_up_vector(p, {0, 0, 0}), invalid_input);
    CHECK_THROWS_AS(surface_direction_field::from_up_vector(p, {NAN, 0, 1}), invalid_input);
    const std::vector<direction_constraint> out{{99, {1, 0, 0}}}, along{{0, {0, 0, 1}}}, zero{{0, {0, 0, 0}}};
    CHECK_THROWS_AS(surface_direction_field::from_constraints(p, out, {0, 1, 0}), invalid_input);
    CHECK_THROWS_AS(surface_direction_field::from_constraints(p, along, {0, 1, 0}), invalid_input);
    CHECK_THROWS_AS(surface_direction_field::from_constraints(p, zero, {0, 1, 0}), invalid_input);
}

}  // namespace surface_field_test
