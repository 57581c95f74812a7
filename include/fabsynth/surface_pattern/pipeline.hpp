// SPDX-License-Identifier: MIT
#pragma once
/// @file pipeline.hpp  One call for the whole surface-pattern pipeline (structurally-sound-patterns.md,
/// Algorithm 1): `make_pattern(mesh, exemplar, options)`.
///
/// Named phases, in order (each reports progress and may be cancelled between and inside them):
///  1. shell      the mesh scaled to size_mm, its conservative surface voxels and pyramid (§3);
///  2. synthesis  SYNTHESIZE (§4.3), then specks below min_feature_mm removed (fabricate.hpp);
///  3. stages     (options.stages) the loop run with the connectivity criterion only, and with the
///                force profile but no geodesic criterion, from the same synthesis (Table 3 rows 1-2);
///  4. structure  STRUCTURALOPTIM alternating with RESYNTHESIZE until done (§5, structural.hpp), then
///                thin features enlarged to min_feature_mm / 2 (§6.2.1, thin_features.hpp);
///  5. fabrication  thickened inward by thickness_mm, edge/corner contacts joined so the mesh has as
///                many pieces as the voxels have 26-components, meshed watertight (fabricate.hpp);
///  6. validation (options.validate) the full-resolution voxel FEM of §6.3 on every solid, under
///                gravity and under the orthogonal unexpected load (validation.hpp);
///  7. preview    a shaded render of the mesh from two sides, in the exemplar's colours when it has
///                them, reinforcements blue and enlarged thin features green.
/// No file is read or written. `examples/surface_patterns` is this call plus argument parsing and
/// the output files.
///
/// Usage (a complete program: README.md, "Surface patterns"):
///   namespace sp = fabsynth::surface_pattern;
///   const fabsynth::triangle_mesh bunny = fabsynth::io::read_mesh("data/meshes/bunny.obj");
///   const fabsynth::image8 mask = fabsynth::io::read_png("data/exemplars/hooks.png");
///   sp::pattern_options o;
///   o.size_mm = 100;                            // longest side of the object
///   o.thickness_mm = 1.2;                       // shell thickness
///   o.synthesis.up = {0, 1, 0};                 // the pattern's up on the surface
///   o.structural.gravity = {0, -1, 0};          // force profile and supports
///   sp::pattern_result r = sp::make_pattern(bunny, sp::make_exemplar(mask, nullptr, {.feature_px = 4}), o);
///   fabsynth::io::write_mesh("pattern.stl", r.mesh);      // watertight, r.components_26 pieces
///   fabsynth::io::write_png("preview.png", r.preview);
///
/// Cancelling: a progress callback that returns false makes the call throw fabsynth::cancelled at
/// its next report: between phases, between the 27 sub-pass classes of every synthesis pass, between
/// the FEM solves of a structural step and per level of a resynthesis.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/render.hpp"
#include "fabsynth/surface_pattern/abstract_graph.hpp"
#include "fabsynth/surface_pattern/exemplar.hpp"
#include "fabsynth/surface_pattern/fabricate.hpp"
#include "fabsynth/surface_pattern/shell.hpp"
#include "fabsynth/surface_pattern/structural.hpp"
#include "fabsynth/surface_pattern/synthesis.hpp"
#include "fabsynth/surface_pattern/thin_features.hpp"
#include "fabsynth/surface_pattern/validation.hpp"

namespace fabsynth::surface_pattern {

/// Everything make_pattern needs besides the mesh and the exemplar. Defaults are the paper's
/// settings (§6: 256^3, 8 levels, 128 candidates, 1000 abstract vertices, ABS).
struct pattern_options {
    double size_mm = 0;          ///< longest side of the scaled mesh [mm], > 0 (required)
    int resolution = 256;        ///< voxels along that side (paper: 256; 512 for large models), 16..4096
    int levels = 0;              ///< pyramid levels; 0 = default_levels(resolution) (8 at 256, 9 at 512)
    double thickness_mm = 0;     ///< shell thickness, inward along the normals [mm], >= one voxel (required)
    double min_feature_mm = -1;  ///< smallest printable feature [mm]: smaller solid pieces are removed, thinner
                                 ///< features enlarged to half of it; < 0 = thickness_mm
    int smoothing = 50;          ///< Taubin smoothing iterations of the mesh, 0..200, each vertex held on its grid edge within half a voxel (mesh_voxels)
    /// Synthesis (§4): scale mm_per_px (0 = one finest voxel per exemplar pixel), candidates, jitter,
    /// passes, the up direction (0 vector = free rotations), seed.
    synthesis_options synthesis{};
    bool structure = true;       ///< false: appearance only, no structural loop (no stages, no validation)
    /// The structural loop (§5): material, gravity, design load, samples, geodesic factor, seed.
    /// r_pattern_mm = 0 is the exemplar's feature radius at the synthesis scale
    /// (feature_px x mm_per_px); thickness_mm = 0 is this struct's thickness_mm; bridge_radius_mm
    /// = 0 is the narrowest bridge that prints: max(min_feature / 2, one voxel), the radius §6.2.1
    /// enlarges thin features to (at least one voxel, so a bridge is never a bare voxel path, which
    /// §5.2 rules out). Set it to r_pattern_mm for the paper's bridges.
    structure_options structural{};
    int max_iterations = 30;     ///< bound on structural iterations (paper: 3-24 needed), >= 1
    bool stages = false;         ///< also the Table 3 stages (connectivity only; with the force profile)
    bool validate = false;       ///< voxel FEM of every solid (§6.3); memory: validation_bytes
    bool preview = true;         ///< render the preview picture
    int preview_size = 768;      ///< pixels of one view of the preview (the picture is two views wide)
    double max_memory_bytes = 16.0 * (1ull << 30);  ///< refuse shells (and validate = true runs: validation_bytes) estimated to need more, before any work

    /// Throws invalid_input naming the first bad value (the structural options are checked by
    /// the loop itself, the synthesis options by the synthesizer).
    void validate_options() const {
        if (!(std::isfinite(size_mm) && size_mm > 0)) throw invalid_input("surface pattern: size must be finite and > 0 mm, got " + detail::num(size_mm));
        if (resolution < 16 || resolution > 4096) throw invalid_input("surface pattern: resolution must be in [16, 4096], got " + std::to_string(resolution));
        if (levels < 0 || levels > 16) throw invalid_input("surface pattern: levels must be in [0, 16], got " + std::to_string(levels));
        const double h = size_mm / resolution;
        if (!(std::isfinite(thickness_mm) && thickness_mm >= h))
            throw invalid_input("surface pattern: thickness " + detail::num(thickness_mm) + " mm is below one voxel (" + detail::num(h) + " mm at size " +
                                detail::num(size_mm) + " mm, resolution " + std::to_string(resolution) + ")");
        if (!std::isfinite(min_feature_mm)) throw invalid_input("surface pattern: min_feature must be finite");
        if (smoothing < 0 || smoothing > 200) throw invalid_input("surface pattern: smoothing must be in [0, 200]");
        if (max_iterations < 1) throw invalid_input("surface pattern: max_iterations must be >= 1");
        if (!structure && (stages || validate)) throw invalid_input("surface pattern: stages and validation need the structural loop (structure = true)");
        if (validate && !(validation_bytes(resolution) <= max_memory_bytes))
            throw invalid_input("surface pattern: validation at resolution " + std::to_string(resolution) + " needs about " +
                                detail::num(validation_bytes(resolution) / double(1ull << 30)) + " GiB, above the limit of " +
                                detail::num(max_memory_bytes / double(1ull << 30)) + " GiB (max_memory_bytes)");
        if (preview && (preview_size < 1 || preview_size > 8192)) throw invalid_input("surface pattern: preview size must be in [1, 8192] pixels");
    }
};

/// Shell-voxel states of pattern_result::state.
enum class voxel_state : std::uint8_t {
    outside = 0,        ///< not a shell voxel (only in grids written from the state list)
    empty = 1,          ///< carved empty
    exemplar = 2,       ///< solid from the exemplar
    reinforcement = 3,  ///< made solid by a bridge of §5.2 where the pattern was empty
    thin_feature = 4,   ///< made solid when a thin feature was enlarged (§6.2.1)
};

/// The validation (§6.3) of one solid: Table 3's statistics under both loads.
struct stage_validation {
    std::string name;  ///< "connected", "forces", then "forces_geodesic" (or "final" without the geodesic criterion)
    stress_statistics expected;    ///< under gravity
    stress_statistics unexpected;  ///< under the orthogonal load (validation.hpp unexpected())
    /// |s1| + |s2| + |s3| [Pa] per voxel of the stage's solid (its voxel order) under each load, the
    /// paper's Fig. 16: 0 in the support zone, NaN in a piece without support (validation.hpp).
    std::vector<double> expected_pa, unexpected_pa;
};

/// Wall time of each phase [s] (Table 2's split: structural analysis and resynthesis apart).
struct pattern_timings {
    double voxelize = 0, synthesis = 0, structural_analysis = 0, resynthesis = 0, fabrication = 0, validation = 0, preview = 0, total = 0;
};

/// What make_pattern returns: the printable mesh, the voxel data behind it and the report figures.
struct pattern_result {
    triangle_mesh mesh;                ///< watertight, smoothed mesh of `thickened` [mm]
    /// sRGB colour per vertex of `mesh`: the exemplar's colour there, detail::reinforcement_colour and
    /// detail::thin_feature_colour where the structure loop added or enlarged (detail::preview_colours);
    /// empty when the exemplar has no colour image and options.structure is off.
    std::vector<std::array<std::uint8_t, 3>> vertex_colours;
    image8 preview;                    ///< RGB, two views side by side (empty when options.preview is false)
    grid_geometry grid;                ///< the finest voxel grid [mm]
    std::vector<ivec3> shell_voxels;   ///< shell voxels of the finest level, sorted by grid index
    std::vector<std::uint8_t> state;   ///< per shell voxel: a voxel_state (1..4)
    voxel_set thickened;               ///< the printable voxels (the pattern thickened inward)
    std::optional<voxel_set> stage_connected, stage_forces;  ///< the Table 3 stages' printable voxels (options.stages)
    std::vector<stage_validation> validation;                ///< options.validate: the stages, then the final solid

    std::size_t pyramid_levels = 0;
    std::vector<level_report> levels;  ///< synthesis, one per level (index = level, 0 finest)
    bool mesh_closed = false;          ///< the input mesh is watertight
    double voxel_mm = 0;               ///< finest voxel size [mm]
    double mm_per_px = 0;              ///< the exemplar scale used [mm per pixel]
    double r_pattern_mm = 0;           ///< feature radius used by the structural loop [mm]
    double bridge_radius_mm = 0;       ///< dilation radius of its bridges [mm]
    double min_feature_mm = 0;         ///< the smallest printable feature used [mm]
    double exemplar_solid_fraction = 0;
    double solid_fraction_synthesized = 0;  ///< of the shell voxels, after SYNTHESIZE
    double solid_fraction = 0;              ///< of the shell voxels, at the end
    std::size_t synthesized_voxels = 0;     ///< solid shell voxels after SYNTHESIZE
    std::size_t final_voxels = 0;           ///< solid shell voxels at the end (states 2-4)
    std::size_t reinforcement_voxels = 0;   ///< state 3: laid by the bridges of §5.2
    std::size_t thin_feature_voxels = 0;    ///< state 4: laid by the enlargement of thin features (§6.2.1)
    /// What the structure added, (state 3 + state 4) / synthesized: the share of the print that is
    /// not the exemplar's (0 without any; the paper's Table 1 bunny with hooks: about 0.6).
    [[nodiscard]] double reinforcement_ratio() const noexcept {
        return synthesized_voxels ? static_cast<double>(reinforcement_voxels + thin_feature_voxels) / static_cast<double>(synthesized_voxels) : 0.0;
    }
    speck_report specks;
    structure_report structure;        ///< empty when options.structure is false
    thin_feature_report thin_features;
    std::size_t components_26 = 0;     ///< 26-components of `thickened`
    bool watertight = false;           ///< `mesh` is closed and manifold
    pattern_timings seconds;
};

namespace detail {

/// The printable solid of shell states: thickened inward, edge/corner contacts joined so the mesh
/// has as many pieces as the voxels have 26-components.
inline voxel_set printable_voxels(const shell_level& l0, const std::vector<std::uint8_t>& solid, double thickness) {
    voxel_set thick = thicken_inward(l0.geometry, l0.voxels, l0.normals, solid, thickness);
    if (set_components(thick, mesh_connectivity{}).count != set_components(thick).count) (void)join_diagonal_contacts(thick);
    return thick;
}

/// Colours of reinforcement and of enlarged thin features, in the preview and the 3MF.
inline constexpr std::array<std::uint8_t, 3> reinforcement_colour{70, 110, 235}, thin_feature_colour{80, 190, 90};

/// Colour of each mesh vertex: the exemplar colour through the label of the nearest solid shell
/// voxel, at that voxel's centre (searched in growing cubes around the vertex, up to `reach`
/// voxels); reinforcement and enlarged thin-feature voxels reinforcement_colour and
/// thin_feature_colour instead; {200, 200, 205} where no solid voxel is in reach.
inline std::vector<std::array<std::uint8_t, 3>> preview_colours(const triangle_mesh& m, const synthesizer& syn, const synthesis_result& r, int reach,
                                                                 const std::vector<std::uint8_t>& state, bool exemplar_colours) {
    const shell_level& lv = syn.pyramid().levels[0];
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
                const auto st = static_cast<voxel_state>(state[static_cast<std::size_t>(bv)]);
                if (st == voxel_state::reinforcement) return void(out[i] = reinforcement_colour);
                if (st == voxel_state::thin_feature) return void(out[i] = thin_feature_colour);
                if (!exemplar_colours) return;
                // the colour at the voxel centre (inside the solid), not at the vertex on its border
                const vec2 p = syn.labels().map(lv.center(static_cast<std::size_t>(bv)), r.labels[0][static_cast<std::size_t>(bv)]);
                out[i] = syn.source().colour_at(p.x, p.y);
                return;
            }
        }
    }, {.grain = 4096});
    return out;
}

}  // namespace detail

/// The whole pipeline on `mesh` (triangles in any unit; scaled so its longest side is
/// options.size_mm) with exemplar `ex` (make_exemplar: mask, optional colour, feature radius).
/// Progress fractions run 0..1 over the phases listed in the file comment; a callback returning
/// false throws fabsynth::cancelled. Throws invalid_input for bad options or inputs (an empty
/// mesh, a shell too large for max_memory_bytes), solver_error from the FEM solves.
template <progress_callback P = no_progress>
[[nodiscard]] pattern_result make_pattern(const triangle_mesh& mesh, exemplar ex, const pattern_options& opt, P&& progress = {}) {
    using clock = std::chrono::steady_clock;
    const auto since = [](clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); };
    opt.validate_options();
    const auto t_start = clock::now();
    pattern_result out;
    const double h = opt.size_mm / opt.resolution;
    out.min_feature_mm = opt.min_feature_mm < 0 ? opt.thickness_mm : opt.min_feature_mm;
    out.exemplar_solid_fraction = ex.solid_fraction();
    const bool exemplar_colours = ex.has_colour();

    // 1. shell
    report_progress(progress, 0.02, "voxelize");
    auto t = clock::now();
    const surface_shell shell = make_shell(mesh, {.size_mm = opt.size_mm, .resolution = opt.resolution, .max_memory_bytes = opt.max_memory_bytes});
    const shell_pyramid pyr = build_shell_pyramid(shell, opt.levels ? opt.levels : default_levels(opt.resolution));
    out.seconds.voxelize = since(t);
    out.mesh_closed = analyze_topology(shell.mesh).is_watertight();
    out.pyramid_levels = pyr.levels.size();
    const shell_level& l0 = pyr.levels[0];
    out.grid = l0.geometry;
    out.shell_voxels = l0.voxels;
    out.voxel_mm = h;

    // 2. synthesis
    t = clock::now();
    const synthesizer syn(pyr, std::move(ex), opt.synthesis);
    const double synthesis_share = opt.structure ? 0.3 : 0.6;
    synthesis_result result = syn.synthesize([&](double f, std::string_view stage) { report_progress(progress, 0.05 + synthesis_share * f, stage); });
    out.seconds.synthesis = since(t);
    out.levels = result.levels;
    out.mm_per_px = syn.options().mm_per_px;
    const auto count_solid = [&] { return static_cast<double>(std::count(result.solid.begin(), result.solid.end(), std::uint8_t{1})); };
    out.synthesized_voxels = static_cast<std::size_t>(count_solid());
    out.solid_fraction_synthesized = count_solid() / static_cast<double>(l0.size());
    out.specks = remove_specks(l0.geometry, l0.voxels, result.solid, out.min_feature_mm);

    // 3.-4. stages and the structural loop (Algorithm 1)
    std::vector<std::uint8_t> forced(l0.size(), 0), added(l0.size(), 0), thin(l0.size(), 0);
    if (opt.structure) {
        const surface_graph gs = build_surface_graph(l0);
        structure_options so = opt.structural;
        if (so.r_pattern_mm == 0) so.r_pattern_mm = syn.source().feature_px() * out.mm_per_px;
        if (so.thickness_mm == 0) so.thickness_mm = opt.thickness_mm;
        if (so.bridge_radius_mm == 0) so.bridge_radius_mm = std::max(0.5 * out.min_feature_mm, h);
        out.r_pattern_mm = so.r_pattern_mm;
        out.bridge_radius_mm = so.bridge_radius_mm;
        // §6.2.1 "Enlarging small features": within the shell, to the smallest printable radius
        // (bridges laid at least that wide are kept out of its skeleton: thin_features.hpp)
        const bool printable_bridges = so.bridge_radius() >= 0.5 * out.min_feature_mm;
        const auto finish = [&](synthesis_result& r, std::vector<std::uint8_t>* grown, const std::vector<std::uint8_t>* bridges) {
            return enlarge_thin_features(gs.graph(), r.solid, 0.5 * out.min_feature_mm, h, grown, printable_bridges ? bridges : nullptr);
        };
        if (opt.stages) {
            const char* names[2] = {"stage: connected", "stage: forces"};
            for (int k = 0; k < 2; ++k) {
                synthesis_result r = result;
                structure_options o = so;
                o.geodesic_factor = 0;
                o.force_criterion = k == 1;
                std::vector<std::uint8_t> stage_forced;
                (void)optimize_structure(syn, r, gs, o, opt.max_iterations, &stage_forced, [&](double f, std::string_view st) {
                    report_progress(progress, 0.35 + 0.1 * k + 0.1 * f, std::string(names[k]) + ", " + std::string(st));
                });
                (void)finish(r, nullptr, &stage_forced);
                (k == 0 ? out.stage_connected : out.stage_forces) = detail::printable_voxels(l0, r.solid, opt.thickness_mm);
            }
        }
        out.structure = optimize_structure(syn, result, gs, so, opt.max_iterations, &forced,
                                           [&](double f, std::string_view st) { report_progress(progress, 0.55 + 0.15 * f, st); }, &added);
        out.thin_features = finish(result, &thin, &forced);
        out.seconds.structural_analysis = out.structure.structure_seconds;
        out.seconds.resynthesis = out.structure.resynthesis_seconds;
    }
    out.state.resize(l0.size());
    for (std::size_t v = 0; v < l0.size(); ++v)
        out.state[v] = static_cast<std::uint8_t>(!result.solid[v] ? voxel_state::empty
                                                 : thin[v]       ? voxel_state::thin_feature
                                                 : added[v]      ? voxel_state::reinforcement
                                                                 : voxel_state::exemplar);
    out.solid_fraction = count_solid() / static_cast<double>(l0.size());
    out.final_voxels = static_cast<std::size_t>(count_solid());
    out.reinforcement_voxels = static_cast<std::size_t>(std::count(out.state.begin(), out.state.end(), static_cast<std::uint8_t>(voxel_state::reinforcement)));
    out.thin_feature_voxels = static_cast<std::size_t>(std::count(out.state.begin(), out.state.end(), static_cast<std::uint8_t>(voxel_state::thin_feature)));

    // 5. fabrication
    report_progress(progress, 0.7, "fabrication");
    t = clock::now();
    out.thickened = detail::printable_voxels(l0, result.solid, opt.thickness_mm);
    out.components_26 = static_cast<std::size_t>(set_components(out.thickened).count);
    out.mesh = mesh_voxels(out.thickened, opt.smoothing);
    out.watertight = analyze_topology(out.mesh).is_watertight();
    out.seconds.fabrication = since(t);

    // 6. validation (§6.3): expected (gravity) and unexpected (orthogonal) loads
    if (opt.validate) {
        t = clock::now();
        validation_options vo;
        vo.material = opt.structural.material.elastic;
        vo.density_kg_m3 = opt.structural.material.elastic.density * 1e12;  // t/mm^3 -> kg/m^3
        vo.gravity = opt.structural.gravity;
        vo.fixed = opt.structural.fixed;  // the user's supports, if any (the loads stay the paper's two weights)
        const auto run = [&](const char* name, const voxel_set& vs, double at) {
            const auto sub = [&](double f, std::string_view st) { report_progress(progress, at + 0.04 * f, std::string("validate ") + name + ", " + std::string(st)); };
            stress_field e = validate_stress_field(vs, vo, sub), u = validate_stress_field(vs, unexpected(vo), sub);
            out.validation.push_back({name, e.stats, u.stats, std::move(e.score), std::move(u.score)});
        };
        if (out.stage_connected) run("connected", *out.stage_connected, 0.72);
        if (out.stage_forces) run("forces", *out.stage_forces, 0.76);
        run(opt.structural.geodesic_factor > 0 ? "forces_geodesic" : "final", out.thickened, 0.80);
        out.seconds.validation = since(t);
    }

    // 7. colours and preview
    t = clock::now();
    if (exemplar_colours || opt.structure)
        out.vertex_colours = detail::preview_colours(out.mesh, syn, result, static_cast<int>(std::ceil(opt.thickness_mm / h)) + 2, out.state, exemplar_colours);
    if (opt.preview) {
        report_progress(progress, 0.85, "preview");
        // exemplar colours lifted to [60, 255] so that shading still shows on near-black ones
        std::vector<std::array<std::uint8_t, 3>> colours = out.vertex_colours;
        for (auto& c : colours)
            if (c != detail::reinforcement_colour && c != detail::thin_feature_colour)
                for (auto& k : c) k = static_cast<std::uint8_t>(60 + k * 195 / 255);
        const vec3 up = opt.synthesis.up;
        const render_view view{.direction = glm::length(up) > 0 && std::abs(up.y) < 0.9 * glm::length(up) ? vec3(0, 1, 0) : vec3(0, 0, -1),
                               .up = glm::length(up) > 0 ? up : vec3(0, 0, 1)};
        const int side = opt.preview_size;
        const render_options look{.width = side, .height = side};
        out.preview = out.mesh.empty() ? image8(2 * side + look.gap, side, 3, 255) : render_two_sides(out.mesh, view, look, colours);
    }
    out.seconds.preview = since(t);
    out.seconds.total = since(t_start);
    report_progress(progress, 1.0, "done");
    return out;
}

}  // namespace fabsynth::surface_pattern
