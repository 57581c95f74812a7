#include <catch2/catch.hpp>

#include <fabsynth/geometry/hausdorff.hpp>
#include <fabsynth/geometry/marching_cubes.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/geometry/self_intersection.hpp>
#include <fabsynth/geometry/simplify.hpp>
#include <fabsynth/io/mesh.hpp>

#include <cmath>
#include <string>

using namespace fabsynth;

namespace {

triangle_mesh bundled_mesh(const char* name) { return io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/" + name); }

// Unit square [0,1]^2 at height z as two triangles (counter-clockwise from +z).
triangle_mesh square(double z) {
    return {{{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}}, {{0, 1, 2}, {0, 2, 3}}};
}

// The unit square with its centre raised to height h: four triangles.
triangle_mesh tent(double h) {
    return {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, h}}, {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}};
}

triangle_mesh append(triangle_mesh a, const triangle_mesh& b) {
    const auto off = static_cast<std::uint32_t>(a.vertices.size());
    a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (auto t : b.faces) a.faces.push_back({t[0] + off, t[1] + off, t[2] + off});
    return a;
}

triangle_mesh translated(triangle_mesh m, vec3 d) {
    for (vec3& v : m.vertices) v += d;
    return m;
}

// Distance from p to the torus of radii R (tube centre) and r (tube) around z through c.
double torus_distance(vec3 p, vec3 c, double R, double r) {
    p -= c;
    const double q = std::hypot(p.x, p.y) - R;
    return std::abs(std::hypot(q, p.z) - r);
}

// Marching-tetrahedra torus of radii 12 and 4 mm at a 0.4 mm grid, centred at c.
triangle_mesh torus_mesh(vec3 c) {
    const double h = 0.4;
    const vec3 origin = c - vec3(17.6, 17.6, 5.6);
    const auto f = [&](ivec3 i) {
        const vec3 p = origin + vec3(i) * h - c;
        return std::hypot(std::hypot(p.x, p.y) - 12.0, p.z) - 4.0;
    };
    return marching_cubes(f, {89, 89, 29}, origin, vec3(h));
}

}  // namespace

TEST_CASE("self-intersections: none on closed published meshes and level sets, found where surfaces cross",
          "[geometry][simplify]") {
    for (const char* name : {"kitten_lowres.obj", "fertility.obj", "torus.obj", "bunny_lowres.obj"}) {
        INFO(name);
        CHECK(find_self_intersections(bundled_mesh(name)).pairs == 0);
    }
    CHECK(find_self_intersections(torus_mesh(vec3(0))).pairs == 0);

    // two cubes side by side: none; overlapping by a third of their size: the crossing faces
    const triangle_mesh cube = bundled_mesh("cube.obj");
    const vec3 size = bounding_box(cube).size();
    CHECK(find_self_intersections(append(cube, translated(cube, vec3(1.5 * size.x, 0, 0)))).pairs == 0);
    std::vector<std::array<std::uint32_t, 2>> pairs;
    const auto crossing = find_self_intersections(append(cube, translated(cube, vec3(size.x / 3, size.y / 3, size.z / 3))), &pairs);
    CHECK(crossing.pairs > 0);
    CHECK(pairs.size() == crossing.pairs);
    CHECK((!pairs.empty() && pairs.front() == crossing.first));
    CHECK(std::all_of(pairs.begin(), pairs.end(), [&](const auto& p) { return p[0] < cube.faces.size() && p[1] >= cube.faces.size(); }));
    CHECK(crossing.first[0] < cube.faces.size());   // one face of each cube
    CHECK(crossing.first[1] >= cube.faces.size());

    // sharing one vertex: a triangle through another is found, a fan around a vertex is not
    triangle_mesh fan{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}}, {{0, 1, 2}, {0, 2, 3}}};
    CHECK(find_self_intersections(fan).pairs == 0);
    triangle_mesh pierce{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, -1}, {0.2, 0.2, 1}}, {{0, 1, 2}, {0, 3, 4}}};
    CHECK(find_self_intersections(pierce).pairs == 1);

    // sharing an edge: a fold back onto the same side is found, a flat continuation is not
    triangle_mesh flat{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}}, {{0, 1, 2}, {1, 0, 3}}};
    CHECK(find_self_intersections(flat).pairs == 0);
    triangle_mesh fold{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0.5, 0}}, {{0, 1, 2}, {1, 0, 3}}};
    CHECK(find_self_intersections(fold).pairs == 1);

    // touching at a point without sharing a vertex counts
    triangle_mesh touch{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, 0}, {0.25, 0.25, 1}, {1, 1, 1}}, {{0, 1, 2}, {3, 4, 5}}};
    CHECK(find_self_intersections(touch).pairs == 1);
}

TEST_CASE("Hausdorff interval holds the analytic distance", "[geometry][simplify]") {
    // parallel squares 0.3 apart: exactly 0.3 both ways
    auto h = hausdorff_distance(square(0), square(0.3), {.precision = 0.002});
    CHECK(h.lower <= 0.3 + 1e-12);
    CHECK(h.upper >= 0.3 - 1e-12);
    CHECK(h.upper - h.lower <= 0.002 + 1e-12);

    // a tent of height 0.2 over the square: from the tent the apex is 0.2 from the square; from the
    // square the farthest point is its centre, at distance h/2 / sqrt(1/4 + h^2) from a tent face
    const double th = 0.2;
    const double centre = 0.5 * th / std::sqrt(0.25 + th * th);
    const mesh_distance to_square(square(0)), to_tent(tent(th));
    const auto up = one_sided_hausdorff(tent(th), to_square, {.precision = 2e-3});
    CHECK(up.lower == Approx(th).margin(1e-12));
    CHECK(up.upper <= th + 2e-3 + 1e-12);
    const auto down = one_sided_hausdorff(square(0), to_tent, {.precision = 2e-3});
    CHECK(down.lower <= centre + 1e-12);
    CHECK(down.upper >= centre - 1e-12);
    CHECK(down.upper - down.lower <= 2e-3 + 1e-12);

    // identical meshes: 0
    const auto same = hausdorff_distance(tent(th), tent(th), {.precision = 2e-3});
    CHECK(same.lower <= 1e-12);
    CHECK(same.upper <= 2e-3);

    // stop_below: refinement stops once the bound is small, and the bound stays a bound
    const auto coarse = one_sided_hausdorff(square(0), to_tent, {.precision = 2e-3, .stop_below = 0.5});
    CHECK(coarse.upper >= centre);
    CHECK(coarse.upper <= 0.5 + 1e-12);  // the true distance is far below: refinement stops at the threshold

    CHECK_THROWS_AS(one_sided_hausdorff(square(0), to_tent, {.precision = 0}), invalid_input);
    CHECK_THROWS_AS(one_sided_hausdorff(square(0), to_tent, {.precision = 1e-3, .stop_below = -1}), invalid_input);
}

TEST_CASE("simplify_mesh: a level-set torus keeps its topology and stays within the tolerance of the true torus",
          "[geometry][simplify]") {
    const triangle_mesh raw = append(torus_mesh(vec3(0)), torus_mesh(vec3(40, 0, 0)));
    // the raw level set's own distance to the analytic torus (the extraction error)
    double raw_error = 0;
    for (const vec3& v : raw.vertices)
        raw_error = std::max(raw_error, std::min(torus_distance(v, vec3(0), 12, 4), torus_distance(v, vec3(40, 0, 0), 12, 4)));
    REQUIRE(raw_error < 0.03);

    const double tol = 0.05;
    simplify_report rep;
    const triangle_mesh s = simplify_mesh(raw, {.tolerance = tol}, &rep);
    INFO(rep.warning);
    REQUIRE(rep.simplified);
    CHECK(rep.raw_faces == raw.faces.size());
    CHECK(rep.faces == s.faces.size());
    CHECK(s.faces.size() * 4 < raw.faces.size());  // at least 4x fewer faces
    CHECK(rep.hausdorff.upper <= tol);
    CHECK(rep.hausdorff.lower <= rep.hausdorff.upper);

    const auto t = analyze_topology(s);
    CHECK(t.is_watertight());
    CHECK(t.components == 2);
    CHECK(t.genus == 2);  // sum over the two tori
    CHECK(find_self_intersections(s).pairs == 0);

    // oracle: the analytic torus; points sampled inside every face are within tol + the raw error
    double worst = 0;
    for (const auto& f : s.faces)
        for (const vec3 w : {vec3(1, 1, 1) / 3.0, vec3(0.6, 0.2, 0.2), vec3(0.2, 0.6, 0.2), vec3(0.2, 0.2, 0.6), vec3(0.5, 0.5, 0)}) {
            const vec3 p = w.x * s.vertices[f[0]] + w.y * s.vertices[f[1]] + w.z * s.vertices[f[2]];
            worst = std::max(worst, std::min(torus_distance(p, vec3(0), 12, 4), torus_distance(p, vec3(40, 0, 0), 12, 4)));
        }
    CHECK(worst <= tol + raw_error);
    CHECK(worst <= rep.hausdorff.upper + raw_error);

    // deterministic, and every output vertex is an input vertex (exact positions)
    CHECK(simplify_mesh(raw, {.tolerance = tol}) == s);
    CHECK(std::all_of(s.vertices.begin(), s.vertices.end(), [&](const vec3& v) {
        return std::find(raw.vertices.begin(), raw.vertices.end(), v) != raw.vertices.end();
    }));
}

// A gyroid sheet about 1.5 mm thick (period 16 mm) clipped to a ball of radius 9 mm, marching
// tetrahedra at the surface-pattern bunny's 0.39 mm voxel: curved everywhere, with a crease all
// along the rim and two sides close together, the case where quadric costs alone let the input
// stray from the result (the collapses' tracked bound is what keeps it).
static triangle_mesh gyroid_ball() {
    const double h = 0.39;
    const vec3 origin(-9.9);
    const auto f = [&](ivec3 i) {
        const vec3 p = origin + vec3(i) * h;
        const double k = 2 * 3.14159265358979 / 16.0;
        const double g = std::sin(k * p.x) * std::cos(k * p.y) + std::sin(k * p.y) * std::cos(k * p.z) + std::sin(k * p.z) * std::cos(k * p.x);
        return std::max(std::abs(g) - 0.35, glm::length(p) - 9.0);
    };
    return marching_cubes(f, {52, 52, 52}, origin, vec3(h));
}

TEST_CASE("simplify_mesh: a creased, curved, thin gyroid sheet passes at half a voxel", "[geometry][simplify]") {
    const triangle_mesh raw = gyroid_ball();
    const double tol = 0.195;
    simplify_report rep;
    const triangle_mesh s = simplify_mesh(raw, {.tolerance = tol}, &rep);
    INFO(rep.warning);
    REQUIRE(rep.simplified);
    CHECK(s.faces.size() * 6 < raw.faces.size());
    const auto t0 = analyze_topology(raw), t1 = analyze_topology(s);
    CHECK(t1.is_watertight());
    CHECK(t1.components == t0.components);
    CHECK(t1.genus == t0.genus);
    CHECK(find_self_intersections(s).pairs == 0);
    // every input vertex lies within the tracked 0.8 tolerance of the result
    const mesh_distance to_result(s);
    double worst = 0;
    for (const vec3& v : raw.vertices) worst = std::max(worst, std::sqrt(to_result.closest(v).dist2));
    CHECK(worst <= 0.8 * tol + 1e-9);
    // the bound recomputed from scratch, finer than the check inside simplify_mesh
    const hausdorff_interval h = hausdorff_distance(raw, s, {.precision = tol / 10});
    CHECK(h.upper <= tol);
    CHECK(h.lower >= worst - 1e-9);
}

TEST_CASE("simplify_mesh: a flat-sided cube collapses to few faces; bad options are refused", "[geometry][simplify]") {
    const auto f = [](ivec3 i) {
        const vec3 p = vec3(i) * 0.5 - 5.0;
        return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) - 3.7;
    };
    const triangle_mesh raw = marching_cubes(f, {21, 21, 21}, vec3(-5), vec3(0.5));
    simplify_report rep;
    const triangle_mesh s = simplify_mesh(raw, {.tolerance = 0.05}, &rep);
    INFO(rep.warning);
    REQUIRE(rep.simplified);
    CHECK(s.faces.size() * 10 < raw.faces.size());
    CHECK(analyze_topology(s).genus == 0);
    CHECK(std::abs(signed_volume(s) - signed_volume(raw)) < 1e-6 * signed_volume(raw) + 7.4 * 7.4 * 6 * 0.05);

    CHECK_THROWS_AS(simplify_mesh(raw, {.tolerance = 0}), invalid_input);
    CHECK_THROWS_AS(simplify_mesh(raw, {.tolerance = std::nan("")}), invalid_input);
    CHECK_THROWS_AS(simplify_mesh(raw, {.tolerance = 0.1, .attempts = 0}), invalid_input);
    triangle_mesh broken = raw;
    broken.faces[0][0] = static_cast<std::uint32_t>(raw.vertices.size());
    CHECK_THROWS_AS(simplify_mesh(broken, {.tolerance = 0.1}), invalid_input);
    // a vertex no face uses, far away, is ignored
    triangle_mesh stray = raw;
    stray.vertices.push_back(vec3(100, 100, 100));
    simplify_report sr;
    CHECK(simplify_mesh(stray, {.tolerance = 0.05}, &sr).faces.size() == s.faces.size());
    CHECK(sr.simplified);
    // a mesh that already crosses itself comes back as it is, saying so
    const triangle_mesh crossed = append(raw, translated(raw, vec3(2, 1, 1)));
    simplify_report xr;
    CHECK(simplify_mesh(crossed, {.tolerance = 0.05}, &xr) == crossed);
    CHECK_FALSE(xr.simplified);
    CHECK(xr.warning.find("self-intersecting") != std::string::npos);
    // nothing to do: an empty mesh comes back with a warning
    simplify_report empty;
    CHECK(simplify_mesh(triangle_mesh{}, {.tolerance = 0.1}, &empty).faces.empty());
    CHECK_FALSE(empty.simplified);
    CHECK_FALSE(empty.warning.empty());
}
