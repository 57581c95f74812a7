// Structural optimizer and the loop of Algorithm 1 (structurally-sound-patterns.md §5, §3) on the
// bunny: connectivity of the result (checked with graph/ components and the mesher, not with the
// abstract graph the optimizer used), force-profile dependence, determinism, bad input.
#include <catch2/catch.hpp>

#include "support/test_util.hpp"

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/graph/components.hpp>
#include <fabsynth/graph/shortest_paths.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/surface_pattern.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

namespace {

/// The bunny (up = +y) at 64^3 on 50 mm with a synthesized pattern, specks removed.
struct bunny_case {
    sp::surface_shell shell;
    sp::shell_pyramid pyr;
    std::unique_ptr<sp::synthesizer> syn;
    sp::synthesis_result r;
    sp::surface_graph gs;
    double h = 0;

    bunny_case(const std::string& exemplar, double feature_px, std::uint64_t seed, int resolution = 64) {
        const triangle_mesh bunny = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj");
        shell = sp::make_shell(bunny, {.size_mm = 50, .resolution = resolution});
        pyr = sp::build_shell_pyramid(shell, sp::default_levels(resolution));
        const sp::exemplar ex =
            sp::make_exemplar(io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/" + exemplar), nullptr, {.feature_px = feature_px});
        syn = std::make_unique<sp::synthesizer>(pyr, ex, sp::synthesis_options{.mm_per_px = 0.25, .up = {0, 1, 0}, .seed = seed});
        r = syn->synthesize();
        const sp::shell_level& l0 = pyr.levels[0];
        h = l0.geometry.spacing.x;
        (void)sp::remove_specks(l0.geometry, l0.voxels, r.solid, 3 * h);
        gs = sp::build_surface_graph(l0);
    }
    [[nodiscard]] const sp::shell_level& l0() const { return pyr.levels[0]; }
    [[nodiscard]] sp::structure_options options(double r_pattern_px) const {
        sp::structure_options o;
        o.r_pattern_mm = r_pattern_px * 0.25;
        o.thickness_mm = 2.5 * h;
        o.target_samples = 300;
        o.gravity = {0, -1, 0};
        return o;
    }
    /// 26-connected components of the solid shell voxels (graph/ on G_surface).
    [[nodiscard]] std::size_t solid_pieces(const std::vector<std::uint8_t>& solid) const {
        return graph::connected_components(gs.graph(), solid).count;
    }
};

}  // namespace

TEST_CASE("structure loop: the pattern ends as one piece and prints as one watertight mesh", "[surface_pattern][structure]") {
    for (const char* name : {"hooks.png", "spots.png"}) {  // spots: separate dots, the paper's Fig. 18 case
        INFO(name);
        bunny_case b(name, 5, 3);
        REQUIRE(b.gs.components.count == 1);
        const std::size_t before = b.solid_pieces(b.r.solid);
        INFO("solid pieces before " << before);
        CHECK(before > 1);
        std::vector<std::uint8_t> forced;
        const sp::structure_report rep = sp::optimize_structure(*b.syn, b.r, b.gs, b.options(5), 30, &forced);
        INFO("iterations " << rep.iterations.size() << ", converged " << rep.converged);
        CHECK(rep.converged);
        CHECK(rep.iterations.front().components_before > 1);
        CHECK(rep.iterations.front().added_connect >= static_cast<std::size_t>(rep.iterations.front().components_before - 1));
        CHECK(rep.iterations.back().done());
        CHECK(rep.iterations.back().components_before == 1);
        // one piece, checked on the voxels with graph/ (not the abstract graph)
        CHECK(b.solid_pieces(b.r.solid) == 1);
        // every reinforcement voxel is solid, and there are some
        REQUIRE(forced.size() == b.r.solid.size());
        std::size_t nforced = 0;
        for (std::size_t v = 0; v < forced.size(); ++v) {
            nforced += forced[v];
            if (forced[v]) REQUIRE(b.r.solid[v] == 1);
        }
        CHECK(nforced == rep.forced_voxels);
        CHECK(nforced > 0);
        // the printed solid: thickened, joined at edge contacts, meshed
        const sp::shell_level& l0 = b.l0();
        sp::voxel_set thick = sp::thicken_inward(l0.geometry, l0.voxels, l0.normals, b.r.solid, 2.5 * b.h);
        if (sp::set_components(thick, sp::mesh_connectivity{}).count != sp::set_components(thick).count) (void)sp::join_diagonal_contacts(thick);
        CHECK(sp::set_components(thick, sp::mesh_connectivity{}).count == 1);
        const triangle_mesh m = sp::mesh_voxels(thick, 10);
        const mesh_topology_info topo = analyze_topology(m);
        CHECK(topo.is_watertight());
        // surface components: the outer surface plus the small enclosed voids of thin parts
        // (fabricate.hpp): every shell but one bounds a void (negative signed volume)
        std::size_t cavities = 0;
        CHECK(analyze_topology(without_cavities(m, &cavities)).components == 1);
        CHECK(topo.components == cavities + 1);
    }
}

TEST_CASE("structure step: bridges follow the force profile", "[surface_pattern][structure]") {
    bunny_case b("hooks.png", 5, 4);
    auto run = [&](vec3 g) {
        std::vector<std::uint8_t> solid = b.r.solid, reinforcement;
        sp::structure_options o = b.options(5);
        o.gravity = g;
        o.geodesic_factor = 0;  // the force profile alone
        const sp::structural_step_report rep = sp::structural_step(b.gs, b.l0(), solid, reinforcement, o);
        CHECK(rep.components_after == 1);
        CHECK(b.solid_pieces(solid) == 1);
        return std::make_pair(rep, reinforcement);
    };
    const auto [down, bridges_down] = run({0, -1, 0});
    const auto [side, bridges_side] = run({1, 0, 0});
    CHECK(down.samples == side.samples);  // same abstract graph: only the profile differs
    CHECK(down.solid_edges == side.solid_edges);
    std::size_t differ = 0, total = 0;
    for (std::size_t v = 0; v < bridges_down.size(); ++v) differ += bridges_down[v] != bridges_side[v], total += bridges_down[v] | bridges_side[v];
    INFO("bridge voxels differing " << differ << " of " << total);
    CHECK(differ > total / 10);
    std::vector<std::uint32_t> ed, es;
    for (const auto& [e, c] : down.inserted) ed.push_back(e);
    for (const auto& [e, c] : side.inserted) es.push_back(e);
    std::sort(ed.begin(), ed.end());
    std::sort(es.begin(), es.end());
    CHECK(ed != es);
}

TEST_CASE("structure step: the force phase runs until no solid edge is overloaded, and only as long as one is", "[surface_pattern][structure]") {
    bunny_case b("hooks.png", 5, 4);
    auto run = [&](double load_n) {
        std::vector<std::uint8_t> solid = b.r.solid, reinforcement;
        sp::structure_options o = b.options(5);
        o.geodesic_factor = 0;
        o.design_load_n = load_n;
        return sp::structural_step(b.gs, b.l0(), solid, reinforcement, o);
    };
    // a load under which the connected pattern is strong enough: connection only
    const sp::structural_step_report light = run(1e-3);
    INFO("light: max " << light.max_stress_after_mpa << " MPa");
    CHECK(light.added_force == 0);
    CHECK(light.max_stress_after_mpa < light.allowable_stress_mpa);
    // stresses are linear in the load: 1e4 times heavier overloads the same connected pattern
    const sp::structural_step_report heavy = run(10.0);
    INFO("heavy: " << heavy.added_force << " force bridges, max " << heavy.max_stress_after_mpa << " MPa");
    CHECK(heavy.load_n == 10.0);
    CHECK(heavy.added_connect == light.added_connect);
    CHECK(heavy.added_force > 0);
    CHECK((heavy.max_stress_after_mpa <= heavy.allowable_stress_mpa || heavy.force_bound_hit));
    // the default profile is the pattern's weight times load_factor (ABS, g = 9.81 m/s^2)
    std::vector<std::uint8_t> solid = b.r.solid, reinforcement;
    sp::structure_options o = b.options(5);
    o.geodesic_factor = 0;
    const sp::structural_step_report weight = sp::structural_step(b.gs, b.l0(), solid, reinforcement, o);
    const double n_solid = static_cast<double>(std::count(b.r.solid.begin(), b.r.solid.end(), std::uint8_t{1}));
    const double expected_n = o.load_factor * n_solid * b.h * b.h * o.thickness_mm * 1.04e-9 * 9810.0;  // ABS 1.04 g/cm^3
    CHECK(weight.load_n == Approx(expected_n).epsilon(0.02));
}

TEST_CASE("structure step: the geodesic criterion bridges edges whose ends are far apart in the pattern", "[surface_pattern][structure]") {
    bunny_case b("hooks.png", 5, 7);
    auto run = [&](double factor, std::vector<std::uint8_t>& solid) {
        std::vector<std::uint8_t> reinforcement;
        sp::structure_options o = b.options(5);
        o.force_criterion = false;  // connect, then the geodesic criterion alone (§5.2.2)
        o.geodesic_factor = factor;
        return sp::structural_step(b.gs, b.l0(), solid, reinforcement, o);
    };
    // a threshold no detour reaches: connection only, and the longest detour of the connected pattern
    std::vector<std::uint8_t> connected = b.r.solid;
    const sp::structural_step_report off = run(1e6, connected);
    CHECK(off.added_geodesic == 0);
    CHECK(off.components_after == 1);
    REQUIRE(std::isfinite(off.max_geodesic_mm));
    const double extent = off.geodesic_threshold_mm / 1e6;
    INFO("extent " << extent << " mm, longest detour " << off.max_geodesic_mm << " mm");
    REQUIRE(off.max_geodesic_mm > 0.2 * extent);
    // half that detour as the threshold: edges go in until no empty edge's ends are farther apart
    std::vector<std::uint8_t> solid = b.r.solid;
    const sp::structural_step_report on = run(0.5 * off.max_geodesic_mm / extent, solid);
    CHECK(on.added_geodesic > 0);
    CHECK(on.added_connect == off.added_connect);
    CHECK(on.max_geodesic_mm <= on.geodesic_threshold_mm);
    CHECK(on.components_after == 1);
    std::size_t geodesic_bridges = 0;
    for (const auto& [e, c] : on.inserted) geodesic_bridges += c == sp::bridge_criterion::geodesic;
    CHECK(geodesic_bridges == on.added_geodesic);
    // the bridges are solid voxels: the connected result is a subset of this one, and one piece
    for (std::size_t v = 0; v < solid.size(); ++v)
        if (connected[v]) REQUIRE(solid[v] == 1);
    CHECK(b.solid_pieces(solid) == 1);
}

TEST_CASE("structure step: bridges are the empty runs of the inserted paths dilated by the bridge radius", "[surface_pattern][structure]") {
    bunny_case b("hooks.png", 5, 4);
    const sp::shell_level& l0 = b.l0();
    auto run = [&](double radius_mm) {
        std::vector<std::uint8_t> solid = b.r.solid, reinforcement, added;
        sp::structure_options o = b.options(5);
        o.bridge_radius_mm = radius_mm;
        const sp::structural_step_report rep = sp::structural_step(b.gs, l0, solid, reinforcement, o, no_progress{}, &added);
        REQUIRE_FALSE(rep.inserted.empty());
        // the oracle: the same abstract graph, the empty voxels of the inserted paths, a fresh
        // multi-source Dijkstra in G_surface; solid now <=> solid before or within the radius
        const sp::abstract_graph ag = sp::build_abstract_graph(b.gs, l0, b.r.solid, {.target_samples = o.target_samples, .seed = o.seed});
        std::vector<graph::vertex_id> seeds;
        for (const auto& [e, c] : rep.inserted)
            for (const std::uint32_t v : ag.edges[e].path)
                if (!b.r.solid[v]) seeds.push_back(v);
        std::sort(seeds.begin(), seeds.end());
        seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
        const graph::shortest_path_forest near = graph::dijkstra_forest(b.gs.graph(), seeds);
        std::size_t n_added = 0;
        for (std::size_t v = 0; v < l0.size(); ++v) {
            const bool bridge = near.distance[v] <= o.bridge_radius();
            REQUIRE(solid[v] == (b.r.solid[v] || bridge ? 1 : 0));
            REQUIRE(added[v] == (bridge && !b.r.solid[v] ? 1 : 0));
            REQUIRE(reinforcement[v] == (bridge ? 1 : 0));
            n_added += added[v];
        }
        CHECK(n_added == rep.reinforced_voxels);
        CHECK(b.solid_pieces(solid) == 1);
        return rep.reinforced_voxels;
    };
    const std::size_t paper = run(0);  // r_pattern, 1.25 mm
    const std::size_t narrow = run(b.h);
    INFO("voxels laid: r_pattern " << paper << ", one voxel " << narrow);
    CHECK(narrow < paper);
    sp::structure_options bad = b.options(5);
    bad.bridge_radius_mm = -1;
    CHECK_THROWS_AS(bad.validate(), invalid_input);
}

TEST_CASE("structure step: user loads and supports (plane_support, area_load)", "[surface_pattern][structure][slow]") {
    bunny_case b("hooks.png", 5, 4);
    const sp::shell_level& l0 = b.l0();
    auto run = [&](const sp::structure_options& o) {
        std::vector<std::uint8_t> solid = b.r.solid, reinforcement;
        return std::make_pair(sp::structural_step(b.gs, l0, solid, reinforcement, o), solid);
    };
    sp::structure_options base = b.options(5);
    base.geodesic_factor = 0;
    // the oracle: one area load along gravity whose radius reaches every vertex is the design load,
    // spread equally over the abstract vertices
    sp::structure_options designed = base, area = base;
    designed.design_load_n = 10.0;
    area.loads = {{.at = {25, 25, 25}, .force_n = 10.0 * vec3(0, -1, 0), .radius_mm = 1e6}};
    const auto [rd, sd] = run(designed);
    const auto [ra, sa] = run(area);
    CHECK(ra.load_n == Approx(10.0));
    CHECK(ra.max_stress_mpa == Approx(rd.max_stress_mpa).epsilon(1e-9));
    CHECK(ra.inserted == rd.inserted);
    CHECK(sa == sd);
    // a point load (radius 0, the nearest vertex takes it): the total is reported, stresses are
    // linear in it
    sp::structure_options point = base, twice = base;
    point.loads = {{.at = {25, 40, 25}, .force_n = {0, -2, 0}, .radius_mm = 0}};
    twice.loads = {{.at = {25, 40, 25}, .force_n = {0, -4, 0}, .radius_mm = 0}};
    const sp::structural_step_report rp = run(point).first;
    CHECK(rp.load_n == Approx(2.0));
    CHECK(run(twice).first.max_stress_mpa == Approx(2 * rp.max_stress_mpa).epsilon(1e-6));
    // hung from a band at the top instead of standing on the lowest 10%: other bridges
    vec3 lo(1e9), hi(-1e9);
    for (std::size_t v = 0; v < l0.size(); ++v) lo = glm::min(lo, l0.center(v)), hi = glm::max(hi, l0.center(v));
    sp::structure_options hung = designed;
    hung.fixed = sp::plane_support(hi, {0, 1, 0}, 0.1 * (hi.y - lo.y));
    CHECK(hung.fixed(vec3(0, hi.y - 0.05 * (hi.y - lo.y), 0)));
    CHECK_FALSE(hung.fixed(vec3(0, lo.y, 0)));
    const auto [rh, sh] = run(hung);
    CHECK(rh.components_after == 1);
    CHECK(rh.inserted != rd.inserted);
    // refused: a plane no vertex lies on, bad planes and loads
    sp::structure_options nowhere = designed;
    nowhere.fixed = sp::plane_support(hi + vec3(0, 100, 0), {0, 1, 0}, 1.0);
    CHECK_THROWS_AS(run(nowhere), no_solution);
    CHECK_THROWS_AS(sp::plane_support({0, 0, 0}, {0, 0, 0}, 1), invalid_input);
    CHECK_THROWS_AS(sp::plane_support({0, 0, 0}, {0, 0, 1}, -1), invalid_input);
    sp::structure_options bad = area;
    bad.loads[0].radius_mm = -1;
    CHECK_THROWS_AS(bad.validate(), invalid_input);
    bad = area;
    bad.load = [](const vec3&) { return vec3(0, -1, 0); };
    CHECK_THROWS_AS(bad.validate(), invalid_input);
}

TEST_CASE("structure step: identical for any thread count", "[surface_pattern][structure]") {
    test::thread_count_guard guard;
    bunny_case b("giraffe.png", 5, 5);
    std::vector<std::uint8_t> s1 = b.r.solid, s2 = b.r.solid, f1, f2;
    set_num_threads(1);
    const sp::structural_step_report r1 = sp::structural_step(b.gs, b.l0(), s1, f1, b.options(5));
    set_num_threads(2);
    const sp::structural_step_report r2 = sp::structural_step(b.gs, b.l0(), s2, f2, b.options(5));
    CHECK(s1 == s2);
    CHECK(f1 == f2);
    CHECK(r1.inserted == r2.inserted);
    CHECK(r1.max_stress_mpa == r2.max_stress_mpa);
    CHECK(r1.max_stress_after_mpa == r2.max_stress_after_mpa);
}

TEST_CASE("structure: bad options and impossible profiles are refused", "[surface_pattern][structure]") {
    bunny_case b("hooks.png", 5, 6);
    std::vector<std::uint8_t> solid = b.r.solid, f;
    auto refuse = [&](auto change) {
        sp::structure_options o = b.options(5);
        change(o);
        std::vector<std::uint8_t> s = solid;
        CHECK_THROWS_AS(sp::structural_step(b.gs, b.l0(), s, f, o), invalid_input);
    };
    refuse([](sp::structure_options& o) { o.r_pattern_mm = 0; });
    refuse([](sp::structure_options& o) { o.thickness_mm = std::numeric_limits<double>::quiet_NaN(); });
    refuse([](sp::structure_options& o) { o.gravity = vec3(0.0); });
    refuse([](sp::structure_options& o) { o.safety_factor = -1; });
    refuse([](sp::structure_options& o) { o.edges_per_solve = 0; });
    refuse([](sp::structure_options& o) { o.support_fraction = 2; });
    std::vector<std::uint8_t> short_solid(3, 1);
    CHECK_THROWS_AS(sp::structural_step(b.gs, b.l0(), short_solid, f, b.options(5)), invalid_input);
    CHECK_THROWS_AS(sp::optimize_structure(*b.syn, b.r, b.gs, b.options(5), 0), invalid_input);
    CHECK_THROWS_AS(sp::print_material::named("wood"), invalid_input);
    // a force profile that fixes nothing cannot carry its loads
    sp::structure_options o = b.options(5);
    o.fixed = [](const vec3&) { return false; };
    CHECK_THROWS_AS(sp::structural_step(b.gs, b.l0(), solid, f, o), no_solution);
    // a user profile: held at the top instead of the bottom (hanging), still one piece
    o.fixed = [&](const vec3& p) { return p.y > b.l0().geometry.origin.y + 0.85 * b.l0().geometry.spacing.y * b.l0().geometry.dims.y; };
    o.load = [](const vec3&) { return vec3(0, -0.05, 0); };
    std::vector<std::uint8_t> s = b.r.solid;
    const sp::structural_step_report rep = sp::structural_step(b.gs, b.l0(), s, f, o);
    CHECK(rep.components_after == 1);
}
