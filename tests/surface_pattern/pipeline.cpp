#include <catch2/catch.hpp>

#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/surface_pattern.hpp>
#include <fabsynth/voxel/voxelize.hpp>

#include <algorithm>
#include <string>

using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

TEST_CASE("make_pattern on the bunny: the printable mesh is watertight and encloses exactly the thickened voxels",
          "[surface_pattern][pipeline]") {
    const triangle_mesh bunny = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj");
    const sp::exemplar ex = sp::make_exemplar(io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/giraffe.png"), nullptr, {.feature_px = 5});
    sp::pattern_options o;
    o.size_mm = 50, o.resolution = 64, o.structure = false;
    const double h = o.size_mm / o.resolution;
    o.thickness_mm = 2.5 * h, o.min_feature_mm = 3 * h;
    o.synthesis = {.mm_per_px = 0.25, .seed = 9};
    const sp::pattern_result r = sp::make_pattern(bunny, ex, o);
    REQUIRE(r.state.size() == r.shell_voxels.size());
    std::size_t shell_solid = 0;
    for (std::uint8_t s : r.state) {
        CHECK((s == 1 || s == 2));  // no structural loop: carved or from the exemplar
        shell_solid += s == 2;
    }
    REQUIRE(shell_solid > 0);
    CHECK(r.solid_fraction == Approx(static_cast<double>(shell_solid) / static_cast<double>(r.state.size())));
    CHECK(r.solid_fraction <= r.solid_fraction_synthesized);  // specks only remove
    REQUIRE(r.thickened.size() > shell_solid);
    CHECK(r.watertight);
    CHECK(analyze_topology(r.mesh).is_watertight());
    CHECK(r.preview.width == 2 * 768 + 16);
    // the voxel centres inside the mesh (the solid voxelizer, an independent inside test) are the thickened voxels
    const voxel_grid<std::uint8_t> inside = voxelize_solid(r.mesh, r.grid);
    std::size_t both = 0, only_mesh = 0, only_voxels = 0;
    std::vector<std::uint8_t> in_set(static_cast<std::size_t>(r.grid.count()), 0);
    for (const ivec3& p : r.thickened.voxels) in_set[static_cast<std::size_t>(r.grid.index(p))] = 1;
    for (std::size_t i = 0; i < in_set.size(); ++i) {
        const bool a = in_set[i] != 0, b = inside.storage().data()[i] != 0;
        both += a && b, only_voxels += a && !b, only_mesh += b && !a;
    }
    INFO("thickened " << r.thickened.size() << ", both " << both << ", only voxels " << only_voxels << ", only mesh " << only_mesh
                      << ", specks removed " << r.specks.removed_components);
    CHECK(static_cast<double>(only_voxels + only_mesh) <= 0.005 * static_cast<double>(r.thickened.size()));
    // the thickened pieces are the shell's solid pieces grown inward: never more of them than the
    // pieces the speck filter left, and the mesh has one shell per piece
    const sp::voxel_set_components cc = sp::set_components(r.thickened);
    CHECK(static_cast<std::size_t>(cc.count) == r.components_26);
    CHECK(cc.count <= r.specks.components_left + 1);
    CHECK(analyze_topology(without_cavities(r.mesh)).components == r.components_26);  // inner shells bound enclosed voids
}

TEST_CASE("make_pattern with the structural loop ends in one piece and matches the hand-chained phases", "[surface_pattern][pipeline][slow]") {
    const triangle_mesh bunny = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj");
    const image8 mask = io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/hooks.png");
    sp::pattern_options o;
    o.size_mm = 40, o.resolution = 48, o.thickness_mm = 1.5, o.preview = false;
    o.synthesis.up = {0, 1, 0};
    o.structural.gravity = {0, -1, 0};
    const sp::pattern_result r = sp::make_pattern(bunny, sp::make_exemplar(mask, nullptr, {.feature_px = 4}), o);
    CHECK(r.structure.converged);
    CHECK(r.components_26 == 1);
    // one solid piece: every other shell of the mesh bounds a small enclosed void (fabricate.hpp)
    std::size_t cavities = 0;
    CHECK(analyze_topology(without_cavities(r.mesh, &cavities)).components == 1);
    CHECK(analyze_topology(r.mesh).components == cavities + 1);
    CHECK(r.watertight);
    CHECK(r.preview.empty());
    std::size_t reinforced = 0;
    for (std::uint8_t s : r.state) reinforced += s == 3;
    CHECK(reinforced > 0);  // the hooks are several pieces after synthesis: bridges were laid

    // the same phases chained by hand give the same voxels
    const sp::surface_shell shell = sp::make_shell(bunny, {.size_mm = 40, .resolution = 48});
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(shell, sp::default_levels(48));
    const sp::synthesizer syn(pyr, sp::make_exemplar(mask, nullptr, {.feature_px = 4}), o.synthesis);
    sp::synthesis_result res = syn.synthesize();
    const sp::shell_level& l0 = pyr.levels[0];
    (void)sp::remove_specks(l0.geometry, l0.voxels, res.solid, 1.5);
    const sp::surface_graph gs = sp::build_surface_graph(l0);
    sp::structure_options so = o.structural;
    so.r_pattern_mm = 4 * syn.options().mm_per_px, so.thickness_mm = 1.5;
    so.bridge_radius_mm = 40.0 / 48;  // the narrowest that prints: max(min feature / 2 = 0.75 mm, one voxel)
    CHECK(r.bridge_radius_mm == so.bridge_radius_mm);
    std::vector<std::uint8_t> bridges;
    const sp::structure_report rep = sp::optimize_structure(syn, res, gs, so, 30, &bridges);
    (void)sp::enlarge_thin_features(gs.graph(), res.solid, 0.75, 40.0 / 48, nullptr, &bridges);  // bridges are printable as laid
    sp::voxel_set thick = sp::thicken_inward(l0.geometry, l0.voxels, l0.normals, res.solid, 1.5);
    if (sp::set_components(thick, sp::mesh_connectivity{}).count != sp::set_components(thick).count) (void)sp::join_diagonal_contacts(thick);
    CHECK(rep.iterations.size() == r.structure.iterations.size());
    CHECK(thick.voxels == r.thickened.voxels);
}

TEST_CASE("make_pattern: the bunny with hooks keeps its look, the bridges add at most 0.6x the synthesized solid (issue bound 1.6x)",
          "[surface_pattern][pipeline][slow]") {
    // the paper's Fig. 1 / Table 1 row at 128^3 (the tool's main job runs it at 256^3): the hooks
    // start as dozens of pieces, so bridges are needed, and they must stay a minor part of the print
    const triangle_mesh bunny = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny.obj");
    const image8 mask = io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/hooks.png");
    sp::pattern_options o;
    o.size_mm = 100, o.resolution = 128, o.thickness_mm = 1.2, o.preview = false;
    o.synthesis.up = {0, 1, 0}, o.synthesis.seed = 1;
    o.structural.gravity = {0, -1, 0};
    const sp::pattern_result r = sp::make_pattern(bunny, sp::make_exemplar(mask, nullptr, {.feature_px = 2}), o);
    INFO("synthesized " << r.synthesized_voxels << ", final " << r.final_voxels << ", states 3+4 " << r.reinforcement_voxels << " + "
                        << r.thin_feature_voxels << ", pieces before " << r.structure.iterations.front().components_before);
    CHECK(r.structure.iterations.front().components_before > 10);
    CHECK(r.structure.converged);
    CHECK_FALSE(r.structure.overloaded);
    CHECK(r.components_26 == 1);
    CHECK(r.final_voxels <= 1.6 * r.synthesized_voxels);
    CHECK(r.reinforcement_ratio() <= 0.6);
}

TEST_CASE("make_pattern: bad options are refused, a cancelling callback stops every phase", "[surface_pattern][pipeline][slow]") {
    const triangle_mesh bunny = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj");
    const image8 mask = io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/voronoi_cells.png");
    const sp::exemplar ex = sp::make_exemplar(mask, nullptr, {.feature_px = 4});
    sp::pattern_options o;
    o.size_mm = 30, o.resolution = 32, o.thickness_mm = 1.5, o.validate = true, o.stages = true;
    o.structural.gravity = {0, -1, 0};
    {
        sp::pattern_options bad = o;
        bad.thickness_mm = 0.5;  // below one voxel (0.94 mm)
        CHECK_THROWS_WITH(sp::make_pattern(bunny, ex, bad), Catch::Contains("below one voxel"));
        bad = o, bad.structure = false;
        CHECK_THROWS_WITH(sp::make_pattern(bunny, ex, bad), Catch::Contains("structural loop"));
        bad = o, bad.size_mm = -1;
        CHECK_THROWS_AS(sp::make_pattern(bunny, ex, bad), invalid_input);
        // validation above the memory budget is refused by make_pattern itself, before any work
        bad = o, bad.resolution = 256, bad.max_memory_bytes = 0.5 * sp::validation_bytes(256);
        bool progressed = false;
        CHECK_THROWS_WITH(sp::make_pattern(bunny, ex, bad, [&](double, std::string_view) { progressed = true; }),
                          Catch::Contains("validation at resolution 256") && Catch::Contains("max_memory_bytes"));
        CHECK_FALSE(progressed);
        bad.validate = false, bad.stages = false, bad.preview = false, bad.max_memory_bytes = 0.5 * sp::validation_bytes(256);
        CHECK_NOTHROW(bad.validate_options());  // the same budget without validation passes the check
    }
    // count the reports of a whole run, then cancel at the first, at the last and in between
    std::vector<std::string> stages;
    const sp::pattern_result whole = sp::make_pattern(bunny, ex, o, [&](double, std::string_view s) { stages.emplace_back(s); });
    REQUIRE(whole.validation.size() == 3);
    REQUIRE(stages.size() > 20);
    for (const std::size_t k : {std::size_t{1}, stages.size() / 5, stages.size() / 2, 4 * stages.size() / 5, stages.size()}) {
        std::size_t calls = 0;
        INFO("cancel at report " << k << " of " << stages.size() << " (" << stages[k - 1] << ")");
        CHECK_THROWS_AS(sp::make_pattern(bunny, ex, o, [&](double, std::string_view) { return ++calls < k; }), cancelled);
        CHECK(calls == k);
    }
}
