#include <catch2/catch.hpp>

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/core/rng.hpp>
#include <fabsynth/geometry/marching_cubes.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/geometry/self_intersection.hpp>
#include <fabsynth/geometry/smooth.hpp>

#include <numbers>

#include "support/sphere_mesh.hpp"

using namespace fabsynth;

namespace {

// Standard deviation of the vertex radii (distance to the origin) and their mean.
struct radii {
    double mean = 0, sd = 0;
};
radii radial_stats(const triangle_mesh& m) {
    radii r;
    for (const vec3& v : m.vertices) r.mean += glm::length(v);
    r.mean /= static_cast<double>(m.vertices.size());
    for (const vec3& v : m.vertices) r.sd += (glm::length(v) - r.mean) * (glm::length(v) - r.mean);
    r.sd = std::sqrt(r.sd / static_cast<double>(m.vertices.size()));
    return r;
}

// A flat n x n grid of vertices in z = 0 (open mesh: its rim is a boundary).
triangle_mesh flat_patch(int n) {
    triangle_mesh m;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) m.vertices.push_back({i, j, 0});
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const auto a = static_cast<std::uint32_t>(j * n + i), b = a + 1, c = a + static_cast<std::uint32_t>(n), d = c + 1;
            m.faces.push_back({a, b, d});
            m.faces.push_back({a, d, c});
        }
    return m;
}

}  // namespace

TEST_CASE("taubin: noisy sphere loses its noise, keeps its volume, faces and watertightness", "[geometry][smooth]") {
    const double r = 10.0;
    const triangle_mesh clean = test::sphere_mesh(r, 4);
    triangle_mesh noisy = clean;
    counter_rng rng(3);
    for (vec3& v : noisy.vertices) v *= 1.0 + 0.02 * (rng.uniform() - 0.5);
    const radii r0 = radial_stats(noisy);
    triangle_mesh smooth = noisy;
    taubin_smooth(smooth, {.iterations = 10});
    CHECK(smooth.faces == noisy.faces);
    CHECK(is_watertight(smooth));
    const radii r1 = radial_stats(smooth);
    INFO("radius " << r0.mean << " +- " << r0.sd << " -> " << r1.mean << " +- " << r1.sd << ", volume " << signed_volume(clean)
                   << " (clean) " << signed_volume(noisy) << " (noisy) -> " << signed_volume(smooth));
    CHECK(r1.sd < 0.5 * r0.sd);  // measured 0.41
    // Taubin does not shrink like Laplacian smoothing (it amplifies frequencies below
    // k_PB = 1/lambda + 1/mu a little: the sphere grows by ~0.1% in radius per iteration)
    CHECK(signed_volume(smooth) == Approx(signed_volume(clean)).epsilon(0.01));
    // the same number of plain Laplacian steps (lambda only) would shrink it: compare with mu
    // close to -lambda (almost no inflation), which must shrink more
    triangle_mesh weak = noisy;
    taubin_smooth(weak, {.iterations = 10, .lambda = 0.5, .mu = -0.5001});
    CHECK(signed_volume(weak) < signed_volume(smooth));
}

TEST_CASE("taubin: voxel staircase of marching tetrahedra becomes smoother", "[geometry][smooth]") {
    // binary occupancy of a ball: vertices half-way between voxel centres, a staircase
    const int n = 40;
    const double R = 15.0;
    auto f = [&](ivec3 p) { return glm::length(vec3(p) - 0.5 * n) < R ? -1.0 : 1.0; };
    triangle_mesh m = marching_cubes(f, ivec3(n + 1), vec3(-0.5 * n), vec3(1.0));
    const radii r0 = radial_stats(m);
    triangle_mesh more = m;
    taubin_smooth(m);
    taubin_smooth(more, {.iterations = 50});
    const radii r1 = radial_stats(m), r2 = radial_stats(more);
    INFO("staircase radius " << r0.mean << " +- " << r0.sd << " -> " << r1.mean << " +- " << r1.sd << " (10 pairs), " << r2.mean
                             << " +- " << r2.sd << " (50 pairs)");
    CHECK(r1.sd < 0.8 * r0.sd);  // measured 0.74
    CHECK(r2.sd < 0.6 * r0.sd);  // measured 0.57
    CHECK(std::abs(r1.mean - R) < 0.1);
    CHECK(is_watertight(more));
    CHECK(is_watertight(m));
    CHECK(signed_volume(m) == Approx(4.0 / 3.0 * std::numbers::pi * R * R * R).epsilon(0.02));
}

TEST_CASE("taubin: boundary vertices of open meshes are fixed, a plane stays a plane", "[geometry][smooth]") {
    triangle_mesh m = flat_patch(12);
    // bump the interior out of plane and jitter it in plane
    counter_rng rng(5);
    for (vec3& v : m.vertices)
        if (v.x > 0 && v.y > 0 && v.x < 11 && v.y < 11) v += vec3(0.2 * rng.uniform(), 0.2 * rng.uniform(), rng.uniform() - 0.5);
    const triangle_mesh before = m;
    taubin_smooth(m, {.iterations = 50});
    double zmax_before = 0, zmax_after = 0;
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
        const vec3 &a = before.vertices[i], &b = m.vertices[i];
        const bool rim = a.x == 0 || a.y == 0 || a.x == 11 || a.y == 11;
        if (rim) REQUIRE(a == b);  // bit-identical
        zmax_before = std::max(zmax_before, std::abs(a.z));
        zmax_after = std::max(zmax_after, std::abs(b.z));
    }
    INFO("max |z| " << zmax_before << " -> " << zmax_after);
    CHECK(zmax_after < 0.5 * zmax_before);
    // an exactly planar grid does not leave its plane
    triangle_mesh flat = flat_patch(8);
    taubin_smooth(flat, {.iterations = 10});
    for (const vec3& v : flat.vertices) CHECK(v.z == 0.0);
    // unused vertices stay where they are
    triangle_mesh extra = flat_patch(4);
    extra.vertices.push_back({7, 7, 7});
    taubin_smooth(extra);
    CHECK(extra.vertices.back() == vec3(7, 7, 7));
}

TEST_CASE("taubin: adjacency, zero iterations, determinism and bad input", "[geometry][smooth]") {
    const triangle_mesh sphere = test::sphere_mesh(5.0, 3);
    const mesh_adjacency a = vertex_adjacency(sphere);
    // closed triangle mesh: every edge in two faces, sum of degrees = 2 E = 3 F
    CHECK(a.nbr.size() == 3 * sphere.faces.size());
    for (auto b : a.boundary) CHECK(b == 0);
    for (std::size_t v = 0; v + 1 < a.off.size(); ++v)
        for (std::size_t k = a.off[v] + 1; k < a.off[v + 1]; ++k) REQUIRE(a.nbr[k - 1] < a.nbr[k]);

    triangle_mesh same = sphere;
    taubin_smooth(same, {.iterations = 0});
    CHECK(same == sphere);

    triangle_mesh noisy = test::sphere_mesh(5.0, 5);
    counter_rng rng(9);
    for (vec3& v : noisy.vertices) v *= 1.0 + 0.05 * rng.uniform();
    triangle_mesh one = noisy, two = noisy;
    set_num_threads(1);
    taubin_smooth(one, {.iterations = 7});
    set_num_threads(2);
    taubin_smooth(two, {.iterations = 7});
    set_num_threads(0);
    CHECK(one == two);

    triangle_mesh m = sphere;
    CHECK_THROWS_AS(taubin_smooth(m, {.iterations = -1}), invalid_input);
    CHECK_THROWS_AS(taubin_smooth(m, {.lambda = 0.0}), invalid_input);
    CHECK_THROWS_AS(taubin_smooth(m, {.lambda = 1.5, .mu = -1.6}), invalid_input);
    CHECK_THROWS_AS(taubin_smooth(m, {.lambda = 0.5, .mu = -0.4}), invalid_input);    // |mu| must exceed lambda
    CHECK_THROWS_AS(taubin_smooth(m, {.lambda = 0.5, .mu = -1.5}), invalid_input);
    CHECK_THROWS_AS(taubin_smooth(m, {.lambda = std::nan(""), .mu = -0.53}), invalid_input);
    CHECK(m == sphere);  // nothing happened
    m.faces.push_back({0, 1, static_cast<std::uint32_t>(m.vertices.size())});
    CHECK_THROWS_AS(taubin_smooth(m), invalid_input);
    triangle_mesh nan = sphere;
    nan.vertices[3].y = std::nan("");
    CHECK_THROWS_AS(taubin_smooth(nan), invalid_input);
}

TEST_CASE("taubin on grid edges: a voxel ball gets rounder, every vertex stays on its edge within half a voxel", "[geometry][smooth]") {
    // binary occupancy of a ball of radius 12.3 voxels at a 0.4 mm grid, origin off zero
    const int n = 32;
    const double h = 0.4, R = 12.3 * h;
    const vec3 origin(1.0, -2.0, 0.5), centre = origin + vec3(15.5 * h);
    auto f = [&](ivec3 p) { return glm::length(origin + vec3(p) * h - centre) < R ? -1.0 : 1.0; };
    const triangle_mesh raw = marching_cubes(f, ivec3(n), origin, vec3(h));
    triangle_mesh m = raw;
    taubin_smooth_on_grid_edges(m, origin, vec3(h), {.iterations = 50});
    CHECK(m.faces == raw.faces);
    // oracle: the analytic sphere; the staircase error drops by about half (measured 0.274 -> 0.149 voxels rms)
    const auto rms = [&](const triangle_mesh& x) {
        double e = 0;
        for (const vec3& v : x.vertices) e += std::pow(glm::length(v - centre) - R, 2);
        return std::sqrt(e / static_cast<double>(x.vertices.size())) / h;
    };
    INFO("rms distance to the sphere, voxels: " << rms(raw) << " -> " << rms(m));
    CHECK(rms(m) < 0.6 * rms(raw));
    // each vertex moved along its grid edge (the line through its start), at most half a voxel
    double worst_move = 0, worst_off_line = 0;
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        const vec3 g = (raw.vertices[v] - origin) / h * 2.0;
        const vec3 d(std::fmod(std::abs(std::round(g.x)), 2.0), std::fmod(std::abs(std::round(g.y)), 2.0), std::fmod(std::abs(std::round(g.z)), 2.0));
        const vec3 move = m.vertices[v] - raw.vertices[v];
        worst_move = std::max(worst_move, glm::length(move) / h);
        worst_off_line = std::max(worst_off_line, glm::length(glm::cross(move, glm::normalize(d))) / h);
    }
    CHECK(worst_move <= 0.5 + 1e-9);
    CHECK(worst_off_line < 1e-9);
}

TEST_CASE("taubin on grid edges: thin and random voxel sets never cross themselves", "[geometry][smooth]") {
    // sparse random voxels: after 200 pairs, unconstrained smoothing lets nearby sheets pass
    // through each other (70 crossing face pairs), the edge-held one cannot
    counter_rng rng(11);
    const int n = 24;
    std::vector<std::uint8_t> solid(static_cast<std::size_t>(n * n * n));
    for (auto& s : solid) s = rng.uniform() < 0.2;
    auto f = [&](ivec3 p) {
        if (glm::any(glm::lessThan(p, ivec3(1))) || glm::any(glm::greaterThan(p, ivec3(n - 2)))) return 1.0;
        return solid[static_cast<std::size_t>((p.z * n + p.y) * n + p.x)] ? -1.0 : 1.0;
    };
    const triangle_mesh raw = marching_cubes(f, ivec3(n), vec3(0), vec3(1));
    REQUIRE(find_self_intersections(raw).pairs == 0);
    triangle_mesh m = raw, free = raw;
    taubin_smooth_on_grid_edges(m, vec3(0), vec3(1), {.iterations = 200});
    taubin_smooth(free, {.iterations = 200});
    CHECK(find_self_intersections(free).pairs > 0);  // the case is one where it matters
    CHECK(find_self_intersections(m).pairs == 0);
    CHECK(analyze_topology(m).genus == analyze_topology(raw).genus);
    CHECK(analyze_topology(m).components == analyze_topology(raw).components);
    // deterministic for any thread count
    triangle_mesh again = raw;
    set_num_threads(1);
    taubin_smooth_on_grid_edges(again, vec3(0), vec3(1), {.iterations = 200});
    set_num_threads(0);
    CHECK(again.vertices == m.vertices);
}

TEST_CASE("taubin on grid edges: bad input is refused", "[geometry][smooth]") {
    triangle_mesh off_grid{{{0.5, 0, 0}, {0, 0.5, 0}, {0.3, 0.3, 0.1}}, {{0, 1, 2}}};
    CHECK_THROWS_AS(taubin_smooth_on_grid_edges(off_grid, vec3(0), vec3(1)), invalid_input);   // vertex 2 is not a midpoint
    triangle_mesh at_point{{{0.5, 0, 0}, {0, 0.5, 0}, {1, 1, 0}}, {{0, 1, 2}}};
    CHECK_THROWS_AS(taubin_smooth_on_grid_edges(at_point, vec3(0), vec3(1)), invalid_input);  // vertex 2 is a grid point
    triangle_mesh ok{{{0.5, 0, 0}, {0, 0.5, 0}, {0.5, 0.5, 1}}, {{0, 1, 2}}};
    CHECK_THROWS_AS(taubin_smooth_on_grid_edges(ok, vec3(0), vec3(1), {}, 0.0), invalid_input);
    CHECK_THROWS_AS(taubin_smooth_on_grid_edges(ok, vec3(0), vec3(1), {}, 0.6), invalid_input);
    CHECK_THROWS_AS(taubin_smooth_on_grid_edges(ok, vec3(0), vec3(0, 1, 1)), invalid_input);
    CHECK_THROWS_AS(taubin_smooth_on_grid_edges(ok, vec3(0), vec3(1), {.iterations = -1}), invalid_input);
    CHECK_NOTHROW(taubin_smooth_on_grid_edges(ok, vec3(0), vec3(1)));
}
