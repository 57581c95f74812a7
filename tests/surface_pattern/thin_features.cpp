#include <catch2/catch.hpp>

#include <fabsynth/surface_pattern/abstract_graph.hpp>
#include <fabsynth/surface_pattern/shell.hpp>
#include <fabsynth/surface_pattern/thin_features.hpp>

#include <cmath>

using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

TEST_CASE("thin features: a one-voxel line is widened to the minimal radius, a wide disk is left alone", "[surface_pattern][thin_features]") {
    triangle_mesh plate;
    plate.vertices = {{0, 0, 0}, {60, 0, 0}, {60, 60, 0}, {0, 60, 0}};
    plate.faces = {{0, 1, 2}, {0, 2, 3}};
    const sp::surface_shell s = sp::make_shell(plate, {.size_mm = 60, .resolution = 60});  // 1 mm voxels, one layer
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, 1);
    const sp::shell_level& l0 = pyr.levels[0];
    const sp::surface_graph gs = sp::build_surface_graph(l0);
    std::vector<std::uint8_t> solid(l0.size(), 0);
    auto at = [&](std::size_t v) { return l0.center(v); };
    for (std::size_t v = 0; v < l0.size(); ++v) {
        const vec3 c = at(v);
        const bool line = c.x > 5 && c.x < 25 && std::abs(c.y - 30.5) < 0.6;         // 1 voxel wide, 20 long
        const bool disk = glm::length(vec3(c.x - 45, c.y - 30, 0)) < 8;               // 16 mm across
        solid[v] = (line || disk) ? 1 : 0;
    }
    const std::vector<std::uint8_t> before = solid;
    std::vector<std::uint8_t> added;
    const sp::thin_feature_report rep = sp::enlarge_thin_features(gs.graph(), solid, 1.5, 1.0, &added);
    CHECK(rep.skeleton_voxels > 0);
    CHECK(rep.added_voxels > 0);
    for (std::size_t v = 0; v < l0.size(); ++v) {
        CHECK(solid[v] >= before[v]);  // a union: nothing removed
        const vec3 c = at(v);
        // inside the middle of the line, every voxel within 1.5 mm across is solid now
        if (c.x > 9 && c.x < 21 && std::abs(c.y - 30.5) <= 1.5) CHECK(solid[v] == 1);
        // the disk is wider than the radius: nothing is added around it
        if (c.x > 33) CHECK(solid[v] == before[v]);
        CHECK(added[v] == (solid[v] && !before[v] ? 1 : 0));
    }
    // voxels flagged printable (bridges laid at the radius) stay out of the skeleton: the line is
    // left as it is, the rest of the pattern is treated as before
    {
        std::vector<std::uint8_t> printable(l0.size(), 0), flagged = before;
        for (std::size_t v = 0; v < l0.size(); ++v) printable[v] = before[v] && at(v).x < 30;
        const sp::thin_feature_report pr = sp::enlarge_thin_features(gs.graph(), flagged, 1.5, 1.0, nullptr, &printable);
        CHECK(pr.added_voxels == 0);
        CHECK(flagged == before);
        std::vector<std::uint8_t> short_flags(5, 0);
        CHECK_THROWS_AS(sp::enlarge_thin_features(gs.graph(), flagged, 1.5, 1.0, nullptr, &short_flags), invalid_input);
    }
    std::vector<std::uint8_t> again = before;
    CHECK(sp::enlarge_thin_features(gs.graph(), again, 0.0, 1.0).added_voxels == 0);
    CHECK(again == before);
    std::vector<std::uint8_t> wrong(3, 0);
    CHECK_THROWS_AS(sp::enlarge_thin_features(gs.graph(), wrong, 1.0, 1.0), invalid_input);
    CHECK_THROWS_AS(sp::enlarge_thin_features(gs.graph(), again, std::nan(""), 1.0), invalid_input);
}
