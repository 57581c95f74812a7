// geometry/distance.hpp against brute force and analytic distances.
#include <catch2/catch.hpp>

#include <cmath>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "support/sphere_mesh.hpp"

using namespace fabsynth;

using test::sphere_mesh;

TEST_CASE("point-triangle distance matches dense sampling", "[geometry][distance]") {
    counter_rng rng(1, 2);
    for (int it = 0; it < 300; ++it) {
        const vec3 a(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const vec3 b(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const vec3 c(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const vec3 p(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
        const auto r = closest_point_on_triangle(p, a, b, c);
        const double d = glm::length(r.point - p);
        double best = 1e300;
        const int N = 200;
        for (int i = 0; i <= N; ++i)
            for (int j = 0; i + j <= N; ++j) {
                const vec3 q = a + (b - a) * (double(i) / N) + (c - a) * (double(j) / N);
                best = std::min(best, glm::length(q - p));
            }
        REQUIRE(d <= best + 1e-12);           // never worse than any sample
        REQUIRE(d >= best - 0.02);            // and samples are within the grid pitch of it
    }
}

TEST_CASE("mesh distance: BVH equals brute force, sign from pseudonormals", "[geometry][distance]") {
    const triangle_mesh m = sphere_mesh(5.0, 4);
    mesh_distance md(m);
    REQUIRE(md.watertight());
    counter_rng rng(7, 8);
    for (int it = 0; it < 2000; ++it) {
        const vec3 p(rng.uniform(-8, 8), rng.uniform(-8, 8), rng.uniform(-8, 8));
        double brute = 1e300;
        for (const auto& t : m.faces) {
            const auto c = closest_point_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
            brute = std::min(brute, glm::length(c.point - p));
        }
        const double sd = md.signed_distance(p);
        REQUIRE(std::abs(sd) == Approx(brute).margin(1e-12));
        // inscribed polyhedron of a sphere of radius 5: inside iff |p| below the polyhedron
        if (glm::length(p) < 4.9) REQUIRE(sd < 0);
        if (glm::length(p) > 5.0) REQUIRE(sd > 0);
        // bounded query
        const auto c = md.closest(p, 1.0);
        REQUIRE(c.found() == (brute <= 1.0));
    }
    // vertices and edges as closest features: points pushed out along vertex directions
    for (std::size_t v = 0; v < m.vertices.size(); v += 7) {
        REQUIRE(md.signed_distance(m.vertices[v] * 1.01) > 0);
        REQUIRE(md.signed_distance(m.vertices[v] * 0.99) < 0);
    }
}

TEST_CASE("mesh distance rejects signed queries on open meshes", "[geometry][distance]") {
    triangle_mesh m = sphere_mesh(1.0, 1);
    m.faces.pop_back();
    mesh_distance md(m);
    CHECK_FALSE(md.watertight());
    CHECK_THROWS_AS(md.signed_distance({0, 0, 0}), invalid_input);
    CHECK(md.unsigned_distance({0, 0, 0}) > 0.5);
    triangle_mesh flipped = sphere_mesh(1.0, 1);
    std::swap(flipped.faces[0][0], flipped.faces[0][1]);
    CHECK_FALSE(mesh_distance(flipped).watertight());
    CHECK_THROWS_AS(mesh_distance(triangle_mesh{}), invalid_input);
    CHECK_THROWS_AS(md.closest({NAN, 0, 0}), invalid_input);
}
