#include <catch2/catch.hpp>

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/core/rng.hpp>
#include <fabsynth/voxel.hpp>

#include <limits>

#include "shapes.hpp"

using namespace fabsynth;

TEST_CASE("triangle/box SAT agrees with independent clipping", "[voxel][voxelize]") {
    counter_rng r(11);
    const box3 box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
    int hits = 0, misses = 0;
    for (int i = 0; i < 20000; ++i) {
        vec3 v[3];
        const vec3 c(r.uniform(-1.5, 1.5), r.uniform(-1.5, 1.5), r.uniform(-1.5, 1.5));
        const double s = r.uniform(0.05, 1.5);
        for (auto& p : v) p = c + s * vec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1));
        const bool sat = triangle_box_overlap(vec3(0), vec3(0.5), v[0], v[1], v[2]);
        if (sat) {
            ++hits;
            REQUIRE(test::clip_intersects(box, v[0], v[1], v[2], 1e-9));
        } else {
            ++misses;
            REQUIRE_FALSE(test::clip_intersects(box, v[0], v[1], v[2], -1e-9));
        }
        const double a = clipped_triangle_area(box, v[0], v[1], v[2]);
        REQUIRE(a >= 0.0);
        REQUIRE(a <= 0.5 * glm::length(glm::cross(v[1] - v[0], v[2] - v[0])) * (1 + 1e-12) + 1e-15);
        if (a > 1e-9) REQUIRE(sat);
    }
    CHECK(hits > 2000);
    CHECK(misses > 2000);
    // touching counts: a triangle in the plane of a box face, and one touching only a corner
    CHECK(triangle_box_overlap(vec3(0), vec3(0.5), {0.5, -2, -2}, {0.5, 2, -2}, {0.5, 0, 2}));
    CHECK(triangle_box_overlap(vec3(0), vec3(0.5), {0.5, 0.5, 0.5}, {2, 0.5, 0.5}, {0.5, 2, 0.5}));
    CHECK_FALSE(triangle_box_overlap(vec3(0), vec3(0.5), {0.51, 0.5, 0.5}, {2, 0.5, 0.5}, {0.51, 2, 0.5}));
    // fully inside: the whole area
    CHECK(clipped_triangle_area(box, {0, 0, 0}, {0.2, 0, 0}, {0, 0.3, 0}) == Approx(0.03));
}

namespace {

voxel_grid<std::uint8_t> shell_mask(const shell_grid& s) {
    voxel_grid<std::uint8_t> m(s.geometry(), 0);
    s.for_each([&](ivec3 p, const shell_voxel&) { m.set(p, 1); });
    return m;
}

void check_shell(const triangle_mesh& mesh, int resolution, double min_aligned_fraction, bool expect_two_components) {
    const shell_grid shell = voxelize_surface(mesh, resolution);
    const grid_geometry& g = shell.geometry();
    INFO("shell voxels " << shell.storage().stored() << " grid " << g.dims.x << "x" << g.dims.y << "x" << g.dims.z);
    REQUIRE(shell.storage().stored() > 0);

    // topology: one 26-connected shell, complement = inside + outside (no holes)
    const auto mask = shell_mask(shell);
    CHECK(label_components<connectivity::c26>(shell, [](const shell_voxel& v) { return v.area > 0 || v.normal != vec3(0); }).count == 1);
    // No holes: the complement's 6-components are one outside component (holding the grid corner)
    // whose voxel centres are all outside the mesh, and inside pockets whose centres are all inside
    // (thin parts, e.g. bunny ears, can have pockets of their own). The inside/outside oracle is the
    // solid voxelizer, checked against the winding number below.
    const auto cc = label_components<connectivity::c6>(mask, [](std::uint8_t v) { return v == 0; });
    const auto solid = voxelize_solid(mesh, g);
    REQUIRE(cc.count >= 2);
    if (expect_two_components) CHECK(cc.count == 2);
    const int outside = cc.labels.get({0, 0, 0});
    std::size_t wrong_side = 0;
    for (std::uint64_t i = 0; i < mask.size(); ++i) {
        const ivec3 p = mask.coord(i);
        const int l = cc.labels.get(p);
        if (l >= 0) wrong_side += solid.get(p) != (l == outside ? 0 : 1);
    }
    CHECK(wrong_side == 0);

    // exactness, with an independent clipping oracle enumerating each triangle's bounding voxels:
    // every shell voxel meets some triangle (grown by 1e-7 voxel), every voxel a triangle meets
    // strictly inside (shrunk box) is in the shell
    voxel_grid<std::uint8_t> witnessed(g, 0);
    const double h = g.spacing.x;
    std::size_t missing = 0, not_in_shell = 0, unwitnessed = 0, not_unit = 0;  // failures (counted, so that
                                                                               // the sanitizer build stays fast)
    double total_area = 0;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& t = mesh.faces[f];
        const vec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
        box3 tb;
        tb.extend(a).extend(b).extend(c);
        const ivec3 lo = glm::max(g.voxel_of(tb.lo) - 1, ivec3(0)), hi = glm::min(g.voxel_of(tb.hi) + 1, g.dims - 1);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) {
                    const box3 vb = g.voxel_box({x, y, z});
                    if (test::clip_intersects(vb, a, b, c, 1e-7 * h)) witnessed.set({x, y, z}, 1);
                    if (test::clip_intersects(vb, a, b, c, -1e-7 * h) && mask.get({x, y, z}) != 1) ++missing;
                }
        // the centroid's voxel is in the shell and its normal agrees with the face normal
        total_area += 0.5 * glm::length(face_normal_area2(mesh, f));
    }
    std::size_t aligned = 0;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& t = mesh.faces[f];
        const vec3 centroid = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
        const ivec3 p = g.voxel_of(centroid);
        not_in_shell += mask.get(p) != 1;
        if (glm::dot(shell.get(p).normal, face_normal_area2(mesh, f)) > 0) ++aligned;
    }
    CHECK(static_cast<double>(aligned) >= min_aligned_fraction * static_cast<double>(mesh.faces.size()));
    double shell_area = 0;
    shell.for_each([&](ivec3 p, const shell_voxel& v) {
        unwitnessed += witnessed.get(p) != 1;
        not_unit += std::abs(glm::length(v.normal) - 1.0) > 1e-12;
        shell_area += v.area;
    });
    CHECK(missing == 0);       // conservative: every voxel the surface enters is in the shell
    CHECK(not_in_shell == 0);  // every triangle centroid's voxel is in the shell
    CHECK(unwitnessed == 0);   // exact: every shell voxel touches a triangle
    CHECK(not_unit == 0);
    // clipped areas partition the surface
    CHECK(shell_area == Approx(total_area).epsilon(1e-9));
}

}  // namespace

TEST_CASE("surface voxelization of a sphere: 26-connected, no holes, exact", "[voxel][voxelize]") {
    check_shell(test::load_normalized("icosphere.obj"), 40, 1.0, true);
}

TEST_CASE("surface voxelization of the bunny: 26-connected, no holes, exact", "[voxel][voxelize]") {
    check_shell(test::load_normalized("bunny_lowres.obj"), 64, 0.97, false);
}

TEST_CASE("surface voxelization of random triangle soups is exact and never crashes", "[voxel][voxelize]") {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        counter_rng r(seed);
        triangle_mesh soup;
        for (int i = 0; i < 60; ++i) {
            const vec3 c(r.uniform(-2, 12), r.uniform(-2, 12), r.uniform(-2, 12));  // some outside the grid
            const double s = r.uniform(0.01, 4.0);
            for (int k = 0; k < 3; ++k) {
                // snap some coordinates to voxel faces, make some triangles degenerate
                vec3 v = c + s * vec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1));
                if (r.uniform() < 0.3) v = glm::round(v);
                soup.vertices.push_back(v);
            }
            if (i % 10 == 0) soup.vertices.back() = soup.vertices[soup.vertices.size() - 2];
            const auto b = static_cast<std::uint32_t>(3 * i);
            soup.faces.push_back({b, b + 1, b + 2});
        }
        const grid_geometry g{{10, 10, 10}, vec3(0), vec3(1)};
        const auto shell = voxelize_surface(soup, g);
        voxel_grid<std::uint8_t> witnessed(g, 0), must(g, 0);
        std::size_t bad = 0;
        for (std::uint64_t i = 0; i < g.count(); ++i) {
            const ivec3 p = g.coord(i);
            for (const auto& t : soup.faces) {
                const vec3 a = soup.vertices[t[0]], b = soup.vertices[t[1]], c = soup.vertices[t[2]];
                if (!box3().extend(a).extend(b).extend(c).intersects(g.voxel_box(p).inflated(1e-6))) continue;
                if (glm::length(glm::cross(b - a, c - a)) == 0) continue;  // zero-area triangles are skipped
                if (test::clip_intersects(g.voxel_box(p), a, b, c, 1e-7)) witnessed.set(p, 1);
                if (test::clip_intersects(g.voxel_box(p), a, b, c, -1e-7)) must.set(p, 1);
            }
            const bool in_shell = shell.storage().is_stored(i);
            bad += in_shell && witnessed.get(p) != 1;
            bad += must.get(p) && !in_shell;
            bad += in_shell && std::abs(glm::length(shell.get(p).normal) - 1.0) > 1e-12;
        }
        CHECK(bad == 0);
        CHECK(shell.storage().stored() > 0);
        (void)voxelize_solid(soup, g);  // open soup: deterministic, no crash
    }
}

TEST_CASE("surface voxelization: sphere normals are radial", "[voxel][voxelize]") {
    const auto mesh = test::load_normalized("icosphere.obj");
    const auto shell = voxelize_surface(mesh, 32);
    double worst = 1;
    shell.for_each([&](ivec3 p, const shell_voxel& v) { worst = std::min(worst, glm::dot(v.normal, glm::normalize(shell.center(p)))); });
    CHECK(worst > 0.9);
}

TEST_CASE("voxelization is identical for 1 and 2 threads", "[voxel][voxelize]") {
    const auto mesh = test::load_normalized("bunny_lowres.obj");
    set_num_threads(1);
    const auto s1 = voxelize_surface(mesh, 48);
    const auto v1 = voxelize_solid(mesh, s1.geometry());
    set_num_threads(2);
    const auto s2 = voxelize_surface(mesh, 48);
    const auto v2 = voxelize_solid(mesh, s1.geometry());
    set_num_threads(0);
    REQUIRE(s1.storage().stored() == s2.storage().stored());
    std::size_t differ = 0;
    s1.for_each([&](ivec3 p, const shell_voxel& v) { differ += !(s2.get(p) == v); });  // bitwise
    CHECK(differ == 0);
    CHECK(v1.storage().data() == v2.storage().data());
}

TEST_CASE("solid voxelization matches the winding number", "[voxel][voxelize]") {
    const auto mesh = test::load_normalized("torus.obj");
    const auto g = fit_grid(bounding_box(mesh), 24, 1);
    const auto solid = voxelize_solid(mesh, g);
    std::size_t checked = 0, inside = 0, wrong = 0;
    for (std::uint64_t i = 0; i < solid.size(); i += 2) {  // every other voxel keeps the sanitizer run short
        const ivec3 p = solid.coord(i);
        const double w = test::winding_number(mesh, solid.center(p));
        if (std::abs(w - std::round(w)) > 0.05) continue;  // centre practically on the surface
        ++checked;
        inside += std::round(w) != 0;
        wrong += solid.get(p) != (std::round(w) != 0 ? 1 : 0);
    }
    CHECK(wrong == 0);
    CHECK(checked > 0.95 * 0.5 * static_cast<double>(solid.size()));
    CHECK(inside > 100);
}

TEST_CASE("solid voxelization: volume of a sphere and shell/solid consistency", "[voxel][voxelize]") {
    const auto mesh = test::load_normalized("icosphere.obj");
    const auto g = fit_grid(bounding_box(mesh), 64, 1);
    const auto solid = voxelize_solid(mesh, g);
    const double h = g.spacing.x;
    const double vol = static_cast<double>(solid.count_if([](std::uint8_t v) { return v != 0; })) * h * h * h;
    CHECK(vol == Approx(signed_volume(mesh)).epsilon(0.02));
    // solid voxels not in the shell are surrounded by solid or shell voxels only
    const auto shell = voxelize_surface(mesh, g);
    std::size_t exposed = 0;
    for (std::uint64_t i = 0; i < solid.size(); ++i) {
        const ivec3 p = solid.coord(i);
        if (!solid.get(p) || shell.storage().is_stored(i)) continue;
        for (auto o : connectivity::c6::offsets) {
            const ivec3 q = p + as_ivec3(o);
            exposed += !(solid.get(q) || shell.storage().is_stored(solid.index(q)));
        }
    }
    CHECK(exposed == 0);
}

TEST_CASE("solid voxelization is robust when rays hit edges and vertices exactly", "[voxel][voxelize]") {
    // unit cube [-0.5, 0.5]^3 made of 12 triangles; voxel centres at multiples of 0.5, so rays run
    // through face diagonals, along faces and through corners
    triangle_mesh cube = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/cube.obj");
    // centres at -1, -0.5, 0, 0.5, 1, 1.5 on every axis (exact in binary)
    const grid_geometry g{{6, 6, 6}, vec3(-1.25), vec3(0.5)};
    const auto solid = voxelize_solid(cube, g);
    // the ray from (x, y, z) is perturbed to (y + eps, z + eps^2) and a hit at exactly x counts as
    // behind, so the result is exactly the half-open cube [-0.5, 0.5)^3
    auto in = [](double t) { return t >= -0.5 && t < 0.5; };
    for (std::uint64_t i = 0; i < solid.size(); ++i) {
        const ivec3 p = solid.coord(i);
        const vec3 c = solid.center(p);
        INFO("centre " << c.x << " " << c.y << " " << c.z);
        REQUIRE(solid.get(p) == (in(c.x) && in(c.y) && in(c.z) ? 1 : 0));
    }
    // an open mesh and bad input do not crash
    triangle_mesh bad = cube;
    bad.vertices[0].x = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(voxelize_solid(bad, g), invalid_input);
    CHECK_THROWS_AS(voxelize_surface(bad, g), invalid_input);
    bad = cube;
    bad.faces[0][1] = 99;
    CHECK_THROWS_AS(voxelize_surface(bad, 10), invalid_input);
    CHECK_THROWS_AS(voxelize_surface(triangle_mesh{}, 10), invalid_input);
    bad = cube;
    bad.vertices[3].z = 1e300;  // finite but would overflow the predicates
    CHECK_THROWS_AS(voxelize_surface(bad, g), invalid_input);
    CHECK_THROWS_AS(voxelize_solid(bad, g), invalid_input);
    CHECK_THROWS_AS(voxelize_surface(cube, 0), invalid_input);
}
