// SPDX-License-Identifier: MIT
#pragma once
/// @file boosting.hpp  Boosting (filigree-synthesis.md §4.4, Algorithm 2): relative positions of
/// well-matched pairs found by the placement search are recorded (the connection database D,
/// placement.hpp); the best sigma_f of them (Table 1: 4.5-5%) become the filtered database D'. Each
/// instance then tries, for every neighbour j, the position that puts j where the most similar
/// good pair of D' (same classes, nearest relative position) had it (a boosting vector), plus the
/// average of those positions, and keeps the one with the lowest energy (learning phase). Old
/// neighbourhoods need not be kept, but connectivity must survive.
///
/// Usage:
///   auto filtered = fabsynth::filigree::filter_candidates(D, 0.05);
///   auto rep = fabsynth::filigree::boost_placement(state, filtered, {.seed = 2});
///
/// Energy of a candidate: the mean of eq. 2 over its neighbours times max(|N_i|, |N'_i|), plus
/// Theta. The paper compares PME values directly; a plain sum would favour candidates that shed
/// neighbours (fewer terms), which the paper's connectivity goal rules out, so the sum is taken
/// as if the instance had kept its neighbour count. A candidate is refused when it leaves the
/// instance without neighbours or leaves a former neighbour without any other neighbour (the
/// "loss of connection" of §4.4; reconnection by deformation is left to the smooth-connection
/// step of the next placement round, which runs the same deformation of §4.3.2).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
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

struct boosting_options {
    int max_iterations = 2;
    std::uint64_t seed = 1;
};

struct boosting_report {
    int iterations = 0;
    std::size_t boosted = 0;      ///< instance moves adopted
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
    for (const std::uint32_t j : nbrs) sum += pair_distance(g, s.geometry()[j]);
    return sum / static_cast<double>(nbrs.size()) * static_cast<double>(std::max(old_count, nbrs.size())) + s.theta(g);
}

// A former neighbour j that i leaves must keep another neighbour.
[[nodiscard]] inline bool keeps_others_connected(const std::vector<std::vector<std::uint32_t>>& adj, std::size_t i,
                                                 std::span<const std::uint32_t> before, std::span<const std::uint32_t> after) {
    (void)i;
    for (const std::uint32_t j : before)
        if (!std::binary_search(after.begin(), after.end(), j) && adj[j].size() <= 1) return false;
    return true;
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
    bool moved = false;
    double translation = 0;
};

[[nodiscard]] inline boost_move learn(const pattern_state& s, const connection_database& filtered, const std::vector<std::vector<std::uint32_t>>& adj,
                                      std::size_t i) {
    const instance& cur = s.instances()[i];
    boost_move r{cur, false, 0};
    const std::span<const std::uint32_t> nbrs = adj[i];
    double best = candidate_energy(s, s.geometry()[i], nbrs, nbrs.size());
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
    for (const vec2& p : cands) {  // learning phase
        if (!s.domain().contains(p) || glm::distance(p, cur.position) < 1e-9) continue;
        const instance cand = s.moved(cur, p);
        const placed g = place(s.classes()[cand.cls], cand);
        const std::vector<std::uint32_t> now = s.neighbours_of(g, i);
        if (!keeps_others_connected(adj, i, nbrs, now)) continue;
        const double e = candidate_energy(s, g, now, nbrs.size());
        if (e < best) best = e, r.best = cand, r.moved = true, r.translation = glm::distance(p, cur.position);
    }
    return r;
}

}  // namespace detail::boosting

/// Algorithm 2 on `s` with the filtered database (see the file comment). Deterministic for any
/// thread count (independent sets, moves applied in instance order after each set). The PME never
/// rises: an iteration that would raise it is undone and ends boosting.
[[nodiscard]] inline boosting_report boost_placement(pattern_state& s, const connection_database& filtered, const boosting_options& opt = {}) {
    namespace db = detail::boosting;
    boosting_report rep;
    if (s.size() == 0 || filtered.empty()) return rep;
    double energy = s.pattern_energy();
    for (int it = 0; it < opt.max_iterations; ++it) {
        const std::vector<instance> before = s.instances();
        std::size_t moved = 0;
        double translation = 0;
        const auto sets = detail::placement::independent_sets(s.connectivity());
        for (const auto& set : sets) {
            const auto adj = s.connectivity();  // moves of the previous set changed neighbourhoods
            std::vector<db::boost_move> res(set.size());
            parallel_for(0, set.size(), [&](std::size_t k) { res[k] = db::learn(s, filtered, adj, set[k]); });
            for (std::size_t k = 0; k < set.size(); ++k)
                if (res[k].moved && db::still_connected_after(s, set[k], res[k].best))
                    s.update(set[k], std::move(res[k].best)), ++moved, translation += res[k].translation;
        }
        ++rep.iterations;
        const double after = s.pattern_energy();
        if (after > energy) {  // boosting never ends above its start (the learning phase scores locally)
            s.set_instances(before);
            rep.energy.push_back(energy);
            break;
        }
        energy = after;
        rep.boosted += moved;
        rep.translation += translation;
        rep.energy.push_back(energy);
        if (moved == 0) break;
    }
    return rep;
}

}  // namespace fabsynth::filigree
