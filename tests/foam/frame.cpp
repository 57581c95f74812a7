// Frame + foam inside a mesh: one connected solid; frame present; cut planes open the foam.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/foam/frame.hpp"
#include "fabsynth/foam/frame_mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/voxel/components.hpp"
#include "fabsynth/voxel/grid.hpp"
#include "support/sphere_mesh.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;


TEST_CASE("frame + foam form one connected solid", "[foam][frame]") {
    const double R = 4.0, vox = 0.1;
    const mesh_distance md(test::sphere_mesh(R, 4));
    const voronoi_foam foam(constant_field{0.15}, constant_field{0.25}, {.cell = 3, .seed = 9});
    const framed_foam obj(foam, md, {.thickness = 0.4, .cuts = {}});
    const int n = static_cast<int>(std::ceil(2 * (R + 0.2) / vox));
    const vec3 o(-R - 0.2);
    voxel_grid<std::uint8_t> g(ivec3(n), o, vox);
    long frame_ok = 0, frame_total = 0, foam_voxels = 0;
    for (int k = 0; k < n; ++k) {
        const double z = o.z + (k + 0.5) * vox;
        const image8 s = obj.slice(z, {{o.x, o.y}, {o.x + n * vox, o.y + n * vox}}, vox);
        REQUIRE(s.width == n);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                g.set({i, j, k}, s.at(i, j));
                const vec3 q = g.center({i, j, k});
                const double r = glm::length(q);
                if (r < R - 0.05 && r > R - 0.35) {  // surely in the frame (mesh is within 0.02 of the sphere)
                    ++frame_total;
                    frame_ok += s.at(i, j) == 255;
                }
                if (r > R + 0.01) REQUIRE(s.at(i, j) == 0);
                if (r < R - 0.5 && s.at(i, j) == 255) ++foam_voxels;
            }
    }
    CHECK(frame_ok == frame_total);
    CHECK(foam_voxels > 1000);  // the interior is not empty...
    CHECK(foam_voxels < static_cast<long>(0.6 * 4.19 * std::pow((R - 0.5) / vox, 3)));  // ...nor full
    const auto cc = label_components<connectivity::c6>(g, [](std::uint8_t v) { return v != 0; });
    CHECK(cc.count == 1);
    // and the foam alone, clipped to the same ball without a frame, falls apart into pieces
    voxel_grid<std::uint8_t> bare(ivec3(n), o, vox);
    const framed_foam open(foam, md, {.thickness = 0.0, .cuts = {}});
    for (int k = 0; k < n; ++k) {
        const image8 s = open.slice(o.z + (k + 0.5) * vox, {{o.x, o.y}, {o.x + n * vox, o.y + n * vox}}, vox);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) bare.set({i, j, k}, s.at(i, j));
    }
    CHECK(label_components<connectivity::c6>(bare, [](std::uint8_t v) { return v != 0; }).count > 1);
}

TEST_CASE("frame: point queries agree with slices; cut planes have no frame", "[foam][frame]") {
    const mesh_distance md(test::sphere_mesh(3.0, 3));
    const voronoi_foam foam(constant_field{0.3}, constant_field{0.2}, {.cell = 2, .seed = 4});
    const framed_foam obj(foam, md, {.thickness = 0.3, .cuts = {{{0, 0, 0.5}, {0, 0, 1}}}});
    const double pix = 0.07;
    for (double z : {-1.0, 0.3, 0.45, 1.0}) {
        const image8 s = obj.slice(z, {{-3.5, -3.5}, {3.5, 3.5}}, pix);
        long mism = 0, solid = 0;
        for (int j = 0; j < s.height; ++j)
            for (int i = 0; i < s.width; ++i) {
                const vec3 q(-3.5 + (i + 0.5) * pix, -3.5 + (j + 0.5) * pix, z);
                const bool c = obj.contains(q);
                mism += c != (s.at(i, j) == 255);
                solid += c;
                if (z > 0.5) REQUIRE(s.at(i, j) == 0);
            }
        CHECK(mism == 0);
        if (z < 0.5) CHECK(solid > 0);
    }
    // just below the cut, away from the sphere surface, the slice is the bare foam
    const double z = 0.49;
    const image8 s = obj.slice(z, {{-1.8, -1.8}, {1.8, 1.8}}, 0.05);
    const image8 f = foam.slice(z, {{-1.8, -1.8}, {1.8, 1.8}}, 0.05);
    CHECK(s == f);  // |(x, y, z)| <= 2.6 < 3 - 0.3 - mesh error: no frame there
}

TEST_CASE("frame bad input", "[foam][frame]") {
    triangle_mesh open = test::sphere_mesh(1, 1);
    open.faces.pop_back();
    const mesh_distance md(open);
    const voronoi_foam foam(constant_field{0.3}, constant_field{0.2}, {});
    CHECK_THROWS_AS(framed_foam(foam, md, {}), invalid_input);
    const mesh_distance ok(test::sphere_mesh(1, 1));
    CHECK_THROWS_AS(framed_foam(foam, ok, {.thickness = -1, .cuts = {}}), invalid_input);
    CHECK_THROWS_AS(framed_foam(foam, ok, {.thickness = NAN, .cuts = {}}), invalid_input);
    CHECK_THROWS_AS(framed_foam(foam, ok, {.thickness = 0.1, .cuts = {{{0, 0, 0}, {0, 0, 0}}}}), invalid_input);
}

TEST_CASE("frame implicit: the formula, and its sign agrees with contains()", "[foam][frame]") {
    const mesh_distance md(test::sphere_mesh(3.0, 3));
    const voronoi_foam foam(constant_field{0.3}, constant_field{0.2}, {.cell = 2, .seed = 4});
    const cut_plane cut{{0, 0, 0.5}, {0, 0, 2}};  // normalized by framed_foam
    const framed_foam obj(foam, md, {.thickness = 0.3, .cuts = {cut}});
    const double reach = 0.5;
    counter_rng rng(8, 9);
    long inside = 0, near_tie = 0;
    for (int n = 0; n < 3000; ++n) {
        const vec3 q = vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 7.0 - 3.5;
        // direct computation of the documented formula
        const double sd = md.signed_distance(q);
        const double d = foam.distance_to_edges(q, reach);
        const double foam_v = std::min(d, reach) - 0.2;
        const double want = std::max({sd, q.z - 0.5, std::min(-(sd + 0.3), foam_v)});
        const double g = obj.implicit(q, reach);
        CHECK(g == Approx(want).margin(1e-12));
        if (std::abs(g) < 1e-9) {
            ++near_tie;
            continue;
        }
        CHECK((g < 0) == obj.contains(q));
        inside += g < 0;
    }
    CHECK(inside > 100);
    CHECK(near_tie < 5);
}

TEST_CASE("framed_foam_mesh: closed mesh of the solid in a box", "[foam][frame]") {
    const mesh_distance md(test::sphere_mesh(3.0, 3));
    const voronoi_foam foam(constant_field{0.3}, constant_field{0.2}, {.cell = 2, .seed = 4});
    const framed_foam obj(foam, md, {.thickness = 0.3, .cuts = {}});
    const box3 b({1.0, -1.0, -1.0}, {3.2, 1.0, 1.0});  // crosses the frame
    const triangle_mesh m = framed_foam_mesh(obj, b, 0.1);
    REQUIRE(!m.faces.empty());
    CHECK(is_watertight(m));
    const box3 mb = bounding_box(m);  // within one sample spacing of the box
    CHECK(mb.lo.x >= b.lo.x - 0.1);
    CHECK(mb.hi.x <= 3.0 + 0.1);  // nothing outside the sphere
    CHECK_THROWS_AS(framed_foam_mesh(obj, b, 0.0), invalid_input);
    CHECK_THROWS_AS(framed_foam_mesh(obj, box3({0, 0, 0}, {100, 100, 100}), 0.01), invalid_input);
}
