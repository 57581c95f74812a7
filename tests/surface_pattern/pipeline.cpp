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

TEST_CASE("pipeline on the bunny: the printable mesh is watertight and encloses exactly the thickened voxels",
          "[surface_pattern][pipeline]") {
    const triangle_mesh bunny = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj");
    const sp::surface_shell s = sp::make_shell(bunny, {.size_mm = 50, .resolution = 64});
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, sp::default_levels(64));
    const sp::exemplar ex = sp::make_exemplar(io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/giraffe.png"), nullptr, {.feature_px = 5});
    const sp::synthesizer syn(pyr, ex, {.mm_per_px = 0.25, .seed = 9});
    const sp::synthesis_result r = syn.synthesize();
    const sp::shell_level& l0 = pyr.levels[0];
    std::vector<std::uint8_t> solid = r.solid;
    const double h = l0.geometry.spacing.x;
    const sp::speck_report specks = sp::remove_specks(l0.geometry, l0.voxels, solid, 3 * h);
    for (std::size_t v = 0; v < solid.size(); ++v) CHECK(solid[v] <= r.solid[v]);  // specks only remove
    const sp::voxel_set thick = sp::thicken_inward(l0.geometry, l0.voxels, l0.normals, solid, 2.5 * h);
    const auto shell_solid = static_cast<std::size_t>(std::count(solid.begin(), solid.end(), std::uint8_t{1}));
    REQUIRE(shell_solid > 0);
    REQUIRE(thick.size() > shell_solid);
    const triangle_mesh m = sp::mesh_voxels(thick, 20);
    const auto topo = analyze_topology(m);
    CHECK(topo.is_watertight());
    // the voxel centres inside the mesh (the solid voxelizer, an independent inside test) are the thickened voxels
    const voxel_grid<std::uint8_t> inside = voxelize_solid(m, l0.geometry);
    std::size_t both = 0, only_mesh = 0, only_voxels = 0;
    std::vector<std::uint8_t> in_set(static_cast<std::size_t>(l0.geometry.count()), 0);
    for (const ivec3& p : thick.voxels) in_set[static_cast<std::size_t>(l0.geometry.index(p))] = 1;
    for (std::size_t i = 0; i < in_set.size(); ++i) {
        const bool a = in_set[i] != 0, b = inside.storage().data()[i] != 0;
        both += a && b, only_voxels += a && !b, only_mesh += b && !a;
    }
    INFO("thickened " << thick.size() << ", both " << both << ", only voxels " << only_voxels << ", only mesh " << only_mesh
                      << ", specks removed " << specks.removed_components);
    CHECK(static_cast<double>(only_voxels + only_mesh) <= 0.005 * static_cast<double>(thick.size()));
    // the thickened pieces are the shell's solid pieces grown inward: never more of them than voxels
    const sp::voxel_set_components cc = sp::set_components(thick);
    CHECK(cc.count >= 1);
    CHECK(cc.count <= specks.components_left + 1);
}
