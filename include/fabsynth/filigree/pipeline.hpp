// SPDX-License-Identifier: MIT
#pragma once
/// @file pipeline.hpp  The whole filigree pipeline in one call (filigree-synthesis.md, Fig. 2), in
/// a planar domain (part 1; on a base surface, part 2: filigree/surface/pipeline.hpp): synthesis
/// (synthesis.hpp), strips, one piece and the structural optimization of §5 (reinforcement.hpp),
/// the printable mesh and the previews, exactly as the `filigree` tool writes them. No file input or output: the caller reads the elements (e.g.
/// element_from_svg(io::read_svg(...))) and writes the results (io::write_stl, io::write_png).
///
/// Planar usage (every length in mm):
///   namespace fg = fabsynth::filigree;
///   std::vector<fg::element> classes{fg::element_from_svg(fabsynth::io::read_svg("spiral.svg"), {.size_mm = 20, .width_mm = 0.8})};
///   std::vector<double> weights{1.0};            // one proportion >= 0 per class (not all 0)
///   fg::filigree_options opt;                      // the paper's defaults (Table 1), the tool's defaults
///   opt.synthesis.seed = 7;                        // same seed -> same bytes
///   opt.reinforcement.enabled = false;             // strips only, no shell FEM (§5)
///   const fg::planar_filigree f = fg::make_filigree(classes, weights, fg::planar_domain::rectangle(90, 70),
///                                                   fg::constant_field{}, opt, [](double fraction, std::string_view stage) {
///                                                       return true;   // false cancels: fabsynth::cancelled is thrown
///                                                   });
///   f.outline();     // the printable piece, polygons with holes in the domain's frame (y down, mm)
///   f.mesh;          // watertight extrusion of f.reinforcement.thickness mm, y flipped (print = drawing)
///   f.preview;       // grey-level picture of the outline over f.view; f.steps: Fig. 8's four stages
///   f.stress_map;    // Fig. 10 (RGB); f.histogram: Fig. 21 (with the structural optimization)
///   f.instances_per_class;  f.seconds.total;
///
/// Parameters of both forms:
///   classes   element classes (element.hpp): skeletons in mm, already scaled; only read during the call.
///   weights   #classes proportions, finite and >= 0, not all 0 (§7.3 multi-class).
///   field     (planar) a control_field (field.hpp) over the domain: rotation (rad) and scale per point.
///   options   filigree_options: `synthesis` (synthesis.hpp: seed, sigma_d, sigma_f, max_rounds,
///             init.max_elements, ...) and `reinforcement` (reinforcement.hpp: enabled, material,
///             thickness mm, pressure Pa, ...); their seed: synthesis.seed (the re-syntheses of §5
///             derive theirs from it).
///   progress  cb(fraction in [0, 1], stage name), called between the named phases and inside the
///             long loops (every set of independent moves of placement and boosting, every FEM
///             analysis of §5, every thickening step); returning false cancels (fabsynth::cancelled)
///             at the next such call. Meshing and rendering take no callback: they run in seconds.
///
/// Errors: invalid_input for bad input (elements, weights, domain, region, up vector, options),
/// no_solution when an element cannot be placed, solver_error when the pattern comes out empty,
/// the FEM fails or the printable mesh is not watertight, cancelled from the callback.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/filigree/appearance.hpp"
#include "fabsynth/filigree/figures.hpp"
#include "fabsynth/filigree/reconstruct.hpp"
#include "fabsynth/filigree/reinforcement.hpp"
#include "fabsynth/filigree/synthesis.hpp"
#include "fabsynth/geometry/coverage_image.hpp"
#include "fabsynth/geometry/extrude.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"

namespace fabsynth::filigree {

/// Options of both forms. Defaults: the paper's (Table 1: sigma_d 0.15, sigma_f 0.05) and the
/// tool's (seed 1, 6 rounds, at most 5000 instances, ABS, 1.0 mm, 1 kPa, structure on).
struct filigree_options {
    synthesis_options synthesis;          ///< §4: seed, sigma_d, sigma_f, max_rounds, init.max_elements, ...
    reinforcement_options reinforcement;  ///< §5, §6: enabled, material, thickness (mm), pressure_pa, ...
    bool previews = true;                 ///< false: no preview pictures (planar_filigree::preview / steps, surface_filigree::preview stay empty)
};

/// Seconds spent per phase (wall clock).
struct filigree_timings {
    synthesis_timings synthesis;  ///< initialization, placement, boosting, topology cut
    double structure = 0;         ///< strips / baking, one piece and §5 (reinforcement_result::seconds)
    double mesh = 0;              ///< the printable mesh and its watertightness check
    double previews = 0;
    double total = 0;             ///< the whole call
};

/// What make_filigree produces in a planar domain.
struct planar_filigree {
    synthesis_result synthesis;          ///< the layout and its skeletons after the topology cut
    reinforcement_result reinforcement;  ///< the final layout, outline and thickness after §5
    triangle_mesh mesh;                  ///< printable_extrusion of the outline, mirrored in y, welded to float precision; watertight
    box2 view;                           ///< the domain's bounds framed by 2% (the SVG's and the previews' view box, mm)
    image8 preview;                      ///< grey levels, 1600 px along the view's longer side
    image8 steps;                        ///< Fig. 8: after initialization, the first placement, the rounds, the topology cut, side by side
    image8 stress_map;                   ///< Fig. 10: von Mises stress at the final thickness over the view (RGB; empty without analysis)
    image8 histogram;                    ///< Fig. 21: nodal stress before and after §5 (RGB; empty without analysis)
    std::vector<std::size_t> instances_per_class;  ///< of the final layout (reinforcement.instances), per class
    appearance_report appearance;        ///< crossings, overlap and free ends of the final skeletons inside the domain (appearance.hpp)
    filigree_timings seconds;
    /// The printable piece: polygons with holes (mm, the domain's frame).
    [[nodiscard]] const std::vector<polygon_with_holes>& outline() const noexcept { return reinforcement.outline; }
};

namespace detail::pipeline {

using clock = std::chrono::steady_clock;
[[nodiscard]] inline double since(clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); }

inline void check_weights(std::span<const element> classes, std::span<const double> weights) {
    if (classes.empty()) throw invalid_input("filigree: no element class");
    if (weights.size() != classes.size())
        throw invalid_input("filigree: " + std::to_string(weights.size()) + " weights for " + std::to_string(classes.size()) + " element classes");
}

// The strips of the instances' skeletons without the topology cut (one panel of the steps picture).
inline std::vector<polygon_with_holes> uncut_strips(std::span<const element> classes, const std::vector<instance>& in, const planar_domain& d) {
    const pattern_state s(classes, in, constant_field{}, d, 0.0);
    const auto sk = world_skeletons(s);
    return strip_outline(std::span<const graph::skeleton_graph<vec2>>(sk), d.region);
}

// Fig. 8: the strips after initialization, after the first placement, after the rounds and after
// the topology cut, side by side.
inline image8 steps_image(std::span<const element> classes, const synthesis_result& syn, const planar_domain& d, const box2& view) {
    const std::vector<std::vector<polygon_with_holes>> panels{
        uncut_strips(classes, syn.initial, d), uncut_strips(classes, syn.placed_once, d), uncut_strips(classes, syn.instances, d),
        strip_outline(std::span<const graph::skeleton_graph<vec2>>(syn.skeletons), d.region)};
    std::vector<image8> imgs;
    for (const auto& p : panels) imgs.push_back(preview_image(p, view, {.max_side = 700, .supersample = 3}));
    return side_by_side(imgs, 12, std::uint8_t{200}, false);
}

}  // namespace detail::pipeline

/// The planar pipeline (see the file comment): synthesize_pattern, reinforce, the printable
/// extrusion and the previews. `domain`: planar_domain (mm, y down as drawn); `field`: any
/// control_field (constant_field, image_field, any_field, ...).
template <control_field F, progress_callback P = no_progress>
[[nodiscard]] planar_filigree make_filigree(std::span<const element> classes, std::span<const double> weights, const planar_domain& domain, const F& field,
                                            const filigree_options& opt = {}, P&& progress = {}) {
    namespace dp = detail::pipeline;
    const auto t_start = dp::clock::now();
    dp::check_weights(classes, weights);
    planar_filigree r;

    detail::reinforce::check_thickness(opt.reinforcement);  // bad structure options fail before the synthesis
    if (opt.reinforcement.enabled) (void)detail::reinforce::planar_structure_options(opt.reinforcement, 1.0);
    report_progress(progress, 0.0, "synthesis");
    r.synthesis = synthesize_pattern(classes, weights, domain, field, opt.synthesis, progress_span(progress, 0.0, 0.6));
    r.seconds.synthesis = r.synthesis.seconds;

    report_progress(progress, 0.6, opt.reinforcement.enabled ? "strips and structure" : "strips");
    r.reinforcement = reinforce(classes, weights, domain, field, opt.synthesis, r.synthesis, opt.reinforcement, progress_span(progress, 0.6, 0.85));
    r.seconds.structure = r.reinforcement.seconds;
    if (r.reinforcement.outline.empty()) throw solver_error("the synthesized pattern is empty");

    report_progress(progress, 0.85, "mesh");
    auto t = dp::clock::now();
    r.mesh = printable_extrusion(r.reinforcement.outline, r.reinforcement.thickness);
    mirror_y(r.mesh);
    weld_to_float(r.mesh);
    require_watertight(r.mesh, "the extruded filigree, rounded to single precision,");
    r.seconds.mesh = dp::since(t);

    report_progress(progress, 0.9, "previews");
    t = dp::clock::now();
    r.view = framed_view(domain.bounds, 0.02);
    if (opt.previews) {
        r.preview = preview_image(r.reinforcement.outline, r.view, {.max_side = 1600, .supersample = 4});
        r.steps = dp::steps_image(classes, r.synthesis, domain, r.view);
        if (r.reinforcement.analysed) {
            r.stress_map = stress_map_image(r.reinforcement.fem, r.reinforcement.final_report, r.view);
            r.histogram = stress_histogram_plot(r.reinforcement);
        }
    }
    r.seconds.previews = dp::since(t);

    r.instances_per_class.assign(classes.size(), 0);
    for (const instance& in : r.reinforcement.instances) ++r.instances_per_class[in.cls];
    r.appearance = measure_appearance(std::span<const graph::skeleton_graph<vec2>>(r.reinforcement.skeletons),
                                      [&](vec2 p) { return domain.contains(p); });
    r.seconds.total = dp::since(t_start);
    report_progress(progress, 1.0, "done");
    return r;
}

}  // namespace fabsynth::filigree
