// surface_patterns MESH --exemplar MASK.png [--color COLOR.png] --size MM --thickness MM --feature PX
//                  [--resolution N] [--scale MM_PER_PX] [--up X Y Z] [--jitter F] [--seed S]
//                  [--gravity X Y Z] [--material abs|pla] [--safety-factor F] [--samples N] [--geodesic F]
//                  [--load-factor F] [--support-plane PX PY PZ NX NY NZ [--support-band MM]] [--loads FILE] [--bridge-radius MM] [--bridge-band F] [--design-load N] [--max-iterations K] [--stages] [--validate] [--no-structure] [--preview-size PX]
//                  -o OUTDIR
//
// By-example synthesis of a structurally sound pattern in the voxel shell of a mesh
// (structurally-sound-patterns.md, Algorithm 1): synthesis (§4), then structural steps (§5:
// abstract graph, beam FEM, reinforcement bridges) alternating with constrained resynthesis until
// the pattern is one piece that carries the force profile, thin features enlarged (§6.2.1),
// thickened inward and meshed. Writes
//   OUTDIR/pattern.stl   watertight, smoothed mesh of the thickened solid voxels, simplified within
//                        --mesh-tolerance (default half a voxel; --no-simplify: as extracted)
//   OUTDIR/pattern.3mf   the same mesh as 3MF, in millimetres, with per-triangle colours: the exemplar's, or
//                        blue reinforcement and green enlarged thin features (where lib3mf is available)
//   OUTDIR/shell.vtk     CELL_DATA `state` (unsigned char): 0 not in the shell, 1 shell voxel carved
//                        empty, 2 solid from the exemplar, 3 reinforcement (made solid by a bridge
//                        of §5.2 where the pattern was empty), 4 thin feature enlarged (§6.2.1)
//   OUTDIR/solid.vtk     CELL_DATA `solid` 0/1 on the same grid: the thickened voxels; with --validate
//                        also `stress_expected_pa` and `stress_unexpected_pa` (float): |s1|+|s2|+|s3|
//                        per voxel under each load (the paper's Fig. 16), 0 outside the solid and in
//                        the support zone, -1 in a piece without support (left out of the statistics);
//                        the stage files below carry their own stage's fields
//   OUTDIR/preview.png   shaded render of pattern.stl from two sides (exemplar colours with --color;
//                        reinforcements blue, enlarged thin features green)
//   OUTDIR/report.json   voxels, energy and time per level, every structural iteration (components,
//                        edges added per criterion, max stress, solves), validation statistics
// With --stages also OUTDIR/solid_connected.vtk and OUTDIR/solid_forces.vtk: the thickened voxels
// of the loop run with the connectivity criterion only and with connectivity + force profile (the
// first two rows of the paper's Table 3; solid.vtk is the third). --validate adds a full-resolution
// voxel FEM of each written solid (§6.3): gravity, then the orthogonal unexpected load.
// --no-structure: appearance only (states 1-2). Every output is computed before the first one is
// written. Conventions (exit codes, --quiet, --json, --version): docs/tools.md.
#include <fabsynth/core.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/geometry/render.hpp>
#include <fabsynth/io/detail/number_lines.hpp>
#include <fabsynth/io/detail/read_file.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/atomic_file.hpp>
#include <fabsynth/io/vtk.hpp>
#include <fabsynth/surface_pattern.hpp>
#if defined(FABSYNTH_HAS_LIB3MF)
#include <fabsynth/io/mesh_3mf.hpp>
#endif

#include <chrono>
#include <cmath>
#include <optional>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "output_set.hpp"
#include "print_mesh.hpp"
#include "tool.hpp"

namespace fs = std::filesystem;
using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

namespace {

/// One uint8 cell field over the whole grid.
io::structured_points byte_grid(const grid_geometry& g, const std::string& name, std::vector<double> values) {
    io::structured_points out{.dims = g.dims + 1, .origin = g.origin, .spacing = g.spacing, .cell_data = true, .fields = {}};
    out.fields.push_back({name, 1, std::move(values), io::vtk_type::uint8});
    return out;
}

/// --loads FILE: one force per line, "x y z fx fy fz [radius]" (mm, N, mm), in io/numbers.hpp's
/// text form (blanks or commas, '#' comments). Throws io_error naming the file and line.
std::vector<sp::area_load> read_loads(const std::string& path) {
    std::vector<sp::area_load> loads;
    io::detail::for_each_number_line(io::detail::read_file(path), path, [&](std::size_t line, const std::vector<double>& v) {
        if (v.size() != 6 && v.size() != 7) throw io_error(path, line, std::to_string(v.size()) + " numbers, expected x y z fx fy fz [radius] (mm, N, mm)");
        if (v.size() == 7 && v[6] < 0) throw io_error(path, line, "the radius must be >= 0 mm");
        loads.push_back({vec3(v[0], v[1], v[2]), vec3(v[3], v[4], v[5]), v.size() == 7 ? v[6] : 0.0});
    });
    if (loads.empty()) throw io_error("--loads file '" + path + "' holds no load");
    return loads;
}

nlohmann::ordered_json stats_json(const sp::stress_statistics& s) {
    return {{"average_pa", s.average}, {"median_pa", s.median}, {"p99_pa", s.p99}, {"max_pa", s.max}, {"elements", s.elements},
            {"fixed_elements", s.fixed_elements}, {"unsupported_pieces", s.unsupported_pieces}, {"unsupported_voxels", s.unsupported_voxels},
            {"cg_iterations", s.iterations},
            {"seconds", s.seconds}};
}

nlohmann::ordered_json structure_json(const sp::structure_report& rep) {
    nlohmann::ordered_json its = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < rep.iterations.size(); ++k) {
        const sp::structural_step_report& it = rep.iterations[k];
        nlohmann::ordered_json j = {
            {"iteration", k + 1}, {"samples", it.samples}, {"solid_edges", it.solid_edges}, {"empty_edges", it.empty_edges},
            {"components_before", it.components_before}, {"components_after", it.components_after},
            {"added_connect", it.added_connect}, {"added_force", it.added_force}, {"added_geodesic", it.added_geodesic},
            {"max_stress_mpa", it.max_stress_mpa}, {"max_stress_after_mpa", it.max_stress_after_mpa},
            {"allowable_stress_mpa", it.allowable_stress_mpa}, {"load_n", it.load_n}, {"force_bound_hit", it.force_bound_hit},
            {"geodesic_threshold_mm", it.geodesic_threshold_mm},
            {"max_geodesic_mm", it.max_geodesic_mm},  // null (inf) while a piece is cut off
            {"solves", it.solves}, {"beam_width_mm", it.beam_width_mm},
            {"beam_knots", it.beam_knots}, {"reinforced_voxels", it.reinforced_voxels},
            {"seconds", it.seconds}, {"solve_seconds", it.solve_seconds}};
        if (k < rep.resyntheses.size()) {
            std::size_t updated = 0;
            for (std::size_t u : rep.resyntheses[k].updated) updated += u;
            j["resynthesis"] = {{"start_level", rep.resyntheses[k].start_level}, {"forced", rep.resyntheses[k].forced},
                                {"updated_voxels", updated}, {"unsatisfied", rep.resyntheses[k].unsatisfied}};
        }
        its.push_back(j);
    }
    return {{"converged", rep.converged}, {"iterations", its}, {"forced_voxels", rep.forced_voxels},
            {"structure_seconds", rep.structure_seconds}, {"resynthesis_seconds", rep.resynthesis_seconds}};
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"By-example synthesis of a structurally sound carved pattern along a surface, thickened into a printable shell",
                 "surface_patterns"};
    tool::common common(app);
    std::string mesh_path, mask_path, colour_path, out_dir, material_name = "abs";
    double size = 0, thickness = 0, feature = 0, scale = 0, jitter = 0.1, min_feature = -1, max_memory_gib = 16;
    double geodesic = 1.5, design_load = 0, load_factor = 20, safety_factor = 2, bridge_radius = 0, bridge_band = 0.25;
    int resolution = 256, levels = 0, passes = 2, candidates = 128, smoothing = 50, max_iterations = 30, preview_size = 768;
    std::size_t samples = 1000;
    std::vector<double> up{0, 0, 1}, gravity{0, 0, -1}, support_plane;
    double support_band = -1;
    std::string loads_path;
    std::uint64_t seed = 1;
    bool no_structure = false, no_tiling = false, stages = false, validate = false;
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
    app.add_option("--min-feature", min_feature, "smallest printable feature (mm): smaller solid pieces are removed, thinner features enlarged (default: the thickness)");
    app.add_option("--smoothing", smoothing, "Taubin smoothing iterations of pattern.stl (each vertex stays within half a voxel of the voxel surface)")->check(CLI::Range(0, 200));
    tool::mesh_simplification simplify(app, 0, "half a voxel");
    app.add_flag("--no-tiling", no_tiling, "the exemplar does not tile: penalise lookups near its border (§6.1)");
    app.add_option("--gravity", gravity, "force profile: gravity direction; the lowest 10% along it are the supports")->expected(3);
    CLI::Option* plane_opt = app.add_option("--support-plane", support_plane,
                   "supports: the abstract vertices (and, with --validate, the voxels) within --support-band of the plane through PX PY PZ "
                   "with normal NX NY NZ are fixed, instead of the lowest 10% along --gravity (mm, in the scaled mesh's frame: bounding-box "
                   "corner at the origin, longest side --size)")
        ->expected(6);
    app.add_option("--support-band", support_band, "supports: half-width of the band around --support-plane (mm; default one voxel)")
        ->check(CLI::NonNegativeNumber)
        ->needs(plane_opt);
    app.add_option("--loads", loads_path,
                   "force profile: a file of forces, one per line 'x y z fx fy fz [radius]' (mm, N, mm; the scaled mesh's frame), each shared by "
                   "the abstract vertices within radius of the point (the nearest when none is); replaces the weight rule");
    app.add_option("--material", material_name, "printing material: abs or pla (elastic constants, tensile strength)");
    app.add_option("--safety-factor", safety_factor, "force profile: beams are reinforced until their stress is below the tensile strength / F")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--bridge-radius", bridge_radius,
                   "reinforcement bridges: dilation radius of their voxel paths (mm; 0 = the narrowest that prints, max(min feature / 2, one voxel); "
                   "the paper uses r_pattern)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--bridge-band", bridge_band,
                   "reinforcement bridges: candidates whose scores lie within this ratio of the best are ranked by the voxels they add (1 = by score only)")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    app.add_option("--samples", samples, "abstract graph vertices (paper: 1000)")->check(CLI::Range(2, 100000));
    app.add_option("--geodesic", geodesic, "geodesic criterion: reinforce empty edges whose endpoints are farther apart in the pattern than F x the object's extent (0 = off)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--load-factor", load_factor, "force profile: the pattern's own weight times this factor, along --gravity")->check(CLI::NonNegativeNumber);
    app.add_option("--design-load", design_load, "force profile: a fixed total force (N) instead of the weight rule, spread over the abstract vertices (0 = the weight rule)")->check(CLI::NonNegativeNumber);
    app.add_option("--max-iterations", max_iterations, "bound on structural iterations (paper: 3-24)")->check(CLI::Range(1, 1000));
    app.add_flag("--stages", stages, "also write solid_connected.vtk and solid_forces.vtk (Table 3 stages)");
    app.add_flag("--validate", validate, "full-resolution voxel FEM of the result (and of the stages): stress statistics in report.json");
    app.add_flag("--no-structure", no_structure, "appearance only, no structural optimization");
    app.add_option("--preview-size", preview_size, "pixels of one view of preview.png (the picture is two views wide)")
        ->check(CLI::Range(16, 8192))
        ->capture_default_str();
    tool::add_memory_limit(app, max_memory_gib);
    app.add_option("-o,--output", out_dir, "output directory")->required();

    return tool::run(app, common, argc, argv, [&] {
        auto progress = common.progress();
        const fs::path out(out_dir);
        const fs::path stl = out / "pattern.stl", shell_vtk = out / "shell.vtk", solid_vtk = out / "solid.vtk", preview = out / "preview.png",
                       report = out / "report.json", connected_vtk = out / "solid_connected.vtk", forces_vtk = out / "solid_forces.vtk",
                       threemf = out / "pattern.3mf";
        std::vector<fs::path> outputs{stl, threemf, shell_vtk, solid_vtk, preview, report};
        if (stages) outputs.push_back(connected_vtk), outputs.push_back(forces_vtk);
        tool::check_outputs({mesh_path, mask_path, colour_path, loads_path}, outputs);
        if (no_structure && (stages || validate)) throw invalid_input("--stages and --validate need the structural optimizer: drop --no-structure");
        if (!(std::isfinite(feature) && feature > 0)) throw invalid_input("--feature must be a finite number of pixels > 0, got " + std::to_string(feature));
        const double h = size / resolution;
        if (thickness < h) {
            char msg[200];
            std::snprintf(msg, sizeof msg, "--thickness %.4g mm is below one voxel (%.4g mm at --size %.4g --resolution %d)", thickness, h, size, resolution);
            throw invalid_input(msg);
        }
        if (min_feature < 0) min_feature = thickness;
        if (!(support_band < 0 || std::isfinite(support_band))) throw invalid_input("--support-band must be a finite number of mm >= 0");
        if (no_structure && (!support_plane.empty() || !loads_path.empty()))
            throw invalid_input("--support-plane and --loads act on the structural optimizer: drop --no-structure");
        if (!loads_path.empty() && design_load > 0) throw invalid_input("--loads replaces --design-load: give one of them");
        const vec3 up_dir(up[0], up[1], up[2]), gravity_dir(gravity[0], gravity[1], gravity[2]);
        if (!(glm::length(gravity_dir) > 0) || !all_finite(gravity_dir)) throw invalid_input("--gravity must be a finite non-zero direction");
        const sp::print_material material = sp::print_material::named(material_name);
        if (validate) {
            tool::require_memory(sp::validation_bytes(resolution), max_memory_gib, "--validate at --resolution " + std::to_string(resolution) + " (voxel FEM)");
        }

        // Staged now (an unwritable OUTDIR is refused before the work), moved into OUTDIR together at
        // the end; report.json, which describes the set, goes last.
        tool::output_set files;
        const fs::path stl_file = files.add(stl), shell_file = files.add(shell_vtk), solid_file = files.add(solid_vtk),
                       preview_file = files.add(preview), connected_file = files.add(connected_vtk), forces_file = files.add(forces_vtk),
                       report_file = files.add_manifest(report);
#if defined(FABSYNTH_HAS_LIB3MF)
        const fs::path threemf_file = files.add(threemf);
#endif

        progress(0.0, "read inputs");
        const triangle_mesh mesh = io::read_mesh(mesh_path);
        const image8 mask = io::read_png(mask_path);
        image8 colour;
        if (!colour_path.empty()) colour = io::read_png(colour_path);
        sp::exemplar ex = sp::make_exemplar(mask, colour_path.empty() ? nullptr : &colour, {.feature_px = feature, .tileable = !no_tiling});

        sp::pattern_options po;
        po.size_mm = size, po.resolution = resolution, po.levels = levels, po.thickness_mm = thickness, po.min_feature_mm = min_feature;
        po.smoothing = smoothing, po.preview_size = preview_size, po.max_memory_bytes = max_memory_gib * double(1ull << 30);
        po.synthesis = {.mm_per_px = scale, .candidates = candidates, .jitter = jitter, .up = up_dir, .passes = passes, .seed = seed};
        po.structure = !no_structure, po.max_iterations = max_iterations, po.stages = stages, po.validate = validate;
        po.structural.target_samples = samples, po.structural.seed = seed, po.structural.material = material, po.structural.safety_factor = safety_factor;
        po.structural.design_load_n = design_load, po.structural.load_factor = load_factor, po.structural.gravity = gravity_dir, po.structural.geodesic_factor = geodesic;
        po.structural.bridge_radius_mm = bridge_radius, po.structural.bridge_band = bridge_band;
        if (!support_plane.empty())
            po.structural.fixed = sp::plane_support({support_plane[0], support_plane[1], support_plane[2]},
                                                    {support_plane[3], support_plane[4], support_plane[5]}, support_band < 0 ? h : support_band);
        if (!loads_path.empty()) po.structural.loads = read_loads(loads_path);
        const sp::pattern_result res = sp::make_pattern(mesh, std::move(ex), po, [&](double f, std::string_view stage) { return progress(0.9 * f, stage); });  // writing is the last 10%

        // everything is computed: write the set
        progress(0.9, "write");
        const auto t = std::chrono::steady_clock::now();
        const grid_geometry& g = res.grid;
        {
            std::vector<double> st(static_cast<std::size_t>(g.count()), 0.0);
            for (std::size_t v = 0; v < res.shell_voxels.size(); ++v) st[static_cast<std::size_t>(g.index(res.shell_voxels[v]))] = res.state[v];
            io::write_vtk(shell_file, byte_grid(g, "state", std::move(st)));
        }
        // `stress`: the validation of `vs` (Fig. 16's fields), or none
        auto write_solid = [&](const fs::path& path, const sp::voxel_set& vs, const sp::stage_validation* stress) {
            std::vector<double> sv(static_cast<std::size_t>(g.count()), 0.0);
            for (const ivec3& p : vs.voxels) sv[static_cast<std::size_t>(g.index(p))] = 1.0;
            io::structured_points grid = byte_grid(g, "solid", std::move(sv));
            if (stress)
                for (const auto& [name, score] : {std::pair{"stress_expected_pa", &stress->expected_pa}, std::pair{"stress_unexpected_pa", &stress->unexpected_pa}}) {
                    std::vector<double> f(static_cast<std::size_t>(g.count()), 0.0);
                    for (std::size_t i = 0; i < vs.voxels.size(); ++i) f[static_cast<std::size_t>(g.index(vs.voxels[i]))] = std::isnan((*score)[i]) ? -1.0 : (*score)[i];
                    grid.fields.push_back({name, 1, std::move(f), io::vtk_type::float32});
                }
            io::write_vtk(path, grid);
        };
        write_solid(solid_file, res.thickened, res.validation.empty() ? nullptr : &res.validation.back());
        auto validation_of = [&](std::string_view stage) -> const sp::stage_validation* {
            for (const sp::stage_validation& v : res.validation)
                if (v.name == stage) return &v;
            return nullptr;
        };
        if (res.stage_connected) write_solid(connected_file, *res.stage_connected, validation_of("connected"));
        if (res.stage_forces) write_solid(forces_file, *res.stage_forces, validation_of("forces"));
        simplify.default_tolerance(0.5 * res.voxel_mm);
        const triangle_mesh pattern = simplify(res.mesh, common, "pattern.stl");
        io::write_mesh(stl_file, pattern);
#if defined(FABSYNTH_HAS_LIB3MF)
        // the same mesh, in millimetres, each triangle in the exemplar's (or the reinforcement's) colour
        io::write_3mf(threemf_file, pattern, {.name = "pattern", .face_colours = simplify.face_colours(pattern, res.vertex_colours)});
#endif
        io::write_png(preview_file, res.preview);
        const double t_write = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();

        nlohmann::ordered_json levels_json = nlohmann::ordered_json::array();
        for (const sp::level_report& l : res.levels)
            levels_json.push_back({{"level", l.level}, {"voxels", l.voxels}, {"spacing_mm", l.spacing_mm}, {"sigma_px", l.sigma_px},
                                   {"energy_initial", l.energy_initial}, {"energy_passes", l.energy_passes}, {"candidates", l.candidates},
                                   {"candidates_per_second", l.seconds > 0 ? static_cast<double>(l.candidates) / l.seconds : 0.0},
                                   {"seconds", l.seconds}});
        std::size_t solves = 0;
        for (const auto& it : res.structure.iterations) solves += static_cast<std::size_t>(it.solves);
        const double total = res.seconds.total + t_write;
        nlohmann::ordered_json rep = {
            {"mesh", mesh_path},
            {"exemplar", mask_path},
            {"color", colour_path},
            {"mesh_closed", res.mesh_closed},
            {"size_mm", size},
            {"grid", {g.dims.x, g.dims.y, g.dims.z}},
            {"voxel_mm", res.voxel_mm},
            {"exemplar_mm_per_px", res.mm_per_px},
            {"r_pattern_mm", feature * res.mm_per_px},
            {"bridge_radius_mm", res.bridge_radius_mm},
            {"thickness_mm", thickness},
            {"min_feature_mm", res.min_feature_mm},
            {"structure", !no_structure},
            {"shell_voxels", res.shell_voxels.size()},
            {"levels", levels_json},
            {"passes_per_level", passes},
            {"solid_fraction", res.solid_fraction},
            {"solid_fraction_synthesized", res.solid_fraction_synthesized},
            {"exemplar_solid_fraction", res.exemplar_solid_fraction},
            {"synthesized_voxels", res.synthesized_voxels},
            {"final_voxels", res.final_voxels},
            {"reinforcement_voxels", res.reinforcement_voxels},
            {"thin_feature_voxels_state4", res.thin_feature_voxels},
            {"reinforcement_ratio", res.reinforcement_ratio()},
            {"specks_removed", res.specks.removed_components},
            {"speck_voxels_removed", res.specks.removed_voxels},
        };
        if (!no_structure) {
            rep["material"] = material.name;
            rep["gravity"] = gravity;
            rep["design_load_n"] = design_load;
            if (!support_plane.empty()) rep["support_plane"] = {{"point_normal", support_plane}, {"band_mm", support_band < 0 ? h : support_band}};
            if (!loads_path.empty()) {
                nlohmann::ordered_json ls = nlohmann::ordered_json::array();
                for (const sp::area_load& L : po.structural.loads)
                    ls.push_back({{"at_mm", {L.at.x, L.at.y, L.at.z}}, {"force_n", {L.force_n.x, L.force_n.y, L.force_n.z}}, {"radius_mm", L.radius_mm}});
                rep["loads"] = ls;
            }
            rep["load_factor"] = load_factor;
            rep["safety_factor"] = safety_factor;
            rep["allowable_stress_mpa"] = po.structural.allowable_stress_mpa();
            rep["geodesic_factor"] = geodesic;
            rep["structural"] = structure_json(res.structure);
            rep["overloaded"] = res.structure.overloaded;
            rep["solves"] = solves;
            rep["thin_feature_voxels"] = res.thin_features.added_voxels;
        }
        rep["solid_voxels"] = res.thickened.voxels.size();
        rep["components_26"] = res.components_26;
        rep["pattern_faces"] = pattern.num_faces();
        rep["meshes"] = simplify.report();
        rep["pattern_watertight"] = res.watertight;
        if (validate) {
            nlohmann::ordered_json validation = nlohmann::ordered_json::object();
            for (const sp::stage_validation& sv : res.validation)
                validation[sv.name] = {{"expected", stats_json(sv.expected)}, {"unexpected", stats_json(sv.unexpected)}};
            rep["validation"] = validation;
        }
        const sp::pattern_timings& ts = res.seconds;
        rep["timings"] = {{"voxelize", ts.voxelize}, {"synthesis", ts.synthesis}, {"structural_analysis", ts.structural_analysis},
                          {"resynthesis", ts.resynthesis}, {"fabrication", ts.fabrication}, {"validation", ts.validation},
                          {"preview", ts.preview}, {"write", t_write}, {"total", total}};
        rep["seed"] = seed;
        io::atomic_write(report_file, rep.dump(2) + "\n");
        files.commit();
        progress(1.0, "write");

        char line[640];
        std::snprintf(line, sizeof line,
                      "%s: %zu shell voxels, %zu levels, solid fraction %.3f (exemplar %.3f), reinforcement %.2f x the synthesized solid, %zu structural iterations (%s), %zu solves, "
                      "%zu solid voxels in %zu 26-components, pattern.stl %zu faces %s; synthesis %.2f s, structure %.2f s, total %.2f s",
                      fs::path(mesh_path).filename().string().c_str(), res.shell_voxels.size(), res.pyramid_levels, res.solid_fraction,
                      res.exemplar_solid_fraction, res.reinforcement_ratio(), res.structure.iterations.size(), no_structure ? "off" : res.structure.converged ? "converged" : "bound hit",
                      solves, res.thickened.voxels.size(), res.components_26, pattern.num_faces(), res.watertight ? "watertight" : "NOT watertight",
                      ts.synthesis, ts.structural_analysis, total);
        common.say(line);
        if (!no_structure && res.structure.overloaded) {
            const sp::structural_step_report& last = res.structure.iterations.back();
            common.warn("the pattern is connected but its beam model still has solid edges at " + std::to_string(last.max_stress_after_mpa) +
                        " MPa, above the allowable " + std::to_string(last.allowable_stress_mpa) + " MPa (" +
                        (last.force_bound_hit ? "the force phase hit its bound of solves" : "no empty edge was left to insert") +
                        "); report.json: overloaded");
        }
        if (!res.validation.empty() && (res.validation.back().expected.unsupported_pieces > 0)) {
            const sp::stress_statistics& s = res.validation.back().expected;
            common.warn(std::to_string(s.unsupported_pieces) + " piece(s) of the printed solid (" + std::to_string(s.unsupported_voxels) +
                        " voxels) touch no support: the validation cannot load them and leaves them out of its statistics (report.json: "
                        "validation unsupported_pieces; -1 in solid.vtk's stress fields)");
        }
        nlohmann::ordered_json outs = nlohmann::ordered_json::array();
        for (const fs::path& o : outputs) outs.push_back(o.string());
        common.summary({{"shell_voxels", res.shell_voxels.size()},
                        {"levels", res.pyramid_levels},
                        {"solid_fraction", res.solid_fraction},
                        {"exemplar_solid_fraction", res.exemplar_solid_fraction},
                        {"reinforcement_ratio", res.reinforcement_ratio()},
                        {"structural_iterations", res.structure.iterations.size()},
                        {"converged", no_structure || res.structure.converged},
                        {"components_26", res.components_26},
                        {"pattern_faces", pattern.num_faces()},
                        {"watertight", res.watertight},
                        {"outputs", outs},
                        {"seconds", total}});
    });
}
