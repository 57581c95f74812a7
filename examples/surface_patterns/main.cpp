// surface_patterns MESH --exemplar MASK.png [--color COLOR.png] --size MM --thickness MM --feature PX
//                  [--resolution N] [--scale MM_PER_PX] [--up X Y Z] [--jitter F] [--seed S]
//                  [--no-structure] -o OUTDIR
//
// By-example synthesis of a pattern in the voxel shell of a mesh (structurally-sound-patterns.md
// §3-§4, §6.1-§6.2.1), carved, thickened inward and meshed. Writes
//   OUTDIR/pattern.stl   watertight, smoothed mesh of the thickened solid voxels
//   OUTDIR/shell.vtk     CELL_DATA `state` (unsigned char): 0 not in the shell, 1 shell voxel carved
//                        empty, 2 shell voxel solid from the exemplar
//   OUTDIR/solid.vtk     CELL_DATA `solid` 0/1 on the same grid: the thickened voxels
//   OUTDIR/preview.png   shaded render of pattern.stl from two sides (exemplar colours with --color)
//   OUTDIR/report.json   voxels, energy and time per level, solid fractions, components, timings
// Every output is computed before the first one is written. The structural optimizer (§5) is not
// part of this version: --no-structure is required. Conventions (exit codes, --quiet, --json,
// --version): docs/tools.md.
#include <fabsynth/core.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/geometry/render.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/detail/atomic_file.hpp>
#include <fabsynth/io/vtk.hpp>
#include <fabsynth/surface_pattern.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tool.hpp"

namespace fs = std::filesystem;
using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

namespace {

using clock_type = std::chrono::steady_clock;
double since(clock_type::time_point t) { return std::chrono::duration<double>(clock_type::now() - t).count(); }

/// One uint8 cell field over the whole grid.
io::structured_points byte_grid(const grid_geometry& g, const std::string& name, std::vector<double> values) {
    io::structured_points out{.dims = g.dims + 1, .origin = g.origin, .spacing = g.spacing, .cell_data = true, .fields = {}};
    out.fields.push_back({name, 1, std::move(values), io::vtk_type::uint8});
    return out;
}

/// Colour of each mesh vertex: the exemplar colour through the label of the nearest solid shell
/// voxel, at that voxel's centre (searched in growing cubes around the vertex, up to `reach`
/// voxels), lifted to [60, 255] so that shading still shows on near-black colours.
std::vector<std::array<std::uint8_t, 3>> vertex_colours(const triangle_mesh& m, const sp::synthesizer& syn, const sp::synthesis_result& r,
                                                        int reach) {
    const sp::shell_level& lv = syn.pyramid().levels[0];
    std::vector<std::array<std::uint8_t, 3>> out(m.num_vertices(), {200, 200, 205});
    parallel_for(0, m.num_vertices(), [&](std::size_t i) {
        const vec3 x = m.vertices[i];
        const ivec3 c = lv.geometry.voxel_of(x);
        for (int rad = 0; rad <= reach; ++rad) {
            double best = 1e300;
            std::int64_t bv = -1;
            for (int dz = -rad; dz <= rad; ++dz)
                for (int dy = -rad; dy <= rad; ++dy)
                    for (int dx = -rad; dx <= rad; ++dx) {
                        if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != rad) continue;
                        const std::int64_t v = lv.find(c + ivec3(dx, dy, dz));
                        if (v < 0 || !r.solid[static_cast<std::size_t>(v)]) continue;
                        const double d = glm::length(lv.center(static_cast<std::size_t>(v)) - x);
                        if (d < best) best = d, bv = v;
                    }
            if (bv >= 0) {
                // the colour at the voxel centre (inside the solid), not at the vertex on its border
                const vec2 p = syn.labels().map(lv.center(static_cast<std::size_t>(bv)), r.labels[0][static_cast<std::size_t>(bv)]);
                const std::array<std::uint8_t, 3> c = syn.source().colour_at(p.x, p.y);
                for (int k = 0; k < 3; ++k) out[i][static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(60 + c[static_cast<std::size_t>(k)] * 195 / 255);
                return;
            }
        }
    }, {.grain = 4096});
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"By-example synthesis of a carved pattern along a surface, thickened into a printable shell "
                 "(structural optimization not available yet: run with --no-structure)",
                 "surface_patterns"};
    tool::common common(app);
    std::string mesh_path, mask_path, colour_path, out_dir;
    double size = 0, thickness = 0, feature = 0, scale = 0, jitter = 0.1, min_feature = -1, max_memory_gib = 16;
    int resolution = 256, levels = 0, passes = 2, candidates = 128, smoothing = 20;
    std::vector<double> up{0, 0, 1};
    std::uint64_t seed = 1;
    bool no_structure = false, no_tiling = false;
    app.add_option("mesh", mesh_path, "input triangle mesh (.obj, .stl, .ply); open meshes are carved along their surface")->required();
    app.add_option("--exemplar", mask_path, "mask PNG: white = solid, black = empty")->required();
    app.add_option("--color", colour_path, "colour PNG of the same size (synthesis channels and the preview)");
    app.add_option("--size", size, "longest side of the scaled mesh (mm)")->required()->check(CLI::PositiveNumber);
    app.add_option("--thickness", thickness, "shell thickness, inward along the normals (mm, >= one voxel)")->required()->check(CLI::PositiveNumber);
    app.add_option("--feature", feature, "r_pattern: feature radius of the exemplar (pixels, > 0)")->required();
    app.add_option("-r,--resolution", resolution, "voxels along the longest side (paper: 256; 512 for large models)")->check(CLI::Range(16, 4096));
    app.add_option("--levels", levels, "pyramid levels (0 = ceil(log2 resolution): 8 at 256, 9 at 512)")->check(CLI::Range(0, 16));
    app.add_option("--scale", scale, "exemplar scale (mm per exemplar pixel; 0 = one voxel per pixel)")->check(CLI::NonNegativeNumber);
    app.add_option("--up", up, "pattern orientation: its up follows this direction on the surface (0 0 0: free rotations)")->expected(3);
    app.add_option("--jitter", jitter, "fraction of voxels given a random label per level")->check(CLI::Range(0.0, 1.0));
    app.add_option("--passes", passes, "optimization passes per level")->check(CLI::Range(1, 64));
    app.add_option("--candidates", candidates, "candidates per voxel (coherent + random)")->check(CLI::Range(1, 4096));
    app.add_option("--seed", seed, "random seed");
    app.add_option("--min-feature", min_feature, "smallest printable feature (mm): smaller solid pieces are removed (default: the thickness)");
    app.add_option("--smoothing", smoothing, "Taubin smoothing iterations of pattern.stl")->check(CLI::Range(0, 200));
    app.add_flag("--no-tiling", no_tiling, "the exemplar does not tile: penalise lookups near its border (§6.1)");
    app.add_flag("--no-structure", no_structure, "appearance only, no structural optimization (the only mode of this version)");
    app.add_option("--max-memory", max_memory_gib, "refuse runs estimated to need more memory than this (GiB)")->check(CLI::PositiveNumber);
    app.add_option("-o,--output", out_dir, "output directory")->required();

    return tool::run(app, common, argc, argv, [&] {
        auto progress = common.progress();
        const auto t_start = clock_type::now();
        const fs::path out(out_dir);
        const fs::path stl = out / "pattern.stl", shell_vtk = out / "shell.vtk", solid_vtk = out / "solid.vtk", preview = out / "preview.png",
                       report = out / "report.json";
        tool::check_outputs({mesh_path, mask_path, colour_path}, {stl, shell_vtk, solid_vtk, preview, report});
        if (!no_structure)
            throw invalid_input("the structural optimizer (connected, reinforced patterns) is not part of this version: run with --no-structure");
        if (!(std::isfinite(feature) && feature > 0)) throw invalid_input("--feature must be a finite number of pixels > 0, got " + std::to_string(feature));
        const double h = size / resolution;
        if (thickness < h) {
            char msg[200];
            std::snprintf(msg, sizeof msg, "--thickness %.4g mm is below one voxel (%.4g mm at --size %.4g --resolution %d)", thickness, h, size, resolution);
            throw invalid_input(msg);
        }
        if (min_feature < 0) min_feature = thickness;
        const vec3 up_dir(up[0], up[1], up[2]);

        progress(0.0, "read inputs");
        const triangle_mesh mesh = io::read_mesh(mesh_path);
        const image8 mask = io::read_png(mask_path);
        image8 colour;
        if (!colour_path.empty()) colour = io::read_png(colour_path);
        sp::exemplar ex = sp::make_exemplar(mask, colour_path.empty() ? nullptr : &colour, {.feature_px = feature, .tileable = !no_tiling});
        const double ex_fraction = ex.solid_fraction();

        progress(0.02, "voxelize");
        auto t = clock_type::now();
        const sp::surface_shell shell = sp::make_shell(mesh, {.size_mm = size, .resolution = resolution, .max_memory_bytes = max_memory_gib * double(1ull << 30)});
        const sp::shell_pyramid pyr = sp::build_shell_pyramid(shell, levels ? levels : sp::default_levels(resolution));
        const double t_voxelize = since(t);
        const mesh_topology_info mesh_topo = analyze_topology(shell.mesh);

        t = clock_type::now();
        const sp::synthesizer syn(pyr, std::move(ex), {.mm_per_px = scale, .candidates = candidates, .jitter = jitter, .up = up_dir, .passes = passes, .seed = seed});
        sp::synthesis_result result = syn.synthesize([&](double f, std::string_view stage) { progress(0.05 + 0.6 * f, stage); });
        const double t_synthesis = since(t);

        progress(0.7, "fabrication");
        t = clock_type::now();
        const sp::shell_level& l0 = pyr.levels[0];
        std::vector<std::uint8_t> solid = result.solid;
        std::size_t carved_solid = 0;
        for (auto s : solid) carved_solid += s;
        const sp::speck_report specks = sp::remove_specks(l0.geometry, l0.voxels, solid, min_feature);
        const sp::voxel_set thick = sp::thicken_inward(l0.geometry, l0.voxels, l0.normals, solid, thickness);
        const sp::voxel_set_components cc = sp::set_components(thick);
        const triangle_mesh pattern = sp::mesh_voxels(thick, smoothing);
        const mesh_topology_info topo = analyze_topology(pattern);
        const double t_fabrication = since(t);

        progress(0.85, "preview");
        t = clock_type::now();
        std::vector<std::array<std::uint8_t, 3>> colours;
        if (!colour_path.empty()) colours = vertex_colours(pattern, syn, result, static_cast<int>(std::ceil(thickness / h)) + 2);
        const render_view view{.direction = glm::length(up_dir) > 0 && std::abs(up_dir.y) < 0.9 * glm::length(up_dir) ? vec3(0, 1, 0) : vec3(0, 0, -1),
                               .up = glm::length(up_dir) > 0 ? up_dir : vec3(0, 0, 1)};
        const image8 picture = pattern.empty() ? image8(1552, 768, 3, 255)
                                               : render_two_sides(pattern, view, {.width = 768, .height = 768}, colours);
        const double t_preview = since(t);

        // everything is computed: write the set
        progress(0.9, "write");
        t = clock_type::now();
        fs::create_directories(out);
        std::size_t shell_solid = 0;
        {
            std::vector<double> state(static_cast<std::size_t>(l0.geometry.count()), 0.0);
            for (std::size_t v = 0; v < l0.size(); ++v) {
                state[static_cast<std::size_t>(l0.geometry.index(l0.voxels[v]))] = solid[v] ? 2.0 : 1.0;
                shell_solid += solid[v];
            }
            io::write_vtk(shell_vtk, byte_grid(l0.geometry, "state", std::move(state)));
        }
        {
            std::vector<double> s(static_cast<std::size_t>(l0.geometry.count()), 0.0);
            for (const ivec3& p : thick.voxels) s[static_cast<std::size_t>(l0.geometry.index(p))] = 1.0;
            io::write_vtk(solid_vtk, byte_grid(l0.geometry, "solid", std::move(s)));
        }
        io::write_mesh(stl, pattern);
        io::write_png(preview, picture);
        const double t_write = since(t);

        nlohmann::ordered_json levels_json = nlohmann::ordered_json::array();
        for (const sp::level_report& l : result.levels)
            levels_json.push_back({{"level", l.level}, {"voxels", l.voxels}, {"spacing_mm", l.spacing_mm}, {"sigma_px", l.sigma_px},
                                   {"energy_initial", l.energy_initial}, {"energy_passes", l.energy_passes}, {"candidates", l.candidates},
                                   {"candidates_per_second", l.seconds > 0 ? static_cast<double>(l.candidates) / l.seconds : 0.0},
                                   {"seconds", l.seconds}});
        const double shell_fraction = static_cast<double>(shell_solid) / static_cast<double>(l0.size());
        const double total = since(t_start);
        nlohmann::ordered_json rep = {
            {"mesh", mesh_path},
            {"exemplar", mask_path},
            {"color", colour_path},
            {"mesh_closed", mesh_topo.is_watertight()},
            {"size_mm", size},
            {"grid", {l0.geometry.dims.x, l0.geometry.dims.y, l0.geometry.dims.z}},
            {"voxel_mm", h},
            {"exemplar_mm_per_px", syn.options().mm_per_px},
            {"thickness_mm", thickness},
            {"min_feature_mm", min_feature},
            {"structure", false},
            {"shell_voxels", l0.size()},
            {"levels", levels_json},
            {"passes_per_level", passes},
            {"solid_fraction", shell_fraction},
            {"solid_fraction_synthesized", static_cast<double>(carved_solid) / static_cast<double>(l0.size())},
            {"exemplar_solid_fraction", ex_fraction},
            {"specks_removed", specks.removed_components},
            {"speck_voxels_removed", specks.removed_voxels},
            {"solid_voxels", thick.voxels.size()},
            {"components_26", cc.count},
            {"pattern_faces", pattern.num_faces()},
            {"pattern_watertight", topo.is_watertight()},
            {"timings", {{"voxelize", t_voxelize}, {"synthesis", t_synthesis}, {"structural_analysis", 0.0}, {"fabrication", t_fabrication},
                         {"preview", t_preview}, {"write", t_write}, {"total", total}}},
            {"seed", seed},
        };
        io::detail::atomic_write(report, rep.dump(2) + "\n");
        progress(1.0, "write");

        char line[512];
        std::snprintf(line, sizeof line,
                      "%s: %zu shell voxels, %zu levels, solid fraction %.3f (exemplar %.3f), %d specks removed, %zu solid voxels in %d "
                      "26-components, pattern.stl %zu faces %s; synthesis %.2f s, total %.2f s",
                      fs::path(mesh_path).filename().string().c_str(), l0.size(), pyr.levels.size(), shell_fraction, ex_fraction,
                      specks.removed_components, thick.voxels.size(), cc.count, pattern.num_faces(),
                      topo.is_watertight() ? "watertight" : "NOT watertight", t_synthesis, total);
        common.say(line);
        common.summary({{"shell_voxels", l0.size()},
                        {"levels", pyr.levels.size()},
                        {"solid_fraction", shell_fraction},
                        {"exemplar_solid_fraction", ex_fraction},
                        {"components_26", cc.count},
                        {"pattern_faces", pattern.num_faces()},
                        {"watertight", topo.is_watertight()},
                        {"outputs", {stl.string(), shell_vtk.string(), solid_vtk.string(), preview.string(), report.string()}},
                        {"seconds", total}});
    });
}
