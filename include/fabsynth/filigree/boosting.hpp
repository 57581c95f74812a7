// SPDX-License-Identifier: MIT
#pragma once
/// @file boosting.hpp  Boosting (filigree-synthesis.md §4.4, Algorithm 2): relative positions of
/// well-matched pairs found by the placement search are recorded (the connection database D,
/// placement.hpp); the best sigma_f of them (Table 1: 4.5-5%) become the filtered database D'.
/// An instance with a pair worse than every pair of D' (the paper's "pair of neighboring elements
/// that cannot be put in a good connection") tries, for every neighbour j, the position that puts
/// j where the most similar good pair of D' (same classes, nearest relative position) had it (a
/// boosting vector), plus the average of those positions, and takes the one with the lowest
/// energy (learning phase) even when that is above its current energy: boosting is a jump to "a
/// new local initialization" from which placement can leave a poor local minimum. Each iteration
/// is therefore followed by a short placement optimization (`relax`), and kept only if the PME
/// then is below the PME before the iteration; otherwise it is undone and boosting ends.
///
/// Usage:
///   auto filtered = fabsynth::filigree::filter_candidates(D, 0.05);
///   auto rep = fabsynth::filigree::boost_placement(state, filtered, {.seed = 2});
///
/// Energy of a candidate: the mean of eq. 2 over its neighbours times max(|N_i|, |N'_i|), plus
/// Theta. The paper compares PME values directly; a plain sum would favour candidates that shed
/// neighbours (fewer terms), which the paper's connectivity goal rules out, so the sum is taken
/// as if the instance had kept its neighbour count. Connections a candidate loses (the "loss of
/// connection" of §4.4) are restored by deformation where possible: the moved instance is deformed
/// into tangent contact with each former neighbour it left (connection.hpp, reconnect(): the
/// narrow-gap case of Fig. 6 for gaps up to reconnect_gap strip widths, distortion below sigma_d,
/// its other contacts fixed); the reconnected instance competes with the plain move as a candidate
/// of its own. A candidate is refused when a former neighbour is still left without any
/// neighbour, or when it has none itself. Candidates also keep the spacing of initialization
/// (pattern_state::spacing_kept).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <span>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/filigree/connection.hpp"
#include "fabsynth/filigree/placement.hpp"

namespace fabsynth::filigree {

/// D' (FILTERCANDIDATEPAIRS): the fraction `sigma_f` of the records with the best (lowest)
/// quality, ties by database order. sigma_f in (0, 1].
[[nodiscard]] inline connection_database filter_candidates(const connection_database& d, double sigma_f) {
    if (!(sigma_f > 0 && sigma_f <= 1)) throw invalid_input("boosting: sigma_f must be in (0, 1]");
    std::vector<std::size_t> order(d.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return d[a].quality < d[b].quality; });
    const std::size_t keep = std::min(d.size(), static_cast<std::size_t>(std::ceil(sigma_f * static_cast<double>(d.size()))));
    connection_database out;
    for (std::size_t k = 0; k < keep; ++k) out.push_back(d[order[k]]);
    return out;
}

/// Placement options with 3 iterations: the relaxation after a boosting iteration.
[[nodiscard]] inline placement_options short_placement() {
    placement_options o;
    o.max_iterations = 3;
    return o;
}

struct boosting_options {
    int max_iterations = 2;
    std::uint64_t seed = 1;
    placement_options relax = short_placement();  ///< the placement that follows each iteration (its seed is derived from `seed`)
    bool reconnect = true;       ///< reconnection by deformation (§4.4)
    double sigma_d = 0.15;       ///< distortion bound of a reconnection (Table 1: 0.13-0.17)
    double reconnect_gap = 3.0;  ///< largest gap bridged by a reconnection, in strip widths of the moved element
};

struct boosting_report {
    int iterations = 0;
    std::size_t boosted = 0;      ///< instance moves adopted
    std::size_t reconnected = 0;  ///< of which kept a neighbour by a deformation
    std::size_t undone = 0;       ///< iterations undone because the PME did not fall
    double translation = 0.0;     ///< mm
    std::vector<double> energy;   ///< PME after each iteration
};

namespace detail::boosting {

// FINDBOOSTINGVECTOR: the record of D' with classes (ci, cj) nearest to `offset`, or null.
[[nodiscard]] inline const connection_record* nearest_record(const connection_database& d, std::uint32_t ci, std::uint32_t cj, vec2 offset) {
    const connection_record* best = nullptr;
    double best_d = std::numeric_limits<double>::infinity();
    for (const connection_record& r : d) {
        if (r.cls_i != ci || r.cls_j != cj) continue;
        const vec2 t = r.offset - offset;
        const double dd = glm::dot(t, t);
        if (dd < best_d) best_d = dd, best = &r;
    }
    return best;
}

[[nodiscard]] inline double candidate_energy(const pattern_state& s, const placed& g, std::span<const std::uint32_t> nbrs, std::size_t old_count) {
    if (nbrs.empty()) return std::numeric_limits<double>::infinity();
    double sum = 0;
    for (const std::uint32_t j : nbrs) sum += s.pair_energy(g, s.geometry()[j]);
    return sum / static_cast<double>(nbrs.size()) * static_cast<double>(std::max(old_count, nbrs.size())) + s.theta(g);
}

// The former neighbours that i leaves without any other neighbour (i was their only one);
// degree[k] is the neighbour count of before[k].
[[nodiscard]] inline std::vector<std::uint32_t> stranded(std::span<const std::uint32_t> before, std::span<const std::size_t> degree,
                                                         std::span<const std::uint32_t> after) {
    std::vector<std::uint32_t> out;
    for (std::size_t k = 0; k < before.size(); ++k)
        if (!std::binary_search(after.begin(), after.end(), before[k]) && degree[k] <= 1) out.push_back(before[k]);
    return out;
}

// Re-check when applying a move: two instances of one set may both leave the same neighbour.
[[nodiscard]] inline bool still_connected_after(const pattern_state& s, std::size_t i, const instance& next) {
    const placed g = place(s.classes()[next.cls], next);
    for (const std::uint32_t j : s.neighbours_of(s.geometry()[i], i)) {
        if (overlapping(g, s.geometry()[j])) continue;
        const auto others = s.neighbours_of(s.geometry()[j], j);
        if (others.size() <= 1) return false;  // i was j's only neighbour
    }
    return true;
}

struct boost_move {
    instance best;
    bool moved = false, reconnected = false;
    double translation = 0;
};

// Instance i of the picture s with neighbours nbrs (ids of s, increasing) whose neighbour counts in
// the whole pattern are `degree`.
[[nodiscard]] inline boost_move learn(const pattern_state& s, const connection_database& filtered, std::size_t i, std::span<const std::uint32_t> nbrs,
                                      std::span<const std::size_t> degree, double good_enough, const boosting_options& opt) {
    const instance& cur = s.instances()[i];
    boost_move r{cur, false, false, 0};
    double worst = 0;
    for (const std::uint32_t j : nbrs) worst = std::max(worst, s.pair_energy(s.geometry()[i], s.geometry()[j]));
    if (worst <= good_enough) return r;  // every pair of i is as good as the pairs of D'
    double best = std::numeric_limits<double>::infinity();
    std::vector<vec2> cands;
    for (const std::uint32_t j : nbrs) {  // selection phase: one boosting vector per neighbour
        const instance& o = s.instances()[j];
        const connection_record* rec = nearest_record(filtered, cur.cls, o.cls, to_local(cur, o.position));
        if (!rec) continue;
        // Position of i that puts j at rec->offset in i's frame (i's rotation and scale kept).
        const vec2 world_offset = to_world(instance{cur.cls, {0, 0}, cur.rotation, cur.scale, {}}, rec->offset);
        cands.push_back(o.position - world_offset);
    }
    if (cands.size() > 1) {
        vec2 avg(0, 0);
        for (const vec2& c : cands) avg += c;
        cands.push_back(avg / static_cast<double>(cands.size()));
    }
    auto consider = [&](const instance& cand, const placed& g, const std::vector<std::uint32_t>& now, bool deformed) {
        if (!stranded(nbrs, degree, now).empty()) return;
        const double e = candidate_energy(s, g, now, nbrs.size());
        if (e < best) best = e, r.best = cand, r.moved = true, r.reconnected = deformed, r.translation = glm::distance(cand.position, cur.position);
    };
    for (const vec2& p : cands) {  // learning phase: each boosting vector as it is, and reconnected
        if (!s.domain().admits(cur.cls, p) || glm::distance(p, cur.position) < 1e-9) continue;
        instance cand = s.moved(cur, p);
        placed g = place(s.classes()[cand.cls], cand);
        std::vector<std::uint32_t> now = s.neighbours_of(g, i);
        if (!s.spacing_kept(i, cand, g, now)) continue;
        consider(cand, g, now, false);
        if (!opt.reconnect) continue;
        std::vector<std::uint32_t> lost;
        std::set_difference(nbrs.begin(), nbrs.end(), now.begin(), now.end(), std::back_inserter(lost));
        bool deformed = false;
        for (const std::uint32_t j : lost) {  // reconnection by deformation (§4.4), in neighbour order
            if (std::binary_search(now.begin(), now.end(), j)) continue;  // an earlier deformation reached it
            const double gap = opt.reconnect_gap * s.classes()[cand.cls].median_width();
            std::optional<instance> fixed_up = reconnect(s, i, cand, j, now, gap, opt.sigma_d);
            if (!fixed_up) continue;
            cand = std::move(*fixed_up);
            g = place(s.classes()[cand.cls], cand);
            now = s.neighbours_of(g, i);
            deformed = true;
        }
        if (deformed && s.spacing_kept(i, cand, g, now)) consider(cand, g, now, true);  // it may have gained neighbours
    }
    return r;
}

}  // namespace detail::boosting

/// Algorithm 2 on `s` with the filtered database (see the file comment). Deterministic for any
/// thread count (independent sets, moves applied in instance order after each set; the relaxing
/// placement is deterministic too). The PME never rises: an iteration whose moves and relaxation
/// end above the PME it started from is undone and ends boosting.
template <pattern_space S>
[[nodiscard]] boosting_report boost_placement(S& s, const connection_database& filtered, const boosting_options& opt = {},
                                              const progress_span& progress = {}) {
    namespace db = detail::boosting;
    using view_type = decltype(s.view(0));
    boosting_report rep;
    if (s.size() == 0 || filtered.empty()) return rep;
    double good_enough = 0;  // the worst quality kept in D'
    for (const connection_record& r : filtered) good_enough = std::max(good_enough, r.quality);
    double energy = s.pattern_energy();
    for (int it = 0; it < opt.max_iterations; ++it) {
        auto before = s.snapshot();
        std::size_t moved = 0, reconnected = 0;
        double translation = 0;
        const auto sets = detail::placement::independent_sets(s.connectivity());
        const double share = 1.0 / opt.max_iterations;  // of the span: one iteration (its sets, then the relaxation)
        for (std::size_t si = 0; si < sets.size(); ++si) {
            const auto& set = sets[si];
            progress(share * (it + 0.5 * static_cast<double>(si) / static_cast<double>(sets.size())), "boosting");
            const auto adj = s.connectivity();  // moves of the previous set changed neighbourhoods
            std::vector<db::boost_move> res(set.size());
            parallel_for(0, set.size(), [&](std::size_t k) {
                const view_type v = s.view(set[k]);
                const auto nbrs = v.to_local(adj[set[k]]);
                if (!nbrs) return;  // a neighbour outside the picture: i stays
                std::vector<std::size_t> degree;
                for (const std::uint32_t j : adj[set[k]]) degree.push_back(adj[j].size());
                res[k] = db::learn(v.state(), filtered, v.index(), *nbrs, degree, good_enough, opt);
            });
            for (std::size_t k = 0; k < set.size(); ++k) {
                if (!res[k].moved) continue;
                const view_type v = s.view(set[k]);  // the same frame as learn's: set[k] has not moved since
                if (!db::still_connected_after(v.state(), v.index(), res[k].best)) continue;
                reconnected += res[k].reconnected;
                translation += res[k].translation, ++moved;
                s.adopt(set[k], v, std::move(res[k].best));
            }
        }
        ++rep.iterations;
        if (moved == 0) {
            rep.energy.push_back(energy);
            break;
        }
        placement_options relax = opt.relax;
        relax.seed = opt.seed ^ (0xbf58476d1ce4e5b9ULL * static_cast<std::uint64_t>(it + 1));
        connection_database scratch;
        translation += place_optimize(s, scratch, relax, progress.part(share * (it + 0.5), share * (it + 1))).translation;
        const double after = s.pattern_energy();
        if (!(after < energy)) {  // boosting never ends above its start
            s.restore(std::move(before));
            ++rep.undone;
            rep.energy.push_back(energy);
            break;
        }
        energy = after;
        rep.boosted += moved;
        rep.reconnected += reconnected;
        rep.translation += translation;
        rep.energy.push_back(energy);
    }
    return rep;
}

}  // namespace fabsynth::filigree
