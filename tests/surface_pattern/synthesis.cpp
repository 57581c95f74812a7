#include <catch2/catch.hpp>

#include "support/test_util.hpp"

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/core/rng.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/surface_pattern/synthesis.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <set>

using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

namespace {

/// A flat square plate [0, L]^2 at z = 0 (two triangles, normal +z).
triangle_mesh plate(double L) {
    triangle_mesh m;
    m.vertices = {{0, 0, 0}, {L, 0, 0}, {L, L, 0}, {0, L, 0}};
    m.faces = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

sp::exemplar load_exemplar(const std::string& name, double feature_px, bool colour = false) {
    const image8 mask = io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/" + name + ".png");
    if (!colour) return sp::make_exemplar(mask, nullptr, {.feature_px = feature_px});
    const image8 c = io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/" + name + "_color.png");
    return sp::make_exemplar(mask, &c, {.feature_px = feature_px});
}

sp::surface_shell bunny_shell(int resolution) {
    return sp::make_shell(io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj"), {.size_mm = 60, .resolution = resolution});
}


}  // namespace

TEST_CASE("surface shell: pyramid links, area conservation, unit normals, symmetric neighbourhoods", "[surface_pattern][synthesis]") {
    const sp::surface_shell s = bunny_shell(48);
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, sp::default_levels(48));
    REQUIRE(pyr.levels.size() == 6);
    double area0 = 0;
    for (double a : s.area) area0 += a;
    for (std::size_t l = 0; l < pyr.levels.size(); ++l) {
        const sp::shell_level& lv = pyr.levels[l];
        double area = 0;
        for (std::size_t v = 0; v < lv.size(); ++v) {
            area += lv.area[v];
            CHECK(std::abs(glm::length(lv.normals[v]) - 1.0) < 1e-9);
            if (v) CHECK(lv.geometry.index(lv.voxels[v - 1]) < lv.geometry.index(lv.voxels[v]));  // sorted, unique
            CHECK(lv.find(lv.voxels[v]) == static_cast<std::int64_t>(v));
        }
        CHECK(area == Approx(area0).epsilon(1e-12));  // every level encloses the same surface
        if (l + 1 < pyr.levels.size()) {
            const sp::shell_level& up = pyr.levels[l + 1];
            std::vector<int> seen(up.size(), 0);
            for (std::size_t v = 0; v < lv.size(); ++v) {
                const ivec3 p = lv.voxels[v];
                CHECK(up.voxels[lv.parent[v]] == ivec3(p.x >> 1, p.y >> 1, p.z >> 1));
                ++seen[lv.parent[v]];
            }
            for (std::size_t P = 0; P < up.size(); ++P) {
                CHECK(seen[P] == static_cast<int>(up.child_offset[P + 1] - up.child_offset[P]));  // child lists = inverse of parent
                for (std::uint32_t k = up.child_offset[P]; k < up.child_offset[P + 1]; ++k) CHECK(lv.parent[up.child_index[k]] == P);
            }
        }
    }
    // the 5x5x5 neighbourhood against a brute-force scan of level 1
    const sp::shell_level& lv = pyr.levels[1];
    const sp::shell_neighbourhood nb = sp::build_neighbourhood(lv, 2);
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (std::size_t v = 0; v < lv.size(); ++v)
        for (std::uint32_t k = nb.offset[v]; k < nb.offset[v + 1]; ++k) pairs.insert({static_cast<std::uint32_t>(v), nb.index[k]});
    std::size_t brute = 0;
    for (std::size_t v = 0; v < lv.size(); ++v)
        for (std::size_t w = 0; w < lv.size(); ++w) {
            const ivec3 d = glm::abs(lv.voxels[v] - lv.voxels[w]);
            if (v != w && d.x <= 2 && d.y <= 2 && d.z <= 2) {
                ++brute;
                CHECK(pairs.count({static_cast<std::uint32_t>(v), static_cast<std::uint32_t>(w)}) == 1);
            }
        }
    CHECK(brute == pairs.size());
}

TEST_CASE("label space: 26 unit plane normals, right-handed frames, nearest plane equals brute force", "[surface_pattern][synthesis]") {
    const sp::label_space ls(128, 64, {.mm_per_px = 0.5});
    for (int p = 0; p < sp::label_space::plane_count; ++p) {
        const vec3 n = ls.normal(p), r = ls.right(p), b = ls.up(p);
        CHECK(std::abs(glm::length(n) - 1) < 1e-12);
        CHECK(std::abs(glm::dot(r, b)) < 1e-12);
        CHECK(glm::length(glm::cross(r, b) - n) < 1e-12);  // r x b = n: seen from outside, not mirrored
    }
    counter_rng rng(5);
    for (int i = 0; i < 20000; ++i) {
        const vec3 d(rng.normal(), rng.normal(), rng.normal());
        double best = -2;
        for (int p = 0; p < sp::label_space::plane_count; ++p) best = std::max(best, glm::dot(ls.normal(p), d));
        CHECK(glm::dot(ls.normal(ls.nearest_plane(d)), d) == Approx(best).epsilon(1e-12));
    }
    // the aligned rotation turns the exemplar's up (-y in pixels) onto the requested direction
    for (int p = 0; p < sp::label_space::plane_count; ++p) {
        const vec3 d = glm::normalize(ls.right(p) + 0.3 * ls.up(p));
        const std::uint32_t l = sp::label_space::make(p, ls.aligned_rotation(p, d), 0, 0);
        const vec2 a = ls.map(vec3(0), l), b = ls.map(d, l);
        const vec2 dir = glm::normalize(b - a);
        CHECK(dir.y < -0.99);  // within one rotation step (5.6 degrees) of straight up
    }
}

TEST_CASE("planar oracle: one plane and the identity transform reproduce the exemplar at the voxel centres exactly",
          "[surface_pattern][synthesis]") {
    const double L = 40;
    const sp::surface_shell s = sp::make_shell(plate(L), {.size_mm = L, .resolution = 40});
    REQUIRE(s.size() == 40u * 40u);  // one layer: the plate lies in the middle of a voxel layer
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, 6);
    const image8 mask = io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/hooks.png");
    sp::exemplar ex = sp::make_exemplar(mask, nullptr, {.feature_px = 5});
    const sp::label_space probe(ex.width(), ex.height(), {.mm_per_px = 1});
    const int plane = probe.nearest_plane(vec3(0, 0, 1));
    sp::synthesizer syn(pyr, ex, {.allowed_labels = {sp::label_space::make(plane, 0, 0, 0)}});
    const sp::synthesis_result r = syn.synthesize();
    // oracle, from the documented frame of the +z plane under up = +z: b = +y, r = +x; pixel = (x, -y) / s,
    // s = one voxel (1 mm): voxel centres fall on pixel centres, so the state is one mask pixel
    const grid_geometry& g = pyr.levels[0].geometry;
    std::size_t checked = 0;
    for (std::size_t v = 0; v < s.size(); ++v) {
        const vec3 c = g.center(s.voxels[v]);
        const long px = static_cast<long>(std::floor(c.x)), py = static_cast<long>(std::floor(-c.y));
        const long i = ((px % 128) + 128) % 128, j = ((py % 128) + 128) % 128;
        const bool expected = mask.at(static_cast<int>(i), static_cast<int>(j)) >= 128;
        CHECK((r.solid[v] != 0) == expected);
        ++checked;
    }
    CHECK(checked == 1600);
}

TEST_CASE("synthesis on a plate: the optimizer picks the plate's plane everywhere", "[surface_pattern][synthesis]") {
    const sp::surface_shell s = sp::make_shell(plate(40), {.size_mm = 40, .resolution = 40});
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, 6);
    sp::synthesizer syn(pyr, load_exemplar("zebra", 6), {.seed = 3});
    const sp::synthesis_result r = syn.synthesize();
    std::size_t aligned = 0;
    for (std::size_t v = 0; v < s.size(); ++v)
        aligned += glm::dot(syn.labels().normal(sp::label_space::plane(r.labels[0][v])), s.normals[v]) > 0.999 ? 1 : 0;
    INFO("aligned " << aligned << " of " << s.size());
    CHECK(aligned == s.size());
}

TEST_CASE("synthesis on the bunny: no pass increases the energy, the result is far below random labels, states match the labels",
          "[surface_pattern][synthesis]") {
    const sp::surface_shell s = bunny_shell(64);
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, sp::default_levels(64));
    sp::synthesizer syn(pyr, load_exemplar("hooks", 5, true), {.passes = 3, .seed = 11});
    const sp::synthesis_result r = syn.synthesize();
    REQUIRE(r.levels.size() == pyr.levels.size());
    for (const sp::level_report& l : r.levels) {
        REQUIRE(l.energy_passes.size() == 3);
        double prev = l.energy_initial;
        for (double e : l.energy_passes) {
            CHECK(e <= prev + 1e-6 * std::abs(prev) + 1e-9);
            prev = e;
        }
        // the reported energy is the energy of the labels returned
        CHECK(syn.energy(l.level, r.labels[static_cast<std::size_t>(l.level)]) == Approx(l.energy_passes.back()).epsilon(1e-12));
    }
    // random labels drawn the way OPTIMIZE draws them
    std::vector<std::uint32_t> random(pyr.levels[0].size());
    for (std::size_t v = 0; v < random.size(); ++v) {
        counter_rng rng(99, v);
        random[v] = syn.random_label(0, v, rng);
    }
    const double ratio = r.levels[0].energy_passes.back() / syn.energy(0, random);
    INFO("final / random energy " << ratio);
    CHECK(ratio < 0.3);
    CHECK(syn.states(0, r.labels[0]) == r.solid);
}

TEST_CASE("synthesis is identical for 1 and 2 threads and depends on the seed", "[surface_pattern][synthesis]") {
    test::thread_count_guard guard;
    const sp::surface_shell s = bunny_shell(48);
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, sp::default_levels(48));
    const sp::exemplar ex = load_exemplar("spots", 5);
    set_num_threads(1);
    const sp::synthesis_result a = sp::synthesizer(pyr, ex, {.seed = 4}).synthesize();
    set_num_threads(2);
    const sp::synthesis_result b = sp::synthesizer(pyr, ex, {.seed = 4}).synthesize();
    const sp::synthesis_result c = sp::synthesizer(pyr, ex, {.seed = 5}).synthesize();
    CHECK(a.labels == b.labels);
    CHECK(a.solid == b.solid);
    for (std::size_t l = 0; l < a.levels.size(); ++l) CHECK(a.levels[l].energy_passes == b.levels[l].energy_passes);
    CHECK(a.labels[0] != c.labels[0]);
}

TEST_CASE("constrained resynthesis: forced voxels end solid, nothing outside the allowed region changes", "[surface_pattern][synthesis]") {
    const sp::surface_shell s = bunny_shell(64);
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, sp::default_levels(64));
    const sp::synthesizer syn(pyr, load_exemplar("hooks", 5), {.seed = 2});
    sp::synthesis_result r = syn.synthesize();
    const sp::synthesis_result before = r;
    const sp::shell_level& l0 = pyr.levels[0];
    // a bridge: the empty voxels within 2 voxels of a segment between two shell voxels; the region: within 6 voxels
    const vec3 a = l0.center(l0.size() / 3), b = a + 6.0 * l0.geometry.spacing.x * glm::normalize(glm::cross(l0.normals[l0.size() / 3], vec3(0.3, 0.2, 1)));
    std::vector<std::uint8_t> forced(l0.size(), 0), allowed(l0.size(), 0);
    std::size_t nforced = 0;
    for (std::size_t v = 0; v < l0.size(); ++v) {
        const vec3 x = l0.center(v), ab = b - a;
        const double t = std::clamp(glm::dot(x - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
        const double d = glm::length(x - (a + t * ab)) / l0.geometry.spacing.x;
        if (d <= 2 && !r.solid[v]) forced[v] = 1, ++nforced;
        if (d <= 6) allowed[v] = 1;
    }
    REQUIRE(nforced > 10);
    const sp::resynthesis_report rep = syn.resynthesize(r, forced, allowed, 4.0);
    CHECK(rep.start_level == 2);
    CHECK(rep.forced == nforced);
    CHECK(rep.unsatisfied == 0);
    std::size_t changed = 0;
    for (std::size_t v = 0; v < l0.size(); ++v) {
        if (forced[v]) CHECK(r.solid[v] == 1);
        if (!allowed[v]) {
            CHECK(r.labels[0][v] == before.labels[0][v]);
            CHECK(r.solid[v] == before.solid[v]);
        }
        changed += r.labels[0][v] != before.labels[0][v];
    }
    CHECK(changed > 0);
    for (std::size_t l = 3; l < pyr.levels.size(); ++l) CHECK(r.labels[l] == before.labels[l]);  // above the start level: untouched
    CHECK(r.solid == syn.states(0, r.labels[0]));  // every forced voxel got a solid-mapping label
}

TEST_CASE("surface shell: open, non-manifold and inward-oriented meshes follow the documented behaviour", "[surface_pattern][synthesis]") {
    // open (a plate) and non-manifold (three fins on one edge): voxelized like any surface
    triangle_mesh fins;
    fins.vertices = {{0, 0, 0}, {0, 0, 10}, {10, 0, 5}, {-5, 8, 5}, {-5, -8, 5}};
    fins.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    const sp::surface_shell f = sp::make_shell(fins, {.size_mm = 20, .resolution = 32});
    CHECK(f.size() > 100);
    for (const vec3& n : f.normals) CHECK(std::abs(glm::length(n) - 1) < 1e-9);
    // an inward-oriented closed mesh gives the same outward normals as the outward one
    triangle_mesh bunny = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj");
    const sp::surface_shell out = sp::make_shell(bunny, {.size_mm = 30, .resolution = 32});
    for (auto& t : bunny.faces) std::swap(t[1], t[2]);
    const sp::surface_shell in = sp::make_shell(bunny, {.size_mm = 30, .resolution = 32});
    REQUIRE(in.voxels == out.voxels);
    for (std::size_t v = 0; v < in.size(); ++v) CHECK(glm::length(in.normals[v] - out.normals[v]) < 1e-12);
}

TEST_CASE("surface shell and synthesizer refuse bad input with invalid_input", "[surface_pattern][synthesis]") {
    triangle_mesh m = plate(10);
    CHECK_THROWS_AS(sp::make_shell(triangle_mesh{}, {.size_mm = 10}), invalid_input);
    CHECK_THROWS_AS(sp::make_shell(m, {.size_mm = 0}), invalid_input);
    CHECK_THROWS_AS(sp::make_shell(m, {.size_mm = 10, .resolution = 2}), invalid_input);
    m.vertices[1].x = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(sp::make_shell(m, {.size_mm = 10}), invalid_input);
    // refused from the estimate, before any voxel is allocated
    const triangle_mesh bunny = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj");
    CHECK_THROWS_WITH(sp::make_shell(bunny, {.size_mm = 100, .resolution = 4096, .max_memory_bytes = 1e9}), Catch::Contains("GiB"));
    const sp::surface_shell s = sp::make_shell(plate(10), {.size_mm = 10, .resolution = 16});
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, 4);
    CHECK_THROWS_AS(sp::build_shell_pyramid(s, 0), invalid_input);
    const sp::exemplar ex = load_exemplar("spots", 5);
    CHECK_THROWS_AS(sp::synthesizer(pyr, ex, {.mm_per_px = -1}), invalid_input);
    CHECK_THROWS_AS(sp::synthesizer(pyr, ex, {.jitter = 2}), invalid_input);
    CHECK_THROWS_AS(sp::synthesizer(pyr, ex, {.candidates = 0}), invalid_input);
    CHECK_THROWS_AS(sp::synthesizer(pyr, ex, {.up = vec3(std::numeric_limits<double>::infinity(), 0, 0)}), invalid_input);
    CHECK_THROWS_AS(sp::synthesizer(pyr, ex, {.allowed_labels = {0xffffffffu}}), invalid_input);
    const sp::synthesizer syn(pyr, ex, {});
    sp::synthesis_result r = syn.synthesize();
    std::vector<std::uint8_t> wrong(3, 0), ok(s.size(), 0);
    CHECK_THROWS_AS(syn.resynthesize(r, wrong, ok, 4.0), invalid_input);
    CHECK_THROWS_AS(syn.resynthesize(r, ok, ok, 0.0), invalid_input);
    CHECK_THROWS_AS(syn.resynthesize(r, ok, ok, 4.0, 0), invalid_input);
}

TEST_CASE("bunny at the paper's 256^3 and 8 levels: the shell's solid fraction is within 0.1 of the exemplar's", "[surface_pattern][synthesis][slow]") {
    const sp::surface_shell s = sp::make_shell(io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny.obj"), {.size_mm = 100, .resolution = 256});
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, sp::default_levels(256));
    REQUIRE(pyr.levels.size() == 8);
    for (const char* name : {"hooks", "zebra"}) {
        const sp::exemplar ex = load_exemplar(name, 6);
        const sp::synthesis_result r = sp::synthesizer(pyr, ex, {.up = vec3(0, 1, 0), .seed = 1}).synthesize();
        double solid = 0;
        for (auto v : r.solid) solid += v;
        solid /= static_cast<double>(r.solid.size());
        INFO(name << ": shell solid fraction " << solid << ", exemplar " << ex.solid_fraction());
        CHECK(std::abs(solid - ex.solid_fraction()) < 0.1);
    }
}
