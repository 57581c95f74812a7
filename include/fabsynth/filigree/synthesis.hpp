// SPDX-License-Identifier: MIT
#pragma once
/// @file synthesis.hpp  Pattern synthesis, the first four steps of the pipeline
/// (filigree-synthesis.md §3.5, §4, Fig. 2): initialization, rounds of placement optimization
/// and boosting until the layout stops moving, removal of fully overlapped duplicates, then the
/// topology cut on the skeletons.
///
/// Usage:
///   fabsynth::filigree::synthesis_options opt;  opt.seed = 7;
///   auto r = fabsynth::filigree::synthesize_pattern(classes, weights, domain, field, opt);
///   r.skeletons;            // world skeleton graphs after the topology cut (mm)
///   r.energy_per_round;     // PME / instance count after each round (the paper's Fig. 22)
///
/// Stopping (§4.4 "Stopping Criteria"): a round is one placement optimization plus one boosting;
/// rounds stop when the summed translation of a round is below `converged_translation` times
/// (instance count x mean element size), or after `max_rounds`.
///
/// Strip widths are physical (mm): the control field scales an element's shape, not its strip
/// width, so the printed strips keep the width the user asked for.
#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/filigree/boosting.hpp"
#include "fabsynth/filigree/connection.hpp"
#include "fabsynth/filigree/domain.hpp"
#include "fabsynth/filigree/element.hpp"
#include "fabsynth/filigree/field.hpp"
#include "fabsynth/filigree/initialization.hpp"
#include "fabsynth/filigree/placement.hpp"
#include "fabsynth/filigree/topology_cut.hpp"
#include "fabsynth/graph/skeleton_graph.hpp"

namespace fabsynth::filigree {

struct synthesis_options {
    initialization_options init;
    placement_options placement;
    boosting_options boosting;
    double sigma_f = 0.05;               ///< Table 1: 4.5-5%
    double sigma_d = 0.15;               ///< Table 1: 0.13-0.17; distortion bound of smooth connections
    bool smooth_connection = true;       ///< §4.3.2
    int max_rounds = 6;
    double converged_translation = 0.01; ///< per instance, fraction of the mean element size
    double gamma_boundary = 1.0;         ///< weight of the boundary Theta term
    /// The crossing term of Theta (pattern_state::pair_energy): mm added to a connected pair's
    /// energy per transversal crossing of their skeletons at more than crossing_angle_deg. 0 = the
    /// paper's eq. 2 alone. Calibrated on the eight 2D cases of examples/filigree/main_job.sh
    /// (transversal crossings per instance of the result, appearance.hpp, mean over the cases;
    /// benchmarks/README.md): with the former 0.3 move limit and the same-class factor in
    /// single-class runs, 0 -> 1.80, 1 -> 1.12, 5 -> 0.92; with no move limit and the factor only
    /// in mixes, 5 -> 0.84 (all with the topology cut's former closeness of 4 strip widths; with
    /// 16, as now, 0.44).
    double crossing_penalty = 5.0;
    double crossing_angle_deg = 30.0;
    /// Most a move of placement or boosting may make an instance's covering region overlap one
    /// neighbour's, as a fraction of its own covering area (pattern_state::spacing_kept). 1 = no
    /// limit: moves may reach complete overlap and the duplicates are merged after each round, so
    /// the count converges from the initialization's (§3.5 "Discussion"). A limit of 0.3 (§4.1's
    /// rule 2, the default before) kept the stacks apart when eq. 2 was the only pair energy; with
    /// the crossing term it measured worse on the eight cases above (1.35 against 0.84 crossings
    /// per instance, and a larger overlap area in 6 of 8), so it is off by default.
    double move_overlap_limit = 1.0;
    bool topology_cut = true;
    std::uint64_t seed = 1;
};

/// What one round of placement and boosting did (the paper's Fig. 22 plots the PME per instance
/// over the rounds; the counts say which step moved what).
struct round_record {
    std::size_t instances = 0;         ///< after the round's merge of duplicates
    double pme_per_instance = 0;       ///< PME / instances after the round
    double translation_mm = 0;         ///< summed translation of placement and boosting
    std::size_t smooth_connections = 0, boosted = 0, reconnected = 0, duplicates_removed = 0;
};

/// Seconds spent per stage.
struct synthesis_timings {
    double initialization = 0, placement = 0, boosting = 0, topology_cut = 0;
};

struct synthesis_result {
    std::vector<instance> initial;      ///< after initialization
    std::vector<instance> placed_once;  ///< after the first placement optimization
    std::vector<instance> instances;    ///< final
    std::vector<graph::skeleton_graph<vec2>> skeletons;  ///< final, world, after the topology cut
    std::vector<double> energy_per_round;                ///< PME / #instances: [0] after initialization, then per round
    double energy_initial = 0, energy_after_placement = 0, energy_final = 0;
    int rounds = 0;
    std::size_t duplicates_removed = 0, smooth_connections = 0, boosted = 0;
    std::size_t reconnected = 0;  ///< boosting moves that kept a neighbour by a deformation (§4.4)
    std::vector<round_record> per_round;  ///< what each round of placement and boosting did
    std::size_t database_size = 0;
    double covered_fraction = 0;
    topology_cut_report cut{};
    synthesis_timings seconds;
};

/// World skeleton graphs of the instances of `s` (widths = the element's strip widths, mm).
[[nodiscard]] inline std::vector<graph::skeleton_graph<vec2>> world_skeletons(const pattern_state& s) {
    std::vector<graph::skeleton_graph<vec2>> out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const element& e = s.classes()[s.instances()[i].cls];
        graph::skeleton_graph<vec2> g;
        for (std::size_t v = 0; v < e.vertices.size(); ++v) g.add_vertex(s.geometry()[i].vertices[v], e.widths[v]);
        for (const skeleton_edge& ed : e.edges) g.add_edge(ed[0], ed[1]);
        out.push_back(std::move(g));
    }
    return out;
}

/// Connected pairs (i < j) of the pattern graph of any pattern space (planar or on a surface).
template <pattern_space S>
[[nodiscard]] std::vector<std::pair<std::uint32_t, std::uint32_t>> connected_pairs(const S& s) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
    const auto adj = s.connectivity();
    for (std::uint32_t i = 0; i < adj.size(); ++i)
        for (const std::uint32_t j : adj[i])
            if (j > i) out.emplace_back(i, j);
    return out;
}

namespace detail::synthesis {

using clock = std::chrono::steady_clock;
[[nodiscard]] inline double since(clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); }

template <pattern_space S>
[[nodiscard]] double mean_size(const S& s) {
    double m = 0;
    for (std::size_t i = 0; i < s.size(); ++i) m += s.classes()[s.instance_at(i).cls].size * s.instance_at(i).scale;
    return s.size() ? m / static_cast<double>(s.size()) : 0.0;
}

// One round: PLACEOPTIM then boosting (Algorithms 1 and 2); returns the translation summed.
template <pattern_space S, class R>
double run_round(S& s, connection_database& D, const synthesis_options& opt, int round, R& r, const progress_span& progress) {
    placement_options po = opt.placement;
    po.seed = opt.seed ^ (0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(round + 1));
    if (opt.smooth_connection) po.smooth_connection = make_smooth_connection(opt.sigma_d);
    auto t = clock::now();
    const placement_report pr = place_optimize(s, D, po, progress.part(0.0, 0.5));
    r.seconds.placement += since(t);
    r.smooth_connections += pr.smooth_connections;
    if (round == 0) r.placed_once = s.snapshot(), r.energy_after_placement = s.pattern_energy();
    t = clock::now();
    boosting_options bo = opt.boosting;
    bo.seed = po.seed + 1;
    bo.relax = po;  // the same search, shorter
    bo.relax.max_iterations = opt.boosting.relax.max_iterations;
    bo.sigma_d = opt.sigma_d;
    bo.reconnect = bo.reconnect && opt.smooth_connection;
    const boosting_report br = boost_placement(s, filter_candidates(D, opt.sigma_f), bo, progress.part(0.5, 1.0));
    r.seconds.boosting += since(t);
    r.boosted += br.boosted;
    r.reconnected += br.reconnected;
    r.duplicates_removed += remove_duplicates(s);
    return pr.translation + br.translation;
}

}  // namespace detail::synthesis

/// The rounds of placement and boosting on the existing instances of `s` (any pattern space) until
/// the layout stops moving, then the removal of fully overlapped duplicates; the moves keep the
/// overlap limits of opt.init (pattern_state::spacing_kept). `r` receives the energies, counts and
/// timings (the fields of synthesis_result of those names; placed_once a snapshot of s).
template <pattern_space S, class R>
void optimize_layout(S& s, const synthesis_options& opt, R& r, const progress_span& progress = {}) {
    namespace ds = detail::synthesis;
    connection_database D;
    bool mixed = false;  // the same-class factor only where the layout mixes classes (initialization.hpp)
    for (std::size_t i = 1; i < s.size() && !mixed; ++i) mixed = s.instance_at(i).cls != s.instance_at(0).cls;
    s.set_spacing(opt.move_overlap_limit, mixed ? opt.init.same_class_penalty : 1.0);
    s.set_crossing_penalty(opt.crossing_penalty, opt.crossing_angle_deg);
    r.energy_initial = s.pattern_energy();
    r.energy_per_round.push_back(s.size() ? r.energy_initial / static_cast<double>(s.size()) : 0.0);
    for (int round = 0; round < opt.max_rounds; ++round) {
        const round_record before{0, 0, 0, r.smooth_connections, r.boosted, r.reconnected, r.duplicates_removed};
        const double moved = ds::run_round(s, D, opt, round, r, progress.part(static_cast<double>(round) / opt.max_rounds, static_cast<double>(round + 1) / opt.max_rounds));
        ++r.rounds;
        r.energy_per_round.push_back(s.size() ? s.pattern_energy() / static_cast<double>(s.size()) : 0.0);
        r.per_round.push_back({s.size(), r.energy_per_round.back(), moved, r.smooth_connections - before.smooth_connections,
                               r.boosted - before.boosted, r.reconnected - before.reconnected, r.duplicates_removed - before.duplicates_removed});
        if (moved < opt.converged_translation * ds::mean_size(s) * static_cast<double>(s.size())) break;
    }
    r.database_size = D.size();
    r.energy_final = s.pattern_energy();
}

/// Runs pattern synthesis on the existing instances of `s` (optimize_layout, then the topology cut).
inline void optimize_pattern(pattern_state& s, const synthesis_options& opt, synthesis_result& r, const progress_span& progress = {}) {
    namespace ds = detail::synthesis;
    optimize_layout(s, opt, r, progress.part(0.0, 0.95));
    progress(0.95, "topology cut");
    r.instances = s.instances();
    r.skeletons = world_skeletons(s);
    if (opt.topology_cut) {
        const auto t = ds::clock::now();
        const auto pairs = connected_pairs(s);
        r.cut = topology_cut(r.skeletons, pairs, topology_cut_options{});  // thresholds from the strip widths
        r.seconds.topology_cut += ds::since(t);
    }
}

/// Initialization plus optimize_pattern (see the file comment). `classes` is only read during the
/// call; the result holds its own instances and skeletons.
template <control_field F>
[[nodiscard]] synthesis_result synthesize_pattern(std::span<const element> classes, std::span<const double> weights, const planar_domain& domain,
                                                  const F& field, const synthesis_options& opt = {}, const progress_span& progress = {}) {
    namespace ds = detail::synthesis;
    synthesis_result r;
    auto t = ds::clock::now();
    initialization_options io = opt.init;
    io.seed = opt.seed;
    const initialization_result init = initialize(classes, weights, domain, field, io);
    r.seconds.initialization = ds::since(t);
    r.initial = init.instances;
    r.covered_fraction = init.covered_fraction;
    pattern_state s(classes, init.instances, any_field(field), domain, opt.gamma_boundary);
    progress(0.05, "placement");
    optimize_pattern(s, opt, r, progress.part(0.05, 1.0));
    return r;
}

}  // namespace fabsynth::filigree
