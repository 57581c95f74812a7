// SPDX-License-Identifier: MIT
#pragma once
/// @file synthesis.hpp  Pattern synthesis on a base surface (filigree-synthesis.md §3.5,
/// §4, §8.1): initialization on the surface, then part 1's rounds of placement and boosting
/// (synthesis.hpp's optimize_layout) through the surface pattern space (surface_space.hpp), and
/// each instance's skeleton mapped onto the surface through its own local parameterization, so
/// elements bend with the surface.
///
/// Usage:
///   auto r = fabsynth::filigree::synthesize_on_surface(classes, weights, region, field, opt);
///   r.instances;   // class, scale, shape, reference point on the surface
///   r.skeletons;   // per instance: vertices as surface points, edges, widths (mm)
///
/// The skeleton of an instance is its picture's placed skeleton located on the surface; an edge
/// is kept when both its ends lie on the map and in the region (an element reaching past an open
/// border or the region is cut there, as the 2D path clips strips to the domain). The topology
/// cut then runs on these skeletons in their own maps (surface_topology_cut.hpp).
#include <array>
#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include "fabsynth/core/progress.hpp"
#include "fabsynth/filigree/surface/space.hpp"
#include "fabsynth/filigree/surface/topology_cut.hpp"
#include "fabsynth/filigree/synthesis.hpp"

namespace fabsynth::filigree {

struct surface_synthesis_result {
    std::vector<surface_instance> initial, placed_once, instances;
    std::vector<surface_skeleton> skeletons;
    std::vector<double> energy_per_round;  ///< PME / #instances: [0] after initialization, then per round
    double energy_initial = 0, energy_after_placement = 0, energy_final = 0;
    int rounds = 0;
    std::size_t duplicates_removed = 0, smooth_connections = 0, boosted = 0, reconnected = 0, database_size = 0;
    std::vector<round_record> per_round;  ///< what each round of placement and boosting did (synthesis.hpp)
    surface_cut_report cut{};        ///< the topology cut (when synthesis_options::topology_cut)
    std::size_t maps_built = 0;      ///< local parameterizations built
    double map_seconds = 0;          ///< time in them, summed over threads
    synthesis_timings seconds;
};

/// Instance i's skeleton on the surface (see the file comment).
[[nodiscard]] inline surface_skeleton skeleton_on_surface(const surface_space& s, std::size_t i) {
    const auto v = s.view(i);
    const element& e = s.classes()[s.instance_at(i).cls];
    surface_skeleton out;
    out.widths = e.widths;
    out.picture = v.state().geometry()[v.index()].vertices;
    std::vector<bool> on(out.picture.size(), false);
    for (std::size_t k = 0; k < out.picture.size(); ++k) {
        const auto at = v.patch().locate(out.picture[k]);
        on[k] = at && s.region().contains(at->face);
        out.vertices.push_back(at ? *at : surface_point{UINT32_MAX, {0, 0, 0}});
    }
    for (const skeleton_edge& ed : e.edges)
        if (on[ed[0]] && on[ed[1]]) out.edges.push_back(ed);
    return out;
}

/// The skeletons of all instances of s on the surface, cut by the topology cut (§4.5,
/// surface_topology_cut.hpp) when `cut` is given (its report is stored there).
[[nodiscard]] inline std::vector<surface_skeleton> surface_skeletons(const surface_space& s, surface_cut_report* cut) {
    std::vector<surface_skeleton> sk(s.size());
    parallel_for(0, s.size(), [&](std::size_t i) { sk[i] = skeleton_on_surface(s, i); });
    if (cut) *cut = topology_cut_on_surface(s, sk, topology_cut_options{});  // thresholds from the strip widths
    return sk;
}

/// Initialization on the surface plus optimize_layout, then the skeletons on the surface and, with
/// opt.topology_cut, their topology cut.
[[nodiscard]] inline surface_synthesis_result synthesize_on_surface(std::span<const element> classes, std::span<const double> weights,
                                                                    const surface_region& region, const surface_control& field,
                                                                    const synthesis_options& opt = {}, const progress_span& progress = {}) {
    namespace ds = detail::synthesis;
    surface_synthesis_result r;
    auto t = ds::clock::now();
    initialization_options io = opt.init;
    io.seed = opt.seed;
    const surface_initialization_result init = initialize_on_surface(classes, weights, region, field, io);
    r.initial = init.instances;
    r.seconds.initialization = ds::since(t);
    surface_space s(classes, r.initial, field, region, opt.gamma_boundary);
    progress(0.05, "placement");
    optimize_layout(s, opt, r, progress.part(0.05, 0.95));
    progress(0.95, "topology cut");
    r.instances = s.instances();
    t = ds::clock::now();
    r.skeletons = surface_skeletons(s, opt.topology_cut ? &r.cut : nullptr);
    if (opt.topology_cut) r.seconds.topology_cut = ds::since(t);
    r.maps_built = init.maps_built + s.maps_built();
    r.map_seconds = init.map_seconds + s.map_seconds();
    return r;
}

}  // namespace fabsynth::filigree
