// surface/bake.hpp (filigree-synthesis.md §6.1): a flat and a tilted mesh baked with a polygonal
// disk, a ring with a hole and a rectangle that leaves the mesh: areas and boundary lengths against
// closed forms (cracks between faces would add boundary), manifold edges, components, bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/surface/bake.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "support/sphere_mesh.hpp"

namespace bake_test {

using namespace fabsynth;

inline double mesh_area(const triangle_mesh& m) {
    double a = 0;
    for (const auto& f : m.faces) a += 0.5 * glm::length(glm::cross(m.vertices[f[1]] - m.vertices[f[0]], m.vertices[f[2]] - m.vertices[f[0]]));
    return a;
}

/// Total length of the edges used by exactly one face (counted by hand, no library code).
inline double boundary_length(const triangle_mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) ++uses[{std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])}];
    double l = 0;
    for (const auto& [e, n] : uses)
        if (n == 1) l += glm::distance(m.vertices[e.first], m.vertices[e.second]);
    return l;
}

TEST_CASE("bake: areas and boundaries of baked contours equal their closed forms, flat and tilted", "[geometry][bake]") {
    const int n = 10;
    triangle_mesh m = test::plane_grid(n, 1.0, 1, 0.0);  // [0, 10]^2
    std::vector<vec2> uv;
    for (const vec3& v : m.vertices) uv.emplace_back(v.x, v.y);
    std::vector<std::uint32_t> faces(m.num_faces());
    for (std::uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;

    const int sides = 64;
    const double r = 2.7;
    ring2 disk;
    for (int k = 0; k < sides; ++k) disk.push_back(vec2(3.5, 3.5) + r * vec2(std::cos(2 * std::numbers::pi * k / sides), std::sin(2 * std::numbers::pi * k / sides)));
    const polygon_with_holes ring{{{6.5, 5.5}, {9.5, 5.5}, {9.5, 9.5}, {6.5, 9.5}}, {{{7.3, 6.5}, {7.3, 8.5}, {8.7, 8.5}, {8.7, 6.5}}}};
    const polygon_with_holes out_of_mesh{{{8.5, 0.5}, {12.0, 0.5}, {12.0, 2.0}, {8.5, 2.0}}, {}};
    const std::vector<polygon_with_holes> contours{{disk, {}}, ring, out_of_mesh};

    const double disk_area = 0.5 * sides * r * r * std::sin(2 * std::numbers::pi / sides), disk_perimeter = sides * 2 * r * std::sin(std::numbers::pi / sides);
    const double exact_area = disk_area + (12.0 - 1.4 * 2.0) + 1.5 * 1.5;
    const double exact_boundary = disk_perimeter + 14.0 + 6.8 + 6.0;

    for (const bool tilted : {false, true}) {
        INFO((tilted ? "tilted" : "flat"));
        triangle_mesh base = m;
        if (tilted)  // rotate 0.6 rad about the x axis and lift: the chart stays the flat x, y
            for (vec3& v : base.vertices) v = vec3(v.x, std::cos(0.6) * v.y - std::sin(0.6) * 5.0, std::sin(0.6) * v.y + 7.0);
        const triangle_mesh mb = bake(base, uv, faces, contours);
        CHECK(mesh_area(mb) == Approx(exact_area).epsilon(1e-9));  // a rotation keeps areas and lengths
        CHECK(boundary_length(mb) == Approx(exact_boundary).epsilon(1e-9));
        const auto t = analyze_topology(mb);
        CHECK(t.nonmanifold_edges == 0);
        std::size_t parts = 0;
        (void)face_components(mb, &parts);
        CHECK(parts == 3);
    }
}

TEST_CASE("bake_per_face: contours given per face, twice over, give the closed-form areas and boundaries (no cracks)", "[geometry][bake]") {
    // mirrored: the second copy's rings come clockwise, as from a chart mirrored against the face
    // (a fold of a local parameterization); a nonzero union of the raw rings would cancel them.
    const int n = 10;
    const triangle_mesh m = test::plane_grid(n, 1.0, 1, 0.0);  // [0, 10]^2
    const int sides = 48;
    const double r = 2.7;
    ring2 disk;
    for (int k = 0; k < sides; ++k) disk.push_back(vec2(3.5, 3.5) + r * vec2(std::cos(2 * std::numbers::pi * k / sides), std::sin(2 * std::numbers::pi * k / sides)));
    const polygon_with_holes out_of_mesh{{{8.5, 0.5}, {12.0, 0.5}, {12.0, 2.0}, {8.5, 2.0}}, {}};
    // the ring given as two overlapping halves (the union per face must join them)
    const polygon_with_holes ring_left{{{6.5, 5.5}, {8.2, 5.5}, {8.2, 6.5}, {7.3, 6.5}, {7.3, 8.5}, {8.2, 8.5}, {8.2, 9.5}, {6.5, 9.5}}, {}};
    const polygon_with_holes ring_right{{{7.9, 5.5}, {9.5, 5.5}, {9.5, 9.5}, {7.9, 9.5}, {7.9, 8.5}, {8.7, 8.5}, {8.7, 6.5}, {7.9, 6.5}}, {}};
    const double disk_area = 0.5 * sides * r * r * std::sin(2 * std::numbers::pi / sides), disk_perimeter = sides * 2 * r * std::sin(std::numbers::pi / sides);
    const double exact_area = disk_area + (12.0 - 1.4 * 2.0) + 1.5 * 1.5;
    const double exact_boundary = disk_perimeter + 14.0 + 6.8 + 6.0;

    for (const auto& [tilted, mirrored] : {std::pair{false, false}, std::pair{true, false}, std::pair{false, true}, std::pair{true, true}}) {
        INFO((tilted ? "tilted" : "flat") << (mirrored ? ", mirrored second copy" : ""));
        auto place = [&](vec2 q) {  // the chart point on the (tilted) plane
            return tilted ? vec3(q.x, std::cos(0.6) * q.y - std::sin(0.6) * 5.0, std::sin(0.6) * q.y + 7.0) : vec3(q.x, q.y, 0.0);
        };
        triangle_mesh base = m;
        for (vec3& v : base.vertices) v = place({v.x, v.y});
        std::vector<face_contours> per_face;
        for (std::uint32_t f = 0; f < base.num_faces(); ++f) {
            const face_frame fr = face_frame::of(base, f);
            auto carry = [&](const polygon_with_holes& p) {
                polygon_with_holes o;
                for (const vec2& q : p.outer) o.outer.push_back(fr.to_2d(place(q)));
                for (const ring2& h : p.holes) {
                    o.holes.emplace_back();
                    for (const vec2& q : h) o.holes.back().push_back(fr.to_2d(place(q)));
                }
                return o;
            };
            auto mirror = [&](polygon_with_holes p) {
                if (mirrored) {
                    std::reverse(p.outer.begin(), p.outer.end());
                    for (ring2& h : p.holes) std::reverse(h.begin(), h.end());
                }
                return p;
            };
            per_face.push_back({f, {carry({disk, {}}), carry(ring_left)}});
            per_face.push_back({f, {mirror(carry({disk, {}})), mirror(carry(ring_right)), mirror(carry(out_of_mesh))}});
        }
        const triangle_mesh mb = bake_per_face(base, per_face);
        CHECK(mesh_area(mb) == Approx(exact_area).epsilon(1e-9));
        CHECK(boundary_length(mb) == Approx(exact_boundary).epsilon(1e-9));
        const auto t = analyze_topology(mb);
        CHECK(t.nonmanifold_edges == 0);
        std::size_t parts = 0;
        (void)face_components(mb, &parts);
        CHECK(parts == 3);
        for (const auto& f : mb.faces) {  // oriented as the base faces
            const vec3 nrm = glm::cross(mb.vertices[f[1]] - mb.vertices[f[0]], mb.vertices[f[2]] - mb.vertices[f[0]]);
            CHECK(glm::dot(nrm, glm::cross(base.vertices[1] - base.vertices[0], base.vertices[n + 2] - base.vertices[0])) > 0);
        }
    }
}

TEST_CASE("bake: nothing to bake, bad input", "[geometry][bake]") {
    const triangle_mesh m = test::plane_grid(2, 1.0, 1, 0.0);
    std::vector<vec2> uv;
    for (const vec3& v : m.vertices) uv.emplace_back(v.x, v.y);
    const std::vector<std::uint32_t> faces{0, 1, 2};
    const std::vector<polygon_with_holes> far{{{{10, 10}, {11, 10}, {11, 11}}, {}}};
    CHECK(bake(m, uv, faces, far).faces.empty());
    CHECK(bake(m, uv, faces, {}).faces.empty());
    const std::vector<vec2> short_uv(3);
    CHECK_THROWS_AS(bake(m, short_uv, faces, far), invalid_input);
    const std::vector<std::uint32_t> bad_face{99};
    CHECK_THROWS_AS(bake(m, uv, bad_face, far), invalid_input);
    std::vector<vec2> nan_uv = uv;
    nan_uv[0].x = NAN;
    CHECK_THROWS_AS(bake(m, nan_uv, faces, far), invalid_input);
}

}  // namespace bake_test
