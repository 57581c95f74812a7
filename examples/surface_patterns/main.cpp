// surface_patterns MESH --exemplar MASK.png [--color COLOR.png] --size MM --thickness MM --feature PX
//                  [--resolution N] [--scale MM_PER_PX] [--up X Y Z] [--jitter F] [--seed S]
//                  [--gravity X Y Z] [--material abs|pla] [--samples N] [--geodesic F]
//                  [--design-load N] [--max-iterations K] [--stages] [--validate] [--no-structure]
//                  -o OUTDIR
//
// By-example synthesis of a structurally sound pattern in the voxel shell of a mesh
// (structurally-sound-patterns.md, Algorithm 1): synthesis (§4), then structural steps (§5:
// abstract graph, beam FEM, reinforcement bridges) alternating with constrained resynthesis until
// the pattern is one piece that carries the force profile, thin features enlarged (§6.2.1),
// thickened inward and meshed. Writes
//   OUTDIR/pattern.stl   watertight, smoothed mesh of the thickened solid voxels
//   OUTDIR/shell.vtk     CELL_DATA `state` (unsigned char): 0 not in the shell, 1 shell voxel carved
//                        empty, 2 solid from the exemplar, 3 reinforcement (made solid by a bridge
//                        of §5.2 where the pattern was empty), 4 thin feature enlarged (§6.2.1)
//   OUTDIR/solid.vtk     CELL_DATA `solid` 0/1 on the same grid: the thickened voxels
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
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/detail/atomic_file.hpp>
#include <fabsynth/io/vtk.hpp>
#include <fabsynth/surface_pattern.hpp>

#include <chrono>
#include <cmath>
#include <optional>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "output_set.hpp"
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
/// voxels), lifted to [60, 255] so that shading still shows on near-black colours; reinforcement
/// (state 3) and enlarged thin-feature (state 4) voxels in blue and green instead.
std::vector<std::array<std::uint8_t, 3>> vertex_colours(const triangle_mesh& m, const sp::synthesizer& syn, const sp::synthesis_result& r,
                                                        int reach, const std::vector<std::uint8_t>& state, bool exemplar_colours) {
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
                const std::uint8_t st = state[static_cast<std::size_t>(bv)];
                if (st == 3) return void(out[i] = {70, 110, 235});  // reinforcement
                if (st == 4) return void(out[i] = {80, 190, 90});   // enlarged thin feature
                if (!exemplar_colours) return;
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

/// The printable solid of shell states: thickened inward, edge/corner contacts joined so the mesh
/// has as many pieces as the voxels have 26-components.
sp::voxel_set printable_voxels(const sp::shell_level& l0, const std::vector<std::uint8_t>& solid, double thickness) {
    sp::voxel_set thick = sp::thicken_inward(l0.geometry, l0.voxels, l0.normals, solid, thickness);
    if (sp::set_components(thick, sp::mesh_connectivity{}).count != sp::set_components(thick).count) (void)sp::join_diagonal_contacts(thick);
    return thick;
}

nlohmann::ordered_json stats_json(const sp::stress_statistics& s) {
    return {{"average_pa", s.average}, {"median_pa", s.median}, {"p99_pa", s.p99}, {"max_pa", s.max}, {"elements", s.elements},
            {"fixed_elements", s.fixed_elements}, {"unsupported_voxels", s.unsupported_voxels}, {"cg_iterations", s.iterations},
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
            {"allowable_stress_mpa", it.allowable_stress_mpa}, {"force_bound_hit", it.force_bound_hit},
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
    double geodesic = 1.5, design_load = 10;
    int resolution = 256, levels = 0, passes = 2, candidates = 128, smoothing = 20, max_iterations = 30;
    std::size_t samples = 1000;
    std::vector<double> up{0, 0, 1}, gravity{0, 0, -1};
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
    app.add_option("--smoothing", smoothing, "Taubin smoothing iterations of pattern.stl")->check(CLI::Range(0, 200));
    app.add_flag("--no-tiling", no_tiling, "the exemplar does not tile: penalise lookups near its border (§6.1)");
    app.add_option("--gravity", gravity, "force profile: gravity direction; the lowest 10% along it are the supports")->expected(3);
    app.add_option("--material", material_name, "printing material: abs or pla (elastic constants, tensile strength)");
    app.add_option("--samples", samples, "abstract graph vertices (paper: 1000)")->check(CLI::Range(2, 100000));
    app.add_option("--geodesic", geodesic, "geodesic criterion: reinforce empty edges whose endpoints are farther apart in the pattern than F x the object's extent (0 = off)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--design-load", design_load, "total force of the force profile (N), spread over the abstract vertices")->check(CLI::NonNegativeNumber);
    app.add_option("--max-iterations", max_iterations, "bound on structural iterations (paper: 3-24)")->check(CLI::Range(1, 1000));
    app.add_flag("--stages", stages, "also write solid_connected.vtk and solid_forces.vtk (Table 3 stages)");
    app.add_flag("--validate", validate, "full-resolution voxel FEM of the result (and of the stages): stress statistics in report.json");
    app.add_flag("--no-structure", no_structure, "appearance only, no structural optimization");
    tool::add_memory_limit(app, max_memory_gib);
    app.add_option("-o,--output", out_dir, "output directory")->required();

    return tool::run(app, common, argc, argv, [&] {
        auto progress = common.progress();
        const auto t_start = clock_type::now();
        const fs::path out(out_dir);
        const fs::path stl = out / "pattern.stl", shell_vtk = out / "shell.vtk", solid_vtk = out / "solid.vtk", preview = out / "preview.png",
                       report = out / "report.json", connected_vtk = out / "solid_connected.vtk", forces_vtk = out / "solid_forces.vtk";
        std::vector<fs::path> outputs{stl, shell_vtk, solid_vtk, preview, report};
        if (stages) outputs.push_back(connected_vtk), outputs.push_back(forces_vtk);
        tool::check_outputs({mesh_path, mask_path, colour_path}, outputs);
        if (no_structure && (stages || validate)) throw invalid_input("--stages and --validate need the structural optimizer: drop --no-structure");
        if (!(std::isfinite(feature) && feature > 0)) throw invalid_input("--feature must be a finite number of pixels > 0, got " + std::to_string(feature));
        const double h = size / resolution;
        if (thickness < h) {
            char msg[200];
            std::snprintf(msg, sizeof msg, "--thickness %.4g mm is below one voxel (%.4g mm at --size %.4g --resolution %d)", thickness, h, size, resolution);
            throw invalid_input(msg);
        }
        if (min_feature < 0) min_feature = thickness;
        const vec3 up_dir(up[0], up[1], up[2]), gravity_dir(gravity[0], gravity[1], gravity[2]);
        if (!(glm::length(gravity_dir) > 0) || !all_finite(gravity_dir)) throw invalid_input("--gravity must be a finite non-zero direction");
        const sp::print_material material = sp::print_material::named(material_name);
        if (validate) {
            // the voxel FEM needs ~0.7 KB per node of the analysed box (validation.hpp): refuse before working
            const double nodes = std::pow(static_cast<double>(resolution) + 1, 3);
            tool::require_memory(700.0 * nodes, max_memory_gib, "--validate at --resolution " + std::to_string(resolution) + " (voxel FEM)");
        }

        // Staged now (an unwritable OUTDIR is refused before the work), moved into OUTDIR together at
        // the end; report.json, which describes the set, goes last.
        tool::output_set files;
        const fs::path stl_file = files.add(stl), shell_file = files.add(shell_vtk), solid_file = files.add(solid_vtk),
                       preview_file = files.add(preview), connected_file = files.add(connected_vtk), forces_file = files.add(forces_vtk),
                       report_file = files.add_manifest(report);

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
        sp::synthesis_result result = syn.synthesize([&](double f, std::string_view stage) { progress(0.05 + (no_structure ? 0.6 : 0.3) * f, stage); });
        const double t_synthesis = since(t);
        const sp::shell_level& l0 = pyr.levels[0];
        std::size_t carved_solid = 0;
        for (auto v : result.solid) carved_solid += v;
        const sp::speck_report specks = sp::remove_specks(l0.geometry, l0.voxels, result.solid, min_feature);

        // structural optimization (Algorithm 1), optionally the Table 3 stages from the same synthesis
        std::vector<std::uint8_t> state(l0.size(), 1), forced(l0.size(), 0), added(l0.size(), 0), thin(l0.size(), 0);
        sp::structure_report structure;
        std::optional<sp::voxel_set> stage_connected, stage_forces;
        double t_structure = 0, t_resynthesis = 0;
        sp::thin_feature_report thin_rep;
        if (!no_structure) {
            const sp::surface_graph gs = sp::build_surface_graph(l0);
            sp::structure_options so;
            so.r_pattern_mm = feature * syn.options().mm_per_px;
            so.thickness_mm = thickness;
            so.target_samples = samples;
            so.seed = seed;
            so.material = material;
            so.design_load_n = design_load;
            so.gravity = gravity_dir;
            so.geodesic_factor = geodesic;
            auto finish = [&](sp::synthesis_result& r, std::vector<std::uint8_t>* added) {
                // §6.2.1 "Enlarging small features": within the shell, to the smallest printable radius
                return sp::enlarge_thin_features(gs.graph(), r.solid, 0.5 * min_feature, h, added);
            };
            if (stages) {
                const char* names[2] = {"stage: connected", "stage: forces"};
                for (int k = 0; k < 2; ++k) {
                    sp::synthesis_result r = result;
                    sp::structure_options o = so;
                    o.geodesic_factor = 0;
                    o.force_criterion = k == 1;
                    const sp::structure_report sr = sp::optimize_structure(syn, r, gs, o, max_iterations, nullptr,
                                                                          [&](double f, std::string_view st) { progress(0.35 + 0.1 * k + 0.1 * f, std::string(names[k]) + ", " + std::string(st)); });
                    (void)finish(r, nullptr);
                    (k == 0 ? stage_connected : stage_forces) = printable_voxels(l0, r.solid, thickness);
                }
            }
            structure = sp::optimize_structure(syn, result, gs, so, max_iterations, &forced,
                                               [&](double f, std::string_view st) { progress(0.55 + 0.15 * f, st); }, &added);
            thin_rep = finish(result, &thin);
            t_structure = structure.structure_seconds;
            t_resynthesis = structure.resynthesis_seconds;
        }
        for (std::size_t v = 0; v < l0.size(); ++v)
            state[v] = !result.solid[v] ? 1 : thin[v] ? 4 : added[v] ? 3 : 2;

        progress(0.7, "fabrication");
        t = clock_type::now();
        const sp::voxel_set thick = printable_voxels(l0, result.solid, thickness);
        const sp::voxel_set_components cc = sp::set_components(thick);
        const triangle_mesh pattern = sp::mesh_voxels(thick, smoothing);
        const mesh_topology_info topo = analyze_topology(pattern);
        const double t_fabrication = since(t);

        // validation (§6.3): expected (gravity) and unexpected (orthogonal) loads
        nlohmann::ordered_json validation = nullptr;
        double t_validation = 0;
        if (validate) {
            t = clock_type::now();
            sp::validation_options vo;
            vo.material = material.elastic;
            vo.density_kg_m3 = material.elastic.density * 1e12;  // t/mm^3 -> kg/m^3
            vo.gravity = gravity_dir;
            validation = nlohmann::ordered_json::object();
            auto run = [&](const char* name, const sp::voxel_set& vs, double at) {
                progress(at, std::string("validate ") + name);
                validation[name] = {{"expected", stats_json(sp::validate_stress(vs, vo))}, {"unexpected", stats_json(sp::validate_stress(vs, sp::unexpected(vo)))}};
            };
            if (stage_connected) run("connected", *stage_connected, 0.72);
            if (stage_forces) run("forces", *stage_forces, 0.76);
            run(geodesic > 0 ? "forces_geodesic" : "final", thick, 0.80);
            t_validation = since(t);
        }

        progress(0.85, "preview");
        t = clock_type::now();
        std::vector<std::array<std::uint8_t, 3>> colours;
        if (!colour_path.empty() || !no_structure)
            colours = vertex_colours(pattern, syn, result, static_cast<int>(std::ceil(thickness / h)) + 2, state, !colour_path.empty());
        const render_view view{.direction = glm::length(up_dir) > 0 && std::abs(up_dir.y) < 0.9 * glm::length(up_dir) ? vec3(0, 1, 0) : vec3(0, 0, -1),
                               .up = glm::length(up_dir) > 0 ? up_dir : vec3(0, 0, 1)};
        const image8 picture = pattern.empty() ? image8(1552, 768, 3, 255)
                                               : render_two_sides(pattern, view, {.width = 768, .height = 768}, colours);
        const double t_preview = since(t);

        // everything is computed: write the set
        progress(0.9, "write");
        t = clock_type::now();
        std::size_t shell_solid = 0;
        {
            std::vector<double> st(static_cast<std::size_t>(l0.geometry.count()), 0.0);
            for (std::size_t v = 0; v < l0.size(); ++v) {
                st[static_cast<std::size_t>(l0.geometry.index(l0.voxels[v]))] = state[v];
                shell_solid += result.solid[v];
            }
            io::write_vtk(shell_file, byte_grid(l0.geometry, "state", std::move(st)));
        }
        auto write_solid = [&](const fs::path& path, const sp::voxel_set& vs) {
            std::vector<double> sv(static_cast<std::size_t>(l0.geometry.count()), 0.0);
            for (const ivec3& p : vs.voxels) sv[static_cast<std::size_t>(l0.geometry.index(p))] = 1.0;
            io::write_vtk(path, byte_grid(l0.geometry, "solid", std::move(sv)));
        };
        write_solid(solid_file, thick);
        if (stage_connected) write_solid(connected_file, *stage_connected);
        if (stage_forces) write_solid(forces_file, *stage_forces);
        io::write_mesh(stl_file, pattern);
        io::write_png(preview_file, picture);
        const double t_write = since(t);

        nlohmann::ordered_json levels_json = nlohmann::ordered_json::array();
        for (const sp::level_report& l : result.levels)
            levels_json.push_back({{"level", l.level}, {"voxels", l.voxels}, {"spacing_mm", l.spacing_mm}, {"sigma_px", l.sigma_px},
                                   {"energy_initial", l.energy_initial}, {"energy_passes", l.energy_passes}, {"candidates", l.candidates},
                                   {"candidates_per_second", l.seconds > 0 ? static_cast<double>(l.candidates) / l.seconds : 0.0},
                                   {"seconds", l.seconds}});
        const double shell_fraction = static_cast<double>(shell_solid) / static_cast<double>(l0.size());
        std::size_t solves = 0;
        for (const auto& it : structure.iterations) solves += static_cast<std::size_t>(it.solves);
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
            {"r_pattern_mm", feature * syn.options().mm_per_px},
            {"thickness_mm", thickness},
            {"min_feature_mm", min_feature},
            {"structure", !no_structure},
            {"shell_voxels", l0.size()},
            {"levels", levels_json},
            {"passes_per_level", passes},
            {"solid_fraction", shell_fraction},
            {"solid_fraction_synthesized", static_cast<double>(carved_solid) / static_cast<double>(l0.size())},
            {"exemplar_solid_fraction", ex_fraction},
            {"specks_removed", specks.removed_components},
            {"speck_voxels_removed", specks.removed_voxels},
        };
        if (!no_structure) {
            rep["material"] = material.name;
            rep["gravity"] = gravity;
            rep["design_load_n"] = design_load;
            rep["allowable_stress_mpa"] = material.tensile_strength_mpa / sp::structure_options{}.safety_factor;
            rep["geodesic_factor"] = geodesic;
            rep["structural"] = structure_json(structure);
            rep["solves"] = solves;
            rep["thin_feature_voxels"] = thin_rep.added_voxels;
        }
        rep["solid_voxels"] = thick.voxels.size();
        rep["components_26"] = cc.count;
        rep["pattern_faces"] = pattern.num_faces();
        rep["pattern_watertight"] = topo.is_watertight();
        if (validate) rep["validation"] = validation;
        rep["timings"] = {{"voxelize", t_voxelize}, {"synthesis", t_synthesis}, {"structural_analysis", t_structure}, {"resynthesis", t_resynthesis},
                          {"fabrication", t_fabrication}, {"validation", t_validation}, {"preview", t_preview}, {"write", t_write}, {"total", total}};
        rep["seed"] = seed;
        io::detail::atomic_write(report_file, rep.dump(2) + "\n");
        files.commit();
        progress(1.0, "write");

        char line[640];
        std::snprintf(line, sizeof line,
                      "%s: %zu shell voxels, %zu levels, solid fraction %.3f (exemplar %.3f), %zu structural iterations (%s), %zu solves, "
                      "%zu solid voxels in %d 26-components, pattern.stl %zu faces %s; synthesis %.2f s, structure %.2f s, total %.2f s",
                      fs::path(mesh_path).filename().string().c_str(), l0.size(), pyr.levels.size(), shell_fraction, ex_fraction,
                      structure.iterations.size(), no_structure ? "off" : structure.converged ? "converged" : "bound hit", solves, thick.voxels.size(),
                      cc.count, pattern.num_faces(), topo.is_watertight() ? "watertight" : "NOT watertight", t_synthesis, t_structure, total);
        common.say(line);
        nlohmann::ordered_json outs = nlohmann::ordered_json::array();
        for (const fs::path& o : outputs) outs.push_back(o.string());
        common.summary({{"shell_voxels", l0.size()},
                        {"levels", pyr.levels.size()},
                        {"solid_fraction", shell_fraction},
                        {"exemplar_solid_fraction", ex_fraction},
                        {"structural_iterations", structure.iterations.size()},
                        {"converged", no_structure || structure.converged},
                        {"components_26", cc.count},
                        {"pattern_faces", pattern.num_faces()},
                        {"watertight", topo.is_watertight()},
                        {"outputs", outs},
                        {"seconds", total}});
    });
}
