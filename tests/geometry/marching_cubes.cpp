#include <catch2/catch.hpp>

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/core/rng.hpp>
#include <fabsynth/geometry/extrude.hpp>
#include <fabsynth/geometry/marching_cubes.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/voxel/grid.hpp>

#include <limits>
#include <numbers>

using namespace fabsynth;

namespace {
double min_face_area(const triangle_mesh& m) {
    double a = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < m.faces.size(); ++f) a = std::min(a, 0.5 * glm::length(face_normal_area2(m, f)));
    return a;
}
}  // namespace

TEST_CASE("marching cubes: sphere SDF at 128^3 is watertight, genus 0, volume within 1%", "[geometry][marching_cubes]") {
    const int n = 128;
    const double h = 1.0 / n, r = 0.4;  // unit box, sphere radius 0.4 centred
    auto f = [&](ivec3 p) { return glm::length(vec3(p) * h - 0.5) - r; };
    const triangle_mesh m = marching_cubes(f, ivec3(n + 1), vec3(0), vec3(h));
    const auto t = analyze_topology(m);
    CHECK(t.is_watertight());
    CHECK(t.components == 1);
    CHECK(t.genus == 0);
    CHECK(t.euler == 2);
    const double exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    CHECK(signed_volume(m) == Approx(exact).epsilon(0.01));
    CHECK(std::abs(signed_volume(m) - exact) < 0.002 * exact);  // the actual error is far below 1%
    double worst = 0;
    for (const vec3& v : m.vertices) worst = std::max(worst, std::abs(glm::length(v - 0.5) - r));
    CHECK(worst < 0.1 * h);  // linear interpolation of an SDF: vertices almost on the sphere
    CHECK(min_face_area(m) > 0.0);
    // every vertex is used (one vertex per crossed edge, all shared)
    std::vector<char> used(m.vertices.size(), 0);
    for (const auto& fc : m.faces)
        for (auto v : fc) used[v] = 1;
    CHECK(std::count(used.begin(), used.end(), 1) == static_cast<long>(m.vertices.size()));
}

TEST_CASE("marching cubes: world-space implicit field over a box", "[geometry][marching_cubes]") {
    // ellipsoid with semi-axes 3, 2, 1.5 mm centred at (1, -1, 2): volume 4/3 pi a b c
    auto f = [](vec3 x) {
        const vec3 q = (x - vec3(1, -1, 2)) / vec3(3, 2, 1.5);
        return glm::dot(q, q) - 1.0;  // not a distance, still a valid implicit field
    };
    const auto m = marching_cubes(f, box3({-3, -4, -0.5}, {5, 2, 4.5}), ivec3(97, 73, 61));
    CHECK(is_watertight(m));
    CHECK(signed_volume(m) == Approx(4.0 / 3.0 * std::numbers::pi * 3 * 2 * 1.5).epsilon(0.01));
    CHECK_THROWS_AS(marching_cubes(f, box3{}, ivec3(4)), invalid_input);
}

TEST_CASE("marching cubes: torus has genus 1, two spheres two components", "[geometry][marching_cubes]") {
    const int n = 64;
    const double h = 1.0 / n;
    auto torus = [&](ivec3 p) {
        const vec3 x = vec3(p) * h - 0.5;
        const double q = std::hypot(x.x, x.y) - 0.3;
        return std::hypot(q, x.z) - 0.1;
    };
    const auto t = analyze_topology(marching_cubes(torus, ivec3(n + 1), vec3(0), vec3(h)));
    CHECK(t.is_watertight());
    CHECK(t.components == 1);
    CHECK(t.genus == 1);
    auto two = [&](ivec3 p) {
        const vec3 x = vec3(p) * h;
        return std::min(glm::length(x - vec3(0.25, 0.5, 0.5)), glm::length(x - vec3(0.75, 0.5, 0.5))) - 0.2;
    };
    const auto t2 = analyze_topology(marching_cubes(two, ivec3(n + 1), vec3(0), vec3(h)));
    CHECK(t2.is_watertight());
    CHECK(t2.components == 2);
    CHECK(t2.euler == 4);
}

TEST_CASE("marching cubes: random fields with samples equal to iso stay watertight", "[geometry][marching_cubes]") {
    // values in {-1, 0, 1} (a third exactly at iso), border forced outside: every ambiguous
    // configuration occurs many times
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        const ivec3 dims(9, 8, 10);
        auto f = [&](ivec3 p) -> double {
            if (p.x == 0 || p.y == 0 || p.z == 0 || p.x == dims.x - 1 || p.y == dims.y - 1 || p.z == dims.z - 1) return 1.0;
            return static_cast<double>(hash64(seed, p.x, p.y, p.z) % 3) - 1.0;
        };
        const triangle_mesh m = marching_cubes(f, dims, vec3(1, 2, 3), vec3(0.5, 0.25, 1.0));
        INFO("seed " << seed);
        REQUIRE(!m.empty());
        const auto t = analyze_topology(m);
        REQUIRE(t.is_watertight());
        REQUIRE(min_face_area(m) > 0.0);
        REQUIRE(signed_volume(m) > 0.0);  // outward orientation
        for (const vec3& v : m.vertices) REQUIRE(box3({1, 2, 3}, {5, 3.75, 12}).contains(v));
    }
}

TEST_CASE("marching cubes: samples at iso far from the origin stay watertight once rounded to float", "[geometry][marching_cubes]") {
    // The same {-1, 0, 1} fields on a 0.3 mm grid 100 mm from the origin, where a float's spacing
    // is 7.6e-6 mm: every sample at iso puts vertices of several edges next to one grid point; they
    // must stay apart when rounded to single precision (what STL stores), or welding them folds
    // the surface.
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        const ivec3 dims(9, 8, 10);
        auto f = [&](ivec3 p) -> double {
            if (p.x == 0 || p.y == 0 || p.z == 0 || p.x == dims.x - 1 || p.y == dims.y - 1 || p.z == dims.z - 1) return 1.0;
            return static_cast<double>(hash64(seed, p.x, p.y, p.z) % 3) - 1.0;
        };
        triangle_mesh m = marching_cubes(f, dims, vec3(100, 100, 100), vec3(0.3));
        INFO("seed " << seed);
        REQUIRE(analyze_topology(m).is_watertight());
        const std::size_t vertices = m.vertices.size(), faces = m.faces.size();
        weld_to_float(m);
        CHECK(m.vertices.size() == vertices);  // no two vertices share a float position
        CHECK(m.faces.size() == faces);
        CHECK(analyze_topology(m).is_watertight());
    }
}

TEST_CASE("marching cubes: orientation follows the iso convention", "[geometry][marching_cubes]") {
    // a plane x = 2.3 crossing the whole grid: open mesh, normals point to increasing f (+x)
    auto f = [](ivec3 p) { return p.x - 2.3; };
    const triangle_mesh m = marching_cubes(f, ivec3(5, 4, 4), vec3(0), vec3(1));
    REQUIRE(!m.empty());
    double area = 0;
    for (std::size_t i = 0; i < m.faces.size(); ++i) {
        const vec3 n = face_normal_area2(m, i);
        REQUIRE(n.x > 0);
        area += 0.5 * n.x;
    }
    CHECK(area == Approx(9.0));  // 3 x 3 mm plane
    for (const vec3& v : m.vertices) CHECK(v.x == Approx(2.3));
    const auto t = analyze_topology(m);
    CHECK(t.boundary_edges > 0);
    CHECK(t.boundary_loops == 1);
    CHECK(t.is_edge_manifold());
    CHECK(t.is_oriented());
    // the inside region touching the border is not closed; inverting the field flips normals
    const triangle_mesh flipped = marching_cubes([](ivec3 p) { return 2.3 - p.x; }, ivec3(5, 4, 4), vec3(0), vec3(1));
    CHECK(face_normal_area2(flipped, 0).x < 0);
}

TEST_CASE("marching cubes of voxel grids is watertight", "[geometry][marching_cubes]") {
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
        voxel_grid<std::uint8_t> g({7, 6, 5}, vec3(0), 2.0);
        for (std::uint64_t i = 0; i < g.size(); ++i) g.set(g.coord(i), hash_uniform(seed, i) < 0.4 ? 1 : 0);
        const auto m = marching_cubes(g);
        REQUIRE(is_watertight(m));
        REQUIRE(signed_volume(m) > 0);
        // every vertex lies on a face between voxels (midway between two centres)
        for (const vec3& v : m.vertices) REQUIRE(box3(vec3(0), vec3(14, 12, 10)).contains(v));
    }
    // a solid 4x4x4 block: vertices on its faces, volume below the block's but close
    voxel_grid<std::uint8_t> block({6, 6, 6}, vec3(0), 1.0);
    for (int z = 1; z < 5; ++z)
        for (int y = 1; y < 5; ++y)
            for (int x = 1; x < 5; ++x) block.set({x, y, z}, 1);
    const auto m = marching_cubes(block);
    CHECK(is_watertight(m));
    CHECK(analyze_topology(m).genus == 0);
    CHECK(signed_volume(m) < 64.0);
    CHECK(signed_volume(m) > 0.75 * 64.0);
    // a sparse grid works the same
    sparse_voxel_grid<std::uint8_t> sp({6, 6, 6}, vec3(0), 1.0);
    block.for_each([&](ivec3 p, std::uint8_t v) {
        if (v) sp.set(p, v);
    });
    CHECK(marching_cubes(sp) == m);
}

TEST_CASE("marching cubes: deterministic for any thread count; bad input", "[geometry][marching_cubes]") {
    auto f = [](ivec3 p) { return glm::length(vec3(p) - 20.0) - 15.3 + 0.5 * std::sin(p.x * 0.7); };
    set_num_threads(1);
    const auto a = marching_cubes(f, ivec3(41), vec3(0), vec3(1));
    set_num_threads(2);
    const auto b = marching_cubes(f, ivec3(41), vec3(0), vec3(1));
    set_num_threads(0);
    CHECK(a == b);
    CHECK_THROWS_AS(marching_cubes(f, ivec3(1, 5, 5), vec3(0), vec3(1)), invalid_input);
    CHECK_THROWS_AS(marching_cubes(f, ivec3(5), vec3(0), vec3(0, 1, 1)), invalid_input);
    CHECK_THROWS_AS(marching_cubes(f, ivec3(5), vec3(std::nan("")), vec3(1)), invalid_input);
    CHECK_THROWS_AS(marching_cubes(f, ivec3(5), vec3(0), vec3(1), std::nan("")), invalid_input);
    auto nan_at = [](ivec3 p) { return p == ivec3(2, 3, 1) ? std::nan("") : 1.0; };
    CHECK_THROWS_WITH(marching_cubes(nan_at, ivec3(5), vec3(0), vec3(1)), Catch::Contains("(2, 3, 1)"));
    // samples near +-DBL_MAX and an iso far away: vertices stay finite
    auto extreme = [](ivec3 p) { return p.x < 2 ? -1.7e308 : 1.7e308; };
    const auto e = marching_cubes(extreme, ivec3(4), vec3(0), vec3(1), 1.7e308);
    for (const vec3& v : e.vertices) REQUIRE(all_finite(v));
    CHECK_THROWS_AS(marching_cubes(f, ivec3(5), vec3(1e308), vec3(1e308)), invalid_input);
    // a field that is everywhere inside or outside gives an empty mesh
    CHECK(marching_cubes([](ivec3) { return 1.0; }, ivec3(4), vec3(0), vec3(1)).empty());
    CHECK(marching_cubes([](ivec3) { return -1.0; }, ivec3(4), vec3(0), vec3(1)).empty());
}
