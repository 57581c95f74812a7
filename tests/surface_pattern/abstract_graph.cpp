#include <catch2/catch.hpp>

#include "support/test_util.hpp"

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/core/rng.hpp>
#include <fabsynth/graph/components.hpp>
#include <fabsynth/graph/from_voxels.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/surface_pattern/abstract_graph.hpp>
#include <fabsynth/surface_pattern/synthesis.hpp>

#include "support/sphere_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

namespace {

sp::shell_pyramid bunny_pyramid() {
    const sp::surface_shell s =
        sp::make_shell(io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj"), {.size_mm = 60, .resolution = 64});
    return sp::build_shell_pyramid(s, sp::default_levels(64));
}

/// Blobs: voxels within `radius` mm of a centre; centres are the voxels with hash64(seed, v) % every == 0.
std::vector<std::uint8_t> blobs(const sp::shell_level& l0, std::uint64_t seed, std::uint64_t every, double radius) {
    std::vector<vec3> centres;
    for (std::size_t v = 0; v < l0.size(); ++v)
        if (hash64(seed, v) % every == 0) centres.push_back(l0.center(v));
    std::vector<std::uint8_t> solid(l0.size(), 0);
    for (std::size_t v = 0; v < l0.size(); ++v)
        for (const vec3& c : centres)
            if (glm::distance(l0.center(v), c) < radius) {
                solid[v] = 1;
                break;
            }
    return solid;
}

/// Number of 26-connected components of the solid voxels, from a graph of the solid voxels alone.
std::size_t solid_voxel_components(const sp::shell_level& l0, const std::vector<std::uint8_t>& solid) {
    std::vector<ivec3> vox;
    for (std::size_t v = 0; v < l0.size(); ++v)
        if (solid[v]) vox.push_back(l0.voxels[v]);
    if (vox.empty()) return 0;
    return graph::connected_components(graph::from_voxels(l0.geometry, vox).graph).count;
}

bool neighbours26(const ivec3& p, const ivec3& q) {
    const ivec3 d = glm::abs(p - q);
    return p != q && d.x <= 1 && d.y <= 1 && d.z <= 1;
}

/// Structural checks of an abstract graph against its inputs.
void check_abstract(const sp::surface_graph& g, const sp::shell_level& l0, const std::vector<std::uint8_t>& solid, const sp::abstract_graph& ag) {
    REQUIRE(ag.surface_component.size() == ag.samples.size());
    for (std::size_t k = 0; k < ag.samples.size(); ++k) {
        CHECK(solid[ag.samples[k]] == 1);
        if (k) CHECK(ag.samples[k - 1] < ag.samples[k]);
        CHECK(ag.surface_component[k] == static_cast<int>(g.components.label[ag.samples[k]]));
    }
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
    bool seen_empty = false;
    std::size_t bad_walk = 0, bad_solid = 0, bad_length = 0, bad_ends = 0, no_empty_voxel = 0;
    for (const sp::abstract_edge& e : ag.edges) {
        REQUIRE(e.a < e.b);
        REQUIRE(e.b < ag.samples.size());
        CHECK(pairs.insert({e.a, e.b}).second);  // one edge per sample pair
        if (e.solid) CHECK(!seen_empty);         // solid edges first
        else seen_empty = true;
        CHECK(ag.surface_component[e.a] == ag.surface_component[e.b]);  // never across pieces of the mesh
        REQUIRE(e.path.size() >= 2);
        if (e.path.front() != ag.samples[e.a] || e.path.back() != ag.samples[e.b]) ++bad_ends;
        double len = 0;
        bool any_empty = false;
        for (std::size_t i = 0; i < e.path.size(); ++i) {
            any_empty |= solid[e.path[i]] == 0;
            if (e.solid && !solid[e.path[i]]) ++bad_solid;
            if (i == 0) continue;
            if (!neighbours26(l0.voxels[e.path[i - 1]], l0.voxels[e.path[i]])) ++bad_walk;
            len += glm::distance(l0.center(e.path[i - 1]), l0.center(e.path[i]));
        }
        if (std::abs(len - e.length_mm) > 1e-9 * len) ++bad_length;
        if (!e.solid && !any_empty) ++no_empty_voxel;
    }
    CHECK(bad_ends == 0);
    CHECK(bad_walk == 0);
    CHECK(bad_solid == 0);
    CHECK(bad_length == 0);
    CHECK(no_empty_voxel == 0);
    // order within each state: increasing (a, b)
    for (std::size_t i = 1; i < ag.edges.size(); ++i)
        if (ag.edges[i].solid == ag.edges[i - 1].solid)
            CHECK(std::make_pair(ag.edges[i - 1].a, ag.edges[i - 1].b) < std::make_pair(ag.edges[i].a, ag.edges[i].b));
    // the key property: the abstract graph has the pattern's connectivity
    CHECK(sp::solid_components(ag).count == solid_voxel_components(l0, solid));
}

/// Shortest solid-edge distances from sample s by Bellman-Ford over the edge list (independent of graph/).
std::vector<double> bellman_ford(const sp::abstract_graph& ag, std::uint32_t s) {
    std::vector<double> d(ag.samples.size(), std::numeric_limits<double>::infinity());
    d[s] = 0;
    for (bool changed = true; changed;) {
        changed = false;
        for (const sp::abstract_edge& e : ag.edges) {
            if (!e.solid) continue;
            if (d[e.a] + e.length_mm < d[e.b]) d[e.b] = d[e.a] + e.length_mm, changed = true;
            if (d[e.b] + e.length_mm < d[e.a]) d[e.a] = d[e.b] + e.length_mm, changed = true;
        }
    }
    return d;
}

}  // namespace

TEST_CASE("abstract graph on the bunny: random blob and noise patterns keep their connectivity, paths are walks of the right length",
          "[surface_pattern][abstract_graph]") {
    const sp::shell_pyramid pyr = bunny_pyramid();
    const sp::shell_level& l0 = pyr.levels[0];
    const sp::surface_graph g = sp::build_surface_graph(l0);
    REQUIRE(g.size() == l0.size());
    CHECK(g.components.count == 1);
    struct pattern {
        std::uint64_t seed, every;
        double radius;
    };
    for (const pattern p : {pattern{1, 60, 2.0}, pattern{2, 120, 2.5}, pattern{3, 30, 1.2}, pattern{4, 400, 4.0}}) {
        const std::vector<std::uint8_t> solid = blobs(l0, p.seed, p.every, p.radius);
        const std::size_t nsolid = static_cast<std::size_t>(std::count(solid.begin(), solid.end(), std::uint8_t{1}));
        INFO("pattern seed " << p.seed << ": " << nsolid << " solid of " << l0.size() << ", " << solid_voxel_components(l0, solid) << " components");
        const sp::abstract_graph ag = sp::build_abstract_graph(g, l0, solid, {.target_samples = 150, .seed = p.seed});
        INFO(ag.samples.size() << " samples (" << ag.extra_samples << " extra), " << ag.edges.size() << " edges, " << ag.num_solid_edges()
                               << " solid, radius " << ag.sample_radius_mm);
        check_abstract(g, l0, solid, ag);
        CHECK(ag.num_solid_edges() > 0);
        CHECK(ag.num_solid_edges() < ag.edges.size());
        const double poisson = static_cast<double>(ag.samples.size() - ag.extra_samples);
        CHECK(std::abs(poisson - 150.0) <= 0.15 * 150.0);  // radius ~ 4 voxels: the count moves in steps (lattice distances)
    }
    // salt noise: hundreds of tiny components, each must keep a sample
    std::vector<std::uint8_t> salt(l0.size(), 0);
    for (std::size_t v = 0; v < l0.size(); ++v) salt[v] = hash64(77, v) % 6 == 0 ? 1 : 0;
    const sp::abstract_graph ag = sp::build_abstract_graph(g, l0, salt, {.target_samples = 200});
    INFO("salt: " << solid_voxel_components(l0, salt) << " components, " << ag.samples.size() << " samples, " << ag.extra_samples << " extra");
    CHECK(ag.extra_samples > 0);
    check_abstract(g, l0, salt, ag);
}

TEST_CASE("abstract graph of synthesized patterns (spots, hooks): connectivity reproduced",
          "[surface_pattern][abstract_graph][slow]") {
    const sp::shell_pyramid pyr = bunny_pyramid();
    const sp::shell_level& l0 = pyr.levels[0];
    const sp::surface_graph g = sp::build_surface_graph(l0);
    for (const char* name : {"spots", "hooks"}) {
        const sp::exemplar ex =
            sp::make_exemplar(io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/" + name + ".png"), nullptr, {.feature_px = 4});
        const std::vector<std::uint8_t> solid = sp::synthesizer(pyr, ex, {.up = vec3(0, 1, 0), .seed = 2}).synthesize().solid;
        const sp::abstract_graph ag = sp::build_abstract_graph(g, l0, solid, {.target_samples = 200});
        INFO(name << ": " << solid_voxel_components(l0, solid) << " solid components, " << ag.samples.size() << " samples (" << ag.extra_samples
                  << " extra), " << ag.edges.size() << " edges, " << ag.num_solid_edges() << " solid");
        check_abstract(g, l0, solid, ag);
        CHECK(ag.num_solid_edges() < ag.edges.size());
    }
}

TEST_CASE("abstract graph at the paper's scale (256^3, 1000 samples): count within 10% of the target, connectivity reproduced",
          "[surface_pattern][abstract_graph][slow]") {
    const sp::surface_shell s =
        sp::make_shell(io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj"), {.size_mm = 100, .resolution = 256});
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, 2);
    const sp::shell_level& l0 = pyr.levels[0];
    const sp::surface_graph g = sp::build_surface_graph(l0);
    const std::vector<std::uint8_t> solid = blobs(l0, 21, 1500, 3.0);
    const sp::abstract_graph ag = sp::build_abstract_graph(g, l0, solid, {.target_samples = 1000});
    INFO(l0.size() << " voxels, " << solid_voxel_components(l0, solid) << " solid components, " << ag.samples.size() << " samples ("
                   << ag.extra_samples << " extra), radius " << ag.sample_radius_mm << " mm, " << ag.edges.size() << " edges");
    CHECK(std::abs(static_cast<double>(ag.samples.size()) - 1000.0) <= 0.1 * 1000.0);
    check_abstract(g, l0, solid, ag);
}

TEST_CASE("abstract graph: everything solid gives no empty edge and one piece; geodesics through solid edges",
          "[surface_pattern][abstract_graph]") {
    const sp::shell_pyramid pyr = bunny_pyramid();
    const sp::shell_level& l0 = pyr.levels[0];
    const sp::surface_graph g = sp::build_surface_graph(l0);
    const std::vector<std::uint8_t> all(l0.size(), 1);
    const sp::abstract_graph full = sp::build_abstract_graph(g, l0, all, {.target_samples = 500});
    check_abstract(g, l0, all, full);
    CHECK(full.num_solid_edges() == full.edges.size());
    CHECK(full.extra_samples == 0);
    CHECK(std::abs(static_cast<double>(full.samples.size()) - 500.0) <= 0.05 * 500.0);
    CHECK(sp::solid_components(full).count == 1);

    // geodesic_in_solid against Bellman-Ford on a blob pattern with several pieces
    const std::vector<std::uint8_t> solid = blobs(l0, 5, 50, 2.2);
    const sp::abstract_graph ag = sp::build_abstract_graph(g, l0, solid, {.target_samples = 250});
    const graph::graph_components cc = sp::solid_components(ag);
    REQUIRE(cc.count > 1);
    const auto sg = sp::solid_edge_graph(ag);
    CHECK(sg.num_edges() == ag.num_solid_edges());
    for (std::uint32_t s : {0u, 7u, static_cast<std::uint32_t>(ag.samples.size() - 1)}) {
        const std::vector<double> ref = bellman_ford(ag, s);
        for (std::uint32_t t = 0; t < ag.samples.size(); t += 3) {
            const graph::geodesic_path p = graph::geodesic(sg, s, t);
            if (std::isinf(ref[t])) {
                CHECK(!p.connected());
                CHECK(std::isinf(p.length));
                CHECK(cc.label[s] != cc.label[t]);
            } else {
                CHECK(p.length == Approx(ref[t]).epsilon(1e-12));
                CHECK(cc.label[s] == cc.label[t]);
            }
        }
    }
    std::size_t checked = 0;
    for (const sp::abstract_edge& e : ag.edges) {
        if (e.solid) continue;
        const graph::geodesic_path p = sp::geodesic_in_solid(ag, e.a, e.b);
        CHECK(p.connected() == (cc.label[e.a] == cc.label[e.b]));
        if (p.connected()) {
            CHECK(p.vertices.front() == e.a);
            CHECK(p.vertices.back() == e.b);
        }
        if (++checked == 20) break;
    }
    // overriding the edge states: all edges solid joins every sample of the (single) surface piece
    const std::vector<std::uint8_t> every(ag.edges.size(), 1);
    CHECK(sp::solid_components(ag, every).count == 1);
    CHECK(sp::geodesic_in_solid(ag, 0, static_cast<std::uint32_t>(ag.samples.size() - 1), every).connected());
}

TEST_CASE("abstract graph on two disjoint spheres: no edge crosses, an all-empty piece gets no sample", "[surface_pattern][abstract_graph]") {
    triangle_mesh m = test::sphere_mesh(10, 3);
    const triangle_mesh other = test::sphere_mesh(8, 3);
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    for (const vec3& v : other.vertices) m.vertices.push_back(v + vec3(40, 0, 0));
    for (const auto& f : other.faces) m.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
    const sp::surface_shell s = sp::make_shell(m, {.size_mm = 60, .resolution = 64});
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, 3);
    const sp::shell_level& l0 = pyr.levels[0];
    const sp::surface_graph g = sp::build_surface_graph(l0);
    REQUIRE(g.components.count == 2);
    std::vector<std::uint8_t> solid = blobs(l0, 9, 40, 2.5);
    const sp::abstract_graph ag = sp::build_abstract_graph(g, l0, solid, {.target_samples = 300});
    check_abstract(g, l0, solid, ag);
    std::set<int> pieces(ag.surface_component.begin(), ag.surface_component.end());
    CHECK(pieces.size() == 2);
    std::size_t empty_edges = 0;
    for (const sp::abstract_edge& e : ag.edges) {
        empty_edges += e.solid ? 0 : 1;
        for (std::uint32_t v : e.path) CHECK(static_cast<int>(g.components.label[v]) == ag.surface_component[e.a]);
    }
    CHECK(empty_edges > 0);
    // every voxel of piece 1 empty: no sample there, piece 0 unchanged in structure
    for (std::size_t v = 0; v < l0.size(); ++v)
        if (g.components.label[v] == 1) solid[v] = 0;
    const sp::abstract_graph one = sp::build_abstract_graph(g, l0, solid, {.target_samples = 300});
    check_abstract(g, l0, solid, one);
    for (int c : one.surface_component) CHECK(c == 0);
    // all solid: one solid component per sphere, no empty edge
    const std::vector<std::uint8_t> all(l0.size(), 1);
    const sp::abstract_graph full = sp::build_abstract_graph(g, l0, all, {.target_samples = 200});
    check_abstract(g, l0, all, full);
    CHECK(sp::solid_components(full).count == 2);
    CHECK(full.num_solid_edges() == full.edges.size());
    const auto other_piece = static_cast<std::uint32_t>(
        std::find(full.surface_component.begin(), full.surface_component.end(), 1 - full.surface_component[0]) - full.surface_component.begin());
    REQUIRE(other_piece < full.samples.size());
    CHECK(!sp::geodesic_in_solid(full, 0, other_piece).connected());
    // nothing solid: an empty graph
    const sp::abstract_graph none = sp::build_abstract_graph(g, l0, std::vector<std::uint8_t>(l0.size(), 0), {});
    CHECK(none.samples.empty());
    CHECK(none.edges.empty());
    CHECK(sp::solid_components(none).count == 0);
}

TEST_CASE("abstract graph is identical for 1 and 2 threads", "[surface_pattern][abstract_graph]") {
    test::thread_count_guard guard;
    const sp::shell_pyramid pyr = bunny_pyramid();
    const sp::shell_level& l0 = pyr.levels[0];
    const std::vector<std::uint8_t> solid = blobs(l0, 11, 60, 2.0);
    set_num_threads(1);
    const sp::surface_graph g1 = sp::build_surface_graph(l0);
    const sp::abstract_graph a = sp::build_abstract_graph(g1, l0, solid, {.target_samples = 400, .seed = 3});
    set_num_threads(2);
    const sp::surface_graph g2 = sp::build_surface_graph(l0);
    const sp::abstract_graph b = sp::build_abstract_graph(g2, l0, solid, {.target_samples = 400, .seed = 3});
    CHECK(g1.components.label == g2.components.label);
    CHECK(a.samples == b.samples);
    CHECK(a.sample_radius_mm == b.sample_radius_mm);
    CHECK(a.surface_component == b.surface_component);
    REQUIRE(a.edges.size() == b.edges.size());
    for (std::size_t i = 0; i < a.edges.size(); ++i) {
        CHECK(a.edges[i].a == b.edges[i].a);
        CHECK(a.edges[i].b == b.edges[i].b);
        CHECK(a.edges[i].solid == b.edges[i].solid);
        CHECK(a.edges[i].path == b.edges[i].path);
        CHECK(a.edges[i].length_mm == b.edges[i].length_mm);
    }
    const sp::abstract_graph c = sp::build_abstract_graph(g2, l0, solid, {.target_samples = 400, .seed = 4});
    CHECK(c.samples != a.samples);  // the seed matters
}

TEST_CASE("abstract graph refuses bad input with invalid_input", "[surface_pattern][abstract_graph]") {
    const sp::shell_pyramid pyr = bunny_pyramid();
    const sp::shell_level& l0 = pyr.levels[0];
    const sp::surface_graph g = sp::build_surface_graph(l0);
    std::vector<std::uint8_t> solid(l0.size(), 1);
    CHECK_NOTHROW(sp::build_abstract_graph(g, l0, solid, {.target_samples = 50}));
    CHECK_THROWS_AS(sp::build_abstract_graph(g, l0, std::vector<std::uint8_t>(l0.size() - 1, 1), {}), invalid_input);
    CHECK_THROWS_AS(sp::build_abstract_graph(g, l0, std::vector<std::uint8_t>(l0.size() + 1, 1), {}), invalid_input);
    solid[17] = 2;
    CHECK_THROWS_AS(sp::build_abstract_graph(g, l0, solid, {}), invalid_input);
    solid[17] = 1;
    CHECK_THROWS_AS(sp::build_abstract_graph(g, l0, solid, {.target_samples = 0}), invalid_input);
    CHECK_THROWS_AS(sp::build_abstract_graph(g, l0, solid, {.relative_tolerance = -1}), invalid_input);
    CHECK_THROWS_AS(sp::build_abstract_graph(g, l0, solid, {.max_evaluations = 0}), invalid_input);
    // a surface graph of another level
    const sp::surface_graph g1 = sp::build_surface_graph(pyr.levels[1]);
    CHECK_THROWS_AS(sp::build_abstract_graph(g1, l0, solid, {}), invalid_input);
    // a target above the number of solid voxels is clamped: every solid voxel becomes a sample
    std::vector<std::uint8_t> few(l0.size(), 0);
    few[3] = few[500] = few[1000] = 1;
    const sp::abstract_graph ag = sp::build_abstract_graph(g, l0, few, {.target_samples = 1000});
    CHECK(ag.samples == std::vector<std::uint32_t>{3, 500, 1000});
    const sp::abstract_graph full = sp::build_abstract_graph(g, l0, solid, {.target_samples = 50});
    CHECK_THROWS_AS(sp::solid_components(full, std::vector<std::uint8_t>(full.edges.size() + 1, 1)), invalid_input);
    CHECK_THROWS_AS(sp::geodesic_in_solid(full, 0, static_cast<std::uint32_t>(full.samples.size())), invalid_input);
}
