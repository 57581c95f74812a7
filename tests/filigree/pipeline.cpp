// The filigree pipeline in one call (filigree/pipeline.hpp): make_filigree gives what the chained
// building blocks give (same outline, same extrusion; same M_b on a surface), its printable mesh is
// one watertight piece, the region options select the faces the instances stand on, and a progress
// callback that returns false at any of its calls cancels the run.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/filigree/pipeline.hpp"
#include "fabsynth/filigree/surface/pipeline.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "support/filigree_elements.hpp"
#include "support/sphere_mesh.hpp"
#include "support/surface_setup.hpp"

namespace pipeline_test {

using namespace fabsynth;
using namespace fabsynth::filigree;

// Small runs: one round, no shell FEM (tests/filigree/reconstruct_structure.cpp and
// surface_structure.cpp cover §5; the latter through make_filigree).
inline filigree_options quick(std::uint64_t seed) {
    filigree_options o;
    o.synthesis.seed = seed;
    o.synthesis.max_rounds = 1;
    o.reinforcement.enabled = false;
    return o;
}

// Records every progress call; returns false at call number `stop` (1-based; 0: never) or at the
// first call of stage `stop_stage`.
struct recorder {
    std::vector<double> fractions;
    std::vector<std::string> stages;
    std::vector<double> seconds;  // since the first call
    std::chrono::steady_clock::time_point t0;
    std::size_t stop = 0;
    std::string stop_stage;
    bool operator()(double f, std::string_view stage) {
        const auto now = std::chrono::steady_clock::now();
        if (fractions.empty()) t0 = now;
        fractions.push_back(f);
        stages.emplace_back(stage);
        seconds.push_back(std::chrono::duration<double>(now - t0).count());
        return fractions.size() != stop && stage != stop_stage;
    }
    // The calls worth cancelling at (1-based): the first and the middle call of every stage, the last.
    [[nodiscard]] std::set<std::size_t> cancel_points() const {
        std::map<std::string, std::vector<std::size_t>> at;
        for (std::size_t i = 0; i < stages.size(); ++i) at[stages[i]].push_back(i + 1);
        std::set<std::size_t> k{stages.size()};
        for (const auto& [stage, calls] : at) k.insert(calls.front()), k.insert(calls[calls.size() / 2]);
        return k;
    }
    [[nodiscard]] std::size_t count(std::string_view stage) const { return static_cast<std::size_t>(std::count(stages.begin(), stages.end(), stage)); }
    [[nodiscard]] double longest_gap() const {
        double g = 0;
        for (std::size_t i = 1; i < seconds.size(); ++i) g = std::max(g, seconds[i] - seconds[i - 1]);
        return g;
    }
};

}  // namespace pipeline_test

TEST_CASE("make_filigree in a rectangle: the chained calls' outline and extrusion, one watertight piece, previews", "[filigree][pipeline]") {
    using namespace pipeline_test;
    const std::vector<element> cls{fabsynth::test::filigree_element("c_scroll", 14)};
    const std::vector<double> w{1.0};
    const planar_domain dom = planar_domain::rectangle(50, 40);
    const filigree_options opt = quick(5);
    recorder rec;
    const planar_filigree f = make_filigree(cls, w, dom, constant_field{}, opt, rec);

    // the same steps chained by hand
    const synthesis_result syn = synthesize_pattern(std::span<const element>(cls), w, dom, constant_field{}, opt.synthesis);
    const reinforcement_result rf = reinforce(std::span<const element>(cls), w, dom, constant_field{}, opt.synthesis, syn, opt.reinforcement);
    REQUIRE(!rf.outline.empty());
    CHECK(f.outline() == rf.outline);
    CHECK(f.synthesis.instances.size() == syn.instances.size());
    triangle_mesh m = printable_extrusion(rf.outline, rf.thickness);
    mirror_y(m);
    weld_to_float(m);
    CHECK(f.mesh == m);

    const mesh_topology_info topo = analyze_topology(f.mesh);
    CHECK(topo.is_watertight());
    CHECK(topo.components == 1);  // the tool prints one piece
    REQUIRE(f.instances_per_class.size() == 1);
    CHECK(f.instances_per_class[0] == f.reinforcement.instances.size());
    CHECK(f.instances_per_class[0] >= 4);
    CHECK(std::max(f.preview.width, f.preview.height) == 1600);
    CHECK(f.steps.width > 4 * 600);  // four panels side by side
    CHECK(f.view.lo.x < 0);
    CHECK(f.view.hi.x > 50);

    // progress: from 0 to 1, never backwards
    REQUIRE(rec.fractions.size() >= 4);
    CHECK(rec.fractions.front() == 0.0);
    CHECK(rec.fractions.back() == 1.0);
    CHECK(std::is_sorted(rec.fractions.begin(), rec.fractions.end()));

    // reported inside the loops of placement and boosting, not only between phases
    CHECK(rec.count("placement") >= 4);
    CHECK(rec.count("boosting") >= 2);
    WARN("planar: " << rec.fractions.size() << " progress calls, longest gap " << rec.longest_gap() << " s");
    // cancelled at the first and the middle call of every stage, and at the last call
    for (const std::size_t k : rec.cancel_points()) {
        INFO("cancelled at call " << k << " (" << rec.stages[k - 1] << ")");
        recorder stop;
        stop.stop = k;
        CHECK_THROWS_AS(make_filigree(cls, w, dom, constant_field{}, opt, stop), cancelled);
        CHECK(stop.fractions.size() == k);  // nothing reported after the refusal
    }

    // with the structural optimization: the FEM analyses and the thickening steps report too
    filigree_options full = opt;
    full.reinforcement.enabled = true;
    recorder thick;
    thick.stop_stage = "thickening";
    CHECK_THROWS_AS(make_filigree(cls, w, dom, constant_field{}, full, thick), cancelled);
    CHECK(thick.count("structural analysis") >= 1);
    CHECK(thick.stages.back() == "thickening");
}

TEST_CASE("make_filigree on a cylinder: the chained calls' M_b, a watertight one-piece solid, region faces, cancellation", "[filigree][pipeline][surface][slow]") {
    using namespace pipeline_test;
    const std::vector<element> cls{fabsynth::test::filigree_element("c_scroll", 12)};
    const std::vector<double> w{1.0};
    const triangle_mesh tube = fabsynth::test::cylinder(15, 24, 48, 1.5);
    surface_filigree_options opt;
    static_cast<filigree_options&>(opt) = quick(4);
    opt.up = {0, 0, 1};
    recorder rec;
    const surface_filigree f = make_filigree(cls, w, tube, opt, rec);

    // the same steps chained by hand on the test set-up (whole mesh, up +z, scale 1)
    const fabsynth::test::surface_setup band(tube, {0, 0, 1});
    const surface_synthesis_result syn = synthesize_on_surface(cls, w, band.region, band.field(), opt.synthesis);
    surface_reinforcement_options ro;
    ro.base = opt.reinforcement, ro.up = opt.up;
    const surface_reinforcement_result rf = reinforce_on_surface(cls, w, band.region, band.field(), opt.synthesis, syn, ro);
    CHECK(f.reinforcement.baked == rf.baked);
    CHECK(f.synthesis.instances.size() == syn.instances.size());

    const mesh_topology_info topo = analyze_topology(f.solid);
    CHECK(topo.is_watertight());
    CHECK(topo.components == 1);
    CHECK(f.solid_components == 1);
    CHECK(f.preview.channels == 3);
    CHECK(f.preview.height == 800);
    REQUIRE(f.instances_per_class.size() == 1);
    CHECK(f.instances_per_class[0] == f.synthesis.instances.size());

    // progress: from 0 to 1, inside placement too; cancelled at the first three calls, inside
    // placement and at the last
    REQUIRE(rec.fractions.size() >= 5);
    CHECK(rec.fractions.front() == 0.0);
    CHECK(rec.fractions.back() == 1.0);
    CHECK(std::is_sorted(rec.fractions.begin(), rec.fractions.end()));
    CHECK(rec.count("placement") >= 4);
    WARN("surface: " << rec.fractions.size() << " progress calls, longest gap " << rec.longest_gap() << " s");
    const std::size_t n = rec.fractions.size();
    const std::size_t in_placement = static_cast<std::size_t>(std::find(rec.stages.begin(), rec.stages.end(), "placement") - rec.stages.begin()) + 2;
    for (const std::size_t k : {std::size_t{1}, std::size_t{2}, std::size_t{3}, in_placement, n}) {
        INFO("cancelled at call " << k << " of " << n);
        recorder stop;
        stop.stop = k;
        CHECK_THROWS_AS(make_filigree(cls, w, tube, opt, stop), cancelled);
        CHECK(stop.fractions.size() == k);
    }

    // a region of faces (the band 4 <= z <= 16 mm): every instance stands in it
    std::vector<std::uint32_t> ids;
    for (std::uint32_t k = 0; k < tube.faces.size(); ++k) {
        double z = 0;
        for (const std::uint32_t v : tube.faces[k]) z += tube.vertices[v].z / 3;
        if (z >= 4 && z <= 16) ids.push_back(k);
    }
    surface_filigree_options part = opt;
    part.region_faces = ids;
    part.previews = false;
    const surface_filigree_base base(tube, part);
    CHECK(base.region().faces.size() == ids.size());
    const surface_filigree g = make_filigree(cls, w, base, part);
    const std::set<std::uint32_t> in(ids.begin(), ids.end());
    REQUIRE(!g.synthesis.instances.empty());
    for (const surface_instance& s : g.synthesis.instances) CHECK(in.count(s.anchor.face) == 1);
    CHECK(g.preview.data.empty());
    // a region of faces and a curve at once is refused
    part.region_curve = std::vector<vec3>{{15, 0, 10}, {0, 15, 10}, {-15, 0, 10}};
    CHECK_THROWS_AS(make_filigree(cls, w, tube, part), invalid_input);
}
