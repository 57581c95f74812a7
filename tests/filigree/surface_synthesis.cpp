// Filigree synthesis on surfaces (filigree-synthesis.md §8.1): on a flat mesh the surface path
// (exponential-map pictures) reproduces the 2D path of part 1 with the same seed, the topology cut
// included; on curved meshes every instance stays in the region, its skeleton lies on the surface,
// the PME drops by 10% or more and the result (the cut skeletons too) is the same for 1 and 2 threads.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/filigree/domain.hpp"
#include "fabsynth/filigree/element.hpp"
#include "fabsynth/filigree/initialization.hpp"
#include "fabsynth/filigree/surface/synthesis.hpp"
#include "fabsynth/filigree/surface/topology_cut.hpp"
#include "support/filigree_elements.hpp"
#include "fabsynth/filigree/synthesis.hpp"
#include "fabsynth/filigree/topology_cut.hpp"
#include "fabsynth/io/svg.hpp"
#include "support/sphere_mesh.hpp"
#include "support/surface_setup.hpp"

namespace surface_synth_test {

using namespace fabsynth;
using namespace fabsynth::filigree;
namespace fs = std::filesystem;

inline element load_element(const std::string& name, double size) { return fabsynth::test::filigree_element(name, size); }



TEST_CASE("surface initialization on a flat square reproduces the planar initialization", "[filigree][surface]") {
    const std::vector<element> cls{load_element("spiral", 16)};
    const std::vector<double> w{1.0};
    const fabsynth::test::surface_setup flat(fabsynth::test::plane_grid(30, 2.0, 1, 0.0), {0, 1, 0});  // up = +y: the planar rotation 0
    for (const std::uint64_t seed : {3u, 11u}) {
        INFO("seed " << seed);
        initialization_options io;
        io.seed = seed;
        const auto planar = initialize(std::span<const element>(cls), w, planar_domain::rectangle(60, 60), constant_field{}, io);
        const auto surf = initialize_on_surface(cls, w, flat.region, flat.field(), io);
        // The same candidates in the same order: equal until a decision on the edge of a rule
        // (an area ratio at its limit, computed by Clipper in differently placed frames) flips.
        std::size_t same = 0;
        while (same < std::min(surf.instances.size(), planar.instances.size())) {
            const vec3 p = flat.patcher.position(surf.instances[same].anchor);
            if (std::abs(p.x - planar.instances[same].position.x) > 1e-6 || std::abs(p.y - planar.instances[same].position.y) > 1e-6) break;
            ++same;
        }
        CHECK(same >= planar.instances.size() * 9 / 10);
        CHECK(std::abs(static_cast<double>(surf.instances.size()) - static_cast<double>(planar.instances.size())) <= 0.1 * planar.instances.size());
    }
}

// The face of the flat square mesh containing (x, y), with barycentric coordinates (brute force).
inline surface_point on_flat(const triangle_mesh& m, vec2 q) {
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
        const vec3 a = m.vertices[m.faces[f][0]], b = m.vertices[m.faces[f][1]], c = m.vertices[m.faces[f][2]];
        const double d = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        const double l1 = ((q.x - a.x) * (c.y - a.y) - (c.x - a.x) * (q.y - a.y)) / d;
        const double l2 = ((b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y)) / d;
        if (l1 >= 0 && l2 >= 0 && l1 + l2 <= 1) return {f, {1 - l1 - l2, l1, l2}};
    }
    FAIL("point off the square");
    return {};
}

TEST_CASE("surface layout optimization and topology cut on a flat square follow the 2D path (same start, same seed)", "[filigree][surface]") {
    const std::vector<element> cls{load_element("c_scroll", 16)};
    const std::vector<double> w{1.0};
    const fabsynth::test::surface_setup flat(fabsynth::test::plane_grid(30, 2.0, 1, 0.0), {0, 1, 0});
    const planar_domain dom = planar_domain::rectangle(60, 60);
    synthesis_options so;
    so.seed = 5;
    // Without the boundary term: its samples lie along the mesh's border edges in a picture and
    // along the domain's rings in the plane, so Theta differs by the sampling (up to a spacing).
    so.gamma_boundary = 0;
    so.smooth_connection = false;
    // Without the crossing term: a crossing count is discontinuous, so the last-bit differences
    // between a picture and the plane can flip a decision and the two paths part (its value on
    // the same layout is compared below).
    so.crossing_penalty = 0;
    // With the 30% move limit: instances stacked completely score ties (eq. 2 is 0 for copies)
    // that the last bits decide differently in a picture and in the plane.
    so.move_overlap_limit = 0.3;
    initialization_options io;
    io.seed = 5;
    const auto init = initialize(std::span<const element>(cls), w, dom, constant_field{}, io);
    pattern_state planar(cls, init.instances, constant_field{}, dom, 0.0);
    std::vector<surface_instance> start;
    for (const instance& in : init.instances) start.push_back({instance{in.cls, {0, 0}, 0, 1, in.shape}, on_flat(flat.mesh, in.position)});
    surface_space surf(cls, start, flat.field(), flat.region, 0.0);
    CHECK(surf.pattern_energy() == Approx(planar.pattern_energy()).epsilon(1e-9));
    CHECK(surf.connectivity() == planar.connectivity());
    const double plain = planar.pattern_energy();
    surf.set_crossing_penalty(5.0), planar.set_crossing_penalty(5.0);
    CHECK(planar.pattern_energy() > plain);  // the start has crossings
    CHECK(surf.pattern_energy() == Approx(planar.pattern_energy()).epsilon(1e-9));
    synthesis_result rp;
    surface_synthesis_result rs;
    optimize_layout(planar, so, rp);
    optimize_layout(surf, so, rs);
    REQUIRE(surf.size() == planar.size());
    CHECK(rs.rounds == rp.rounds);
    CHECK(rs.boosted == rp.boosted);
    CHECK(rs.energy_final == Approx(rp.energy_final).epsilon(1e-6));
    for (std::size_t i = 0; i < surf.size(); ++i) {
        const vec3 p = surf.anchor_position(i);
        CHECK(std::abs(p.x - planar.instances()[i].position.x) < 1e-6);
        CHECK(std::abs(p.y - planar.instances()[i].position.y) < 1e-6);
        // the skeleton on the surface is the planar skeleton
        const surface_skeleton sk = skeleton_on_surface(surf, i);
        const auto& pv = planar.geometry()[i].vertices;
        REQUIRE(sk.vertices.size() == pv.size());
        for (std::size_t v = 0; v < pv.size(); ++v) {
            if (sk.vertices[v].face == UINT32_MAX) continue;  // off the square
            const vec3 q = flat.patcher.position(sk.vertices[v]);
            CHECK(std::abs(q.x - pv[v].x) < 1e-6);
            CHECK(std::abs(q.y - pv[v].y) < 1e-6);
        }
    }

    // The topology cut with every skeleton in its own map makes the planar cut's decisions: the
    // planar skeletons, clipped to the square as the surface's are, cut in the plane.
    std::vector<graph::skeleton_graph<vec2>> planar_skeletons = world_skeletons(planar);
    for (auto& g : planar_skeletons)
        for (graph::edge_id e = 0; e < g.edge_slots(); ++e) {
            const auto [a, b] = g.endpoints(e);
            auto inside = [&](vec2 q) { return q.x >= 0 && q.x <= 60 && q.y >= 0 && q.y <= 60; };
            if (g.edge_alive(e) && !(inside(g.position(a)) && inside(g.position(b)))) g.remove_edge(e);
        }
    const auto pairs = connected_pairs(planar);
    const topology_cut_report planar_cut = topology_cut(planar_skeletons, pairs, {});
    std::vector<surface_skeleton> on_surface = surface_skeletons(surf, nullptr);
    const surface_cut_report surface_cut = topology_cut_on_surface(surf, on_surface, {});
    CHECK(planar_cut.branches_cut + planar_cut.protrusions_trimmed > 0);  // the comparison has cuts to compare
    CHECK(surface_cut.cut.branches_cut == planar_cut.branches_cut);
    CHECK(surface_cut.cut.protrusions_trimmed == planar_cut.protrusions_trimmed);
    CHECK(surface_cut.cut.cuts_refused_for_connectivity == planar_cut.cuts_refused_for_connectivity);
    CHECK(surface_cut.vertices_off_surface == 0);
    for (std::size_t i = 0; i < surf.size(); ++i) {
        INFO("instance " << i);
        const auto& g = planar_skeletons[i];
        const surface_skeleton& sk = on_surface[i];
        REQUIRE(sk.vertices.size() == g.num_vertices());  // the same split vertices, in the same order
        CHECK(sk.edges.size() == g.num_edges());
        double length = 0;
        for (const skeleton_edge& e : sk.edges) length += glm::distance(sk.picture[e[0]], sk.picture[e[1]]);
        CHECK(length == Approx(g.total_length()).margin(1e-6));
        for (std::size_t v = 0; v < g.num_vertices(); ++v) {
            if (sk.vertices[v].face == UINT32_MAX) continue;
            const vec3 q = flat.patcher.position(sk.vertices[v]);
            CHECK(std::abs(q.x - g.position(static_cast<graph::vertex_id>(v)).x) < 1e-6);
            CHECK(std::abs(q.y - g.position(static_cast<graph::vertex_id>(v)).y) < 1e-6);
        }
    }
}

TEST_CASE("surface synthesis on a cylinder band: in the region, on the surface, PME 10% below its start, same for 1 and 2 threads",
          "[filigree][surface][slow]") {
    const std::vector<element> cls{load_element("s_curl", 14)};
    const std::vector<double> w{1.0};
    const fabsynth::test::surface_setup band(fabsynth::test::cylinder(25, 50, 64, 2.5), {0, 0, 1});
    synthesis_options so;
    so.seed = 2;
    so.max_rounds = 2;
    std::vector<std::vector<surface_instance>> runs;
    std::vector<std::vector<std::vector<skeleton_edge>>> edges;  // per run, per instance
    for (const unsigned threads : {1u, 2u}) {
        set_num_threads(threads);
        const auto r = synthesize_on_surface(cls, w, band.region, band.field(), so);
        set_num_threads(0);
        REQUIRE(r.instances.size() >= 10);
        CHECK(r.energy_final < 0.9 * r.energy_initial);  // placement works (a rise is undone by construction)
        CHECK(r.maps_built > 0);
        for (std::size_t i = 0; i < r.instances.size(); ++i) {
            CHECK(band.region.contains(r.instances[i].anchor.face));
            const vec3 p = band.patcher.position(r.instances[i].anchor);
            CHECK(std::abs(std::hypot(p.x, p.y) - 25) < 0.1);  // on the cylinder (chords of the 64-gon: within 0.076 mm)
            for (const surface_point& q : r.skeletons[i].vertices)
                if (q.face != UINT32_MAX) CHECK(std::abs(std::hypot(band.patcher.position(q).x, band.patcher.position(q).y) - 25) < 0.1);
        }
        CHECK(r.cut.cut.branches_cut + r.cut.cut.protrusions_trimmed > 0);  // the cut ran on the surface
        runs.push_back(r.instances);
        edges.push_back({});
        for (const surface_skeleton& sk : r.skeletons) edges.back().push_back(sk.edges);
    }
    CHECK(edges[0] == edges[1]);
    REQUIRE(runs[0].size() == runs[1].size());
    for (std::size_t i = 0; i < runs[0].size(); ++i) {
        CHECK(runs[0][i].anchor.face == runs[1][i].anchor.face);
        CHECK(runs[0][i].anchor.bary == runs[1][i].anchor.bary);
        CHECK(runs[0][i].shape.shape == runs[1][i].shape.shape);
    }
}

TEST_CASE("surface element sets per region (Fig. 1c): each class only on the faces its labels name, both halves filled",
          "[filigree][surface][slow]") {
    // A cylinder band labelled 0 below z = 25 and 1 above; S-scrolls may lie on 0, C-scrolls on 1.
    const std::vector<element> cls{load_element("s_curl", 12), load_element("c_scroll", 12)};
    const std::vector<double> w{1.0, 1.0};
    fabsynth::test::surface_setup band(fabsynth::test::cylinder(25, 50, 64, 2.5), {0, 0, 1});
    std::vector<int> labels;
    for (const auto& f : band.mesh.faces)
        labels.push_back((band.mesh.vertices[f[0]].z + band.mesh.vertices[f[1]].z + band.mesh.vertices[f[2]].z) / 3 < 25 ? 0 : 1);
    synthesis_options so;
    so.seed = 3;
    so.max_rounds = 1;
    auto on_wrong_half = [&](const std::vector<surface_instance>& in) {
        std::size_t n = 0;
        for (const surface_instance& s : in) n += labels[s.anchor.face] != static_cast<int>(s.shape.cls);
        return n;
    };
    const auto free = synthesize_on_surface(cls, w, band.region, band.field(), so);
    REQUIRE(on_wrong_half(free.instances) > 3);  // without the sets both classes spread over both halves
    band.region.class_allowed = face_label_regions(labels, band.mesh.faces.size(), {{0}, {1}});
    const auto sets = synthesize_on_surface(cls, w, band.region, band.field(), so);
    CHECK(on_wrong_half(sets.initial) == 0);
    CHECK(on_wrong_half(sets.instances) == 0);  // placement, boosting and the merges keep to it
    std::size_t per_class[2] = {0, 0};
    for (const surface_instance& s : sets.instances) ++per_class[s.shape.cls];
    CHECK(per_class[0] >= 5);
    CHECK(per_class[1] >= 5);
    CHECK(sets.energy_final < sets.energy_initial);
}

TEST_CASE("face_label_regions: the count, the range and the classes' labels are checked by name", "[filigree][surface]") {
    const std::vector<int> labels{0, 0, 7, 7};
    const auto allowed = face_label_regions(labels, 4, {{}, {7}});
    CHECK(allowed(0, 0));
    CHECK(allowed(0, 2));
    CHECK_FALSE(allowed(1, 1));
    CHECK(allowed(1, 3));
    CHECK_FALSE(allowed(2, 3));  // no such class
    CHECK_FALSE(allowed(1, 9));  // no such face
    CHECK_THROWS_WITH(face_label_regions(labels, 5, {{0}}), Catch::Contains("4 labels for a mesh of 5 faces"));
    CHECK_THROWS_WITH(face_label_regions({0, 300, 0, 0}, 4, {{0}}), Catch::Contains("face 1 has label 300"));
    CHECK_THROWS_WITH(face_label_regions(labels, 4, {{3}}, "bands.txt"), Catch::Contains("bands.txt: no face has label 3"));
}

}  // namespace surface_synth_test
