// SPDX-License-Identifier: MIT
#pragma once
/// @file placement.hpp  Placement optimization (filigree-synthesis.md §4.3, Algorithm 1): the
/// connectivity graph of the instances, its independent sets as the update order, and per
/// instance a stochastic translation search that lowers the pattern matching energy (§4.2) under
/// the hard constraint that the instance keeps every neighbour it had (N_i ⊆ N'_i); every pair
/// scored is recorded in the connection database D (the input of boosting, §4.4). A smooth
/// connection step (§4.3.2) can follow each move (a callable; see connection.hpp).
///
/// Usage:
///   fabsynth::filigree::pattern_state s(classes, instances, field, domain);
///   fabsynth::filigree::connection_database D;
///   auto report = fabsynth::filigree::place_optimize(s, D, {.seed = 3});
///   s.pattern_energy();      // PME of eq. 3
///
/// Determinism and threads: the instances of one independent set are updated in parallel; each
/// reads the state as it was when the set began (no two of them are neighbours, §4.3.2 "Updating
/// Sequence") and draws from counter_rng(seed, iteration, instance); their moves are applied in
/// instance order once the set is done, and D receives their records in instance order. The result
/// is therefore the same for any thread count.
///
/// Neighbours: i and j are connected when their skeletons reach into each other's covering region
/// (matching.hpp, overlapping(): dist(P_i, P_j) of eq. 2 is finite). The local energy of i is the
/// sum of eq. 2 over its neighbours plus gamma_boundary times the boundary term (Theta, §7.2).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/filigree/domain.hpp"
#include "fabsynth/filigree/element.hpp"
#include "fabsynth/filigree/field.hpp"
#include "fabsynth/filigree/matching.hpp"
#include "fabsynth/filigree/pattern.hpp"
#include "fabsynth/graph/colouring.hpp"
#include "fabsynth/graph/csr_graph.hpp"

namespace fabsynth::filigree {

/// One scored pair (§4.3.1 "we record data (relative position, class ID etc) of all element pairs
/// that have been traversed"): j relative to i in i's frame (rotated back and divided by i's scale).
struct connection_record {
    std::uint32_t cls_i = 0, cls_j = 0;
    vec2 offset{0, 0};      ///< element-frame position of j's reference point seen from i
    double quality = 0.0;   ///< eq. 2 (mm), finite
};
using connection_database = std::vector<connection_record>;

/// The pattern being synthesized: classes, instances, their geometry and the control field in one
/// 2D frame, with the domain as seen in that frame. For a planar domain the frame is the plane;
/// on a surface (surface_space.hpp) a pattern_state is the picture of one instance's neighbourhood
/// in its local parameterization.
///
/// It is also the planar pattern space of the synthesis drivers (place_optimize, boost_placement,
/// optimize_pattern): snapshot()/restore(), view(i) (the state itself, see identity_view) and
/// adopt(i, view, instance).
class pattern_state {
public:
    pattern_state(std::span<const element> classes, std::vector<instance> instances, any_field field, const planar_domain& domain,
                  double gamma_boundary = 1.0)
        : pattern_state(classes, std::move(instances), std::move(field), domain.frame(), gamma_boundary) {}

    pattern_state(std::span<const element> classes, std::vector<instance> instances, any_field field, local_domain domain, double gamma_boundary = 1.0)
        : classes_(classes), field_(std::move(field)), domain_(std::move(domain)), gamma_boundary_(gamma_boundary) {
        double w = 0;
        for (const element& e : classes) w = std::max(w, e.median_width());
        band_ = 2 * w;
        boundary_ = domain_.boundary_samples(std::max(w, 1e-3));
        for (std::size_t r = 0; r < domain_.boundary.size(); ++r) {  // every polyline as a skeleton
            const auto& line = domain_.boundary[r];
            const auto first = static_cast<std::uint32_t>(boundary_positions_.size());
            const std::size_t n = line.size(), segs = domain_.closed[r] ? n : (n ? n - 1 : 0);
            boundary_positions_.insert(boundary_positions_.end(), line.begin(), line.end());
            for (std::size_t k = 0; k < segs; ++k)
                boundary_edges_.push_back({first + static_cast<std::uint32_t>(k), first + static_cast<std::uint32_t>((k + 1) % n)});
        }
        set_instances(std::move(instances));
    }

    [[nodiscard]] std::span<const element> classes() const noexcept { return classes_; }
    [[nodiscard]] const std::vector<instance>& instances() const noexcept { return instances_; }
    [[nodiscard]] const std::vector<placed>& geometry() const noexcept { return geo_; }
    [[nodiscard]] const any_field& field() const noexcept { return field_; }
    [[nodiscard]] const local_domain& domain() const noexcept { return domain_; }
    [[nodiscard]] std::size_t size() const noexcept { return instances_.size(); }
    /// The domain boundary as a skeleton: ring vertices (mm) and the edges closing every ring.
    [[nodiscard]] std::span<const vec2> boundary_positions() const noexcept { return boundary_positions_; }
    [[nodiscard]] std::span<const std::array<std::uint32_t, 2>> boundary_edges() const noexcept { return boundary_edges_; }
    /// Boundary samples (mm), at most the widest median strip width apart (the Theta term's B).
    [[nodiscard]] std::span<const vec2> boundary_samples() const noexcept { return boundary_; }

    void set_instances(std::vector<instance> in) {
        instances_ = std::move(in);
        geo_.clear();
        for (const instance& i : instances_) geo_.push_back(place(classes_[i.cls], i));
    }
    /// Replaces instance i (and its geometry).
    void update(std::size_t i, instance in) {
        geo_[i] = place(classes_[in.cls], in);
        instances_[i] = std::move(in);
    }
    /// The instance `in` moved to `p` (rotation and scale re-read from the field, shape kept).
    [[nodiscard]] instance moved(const instance& in, vec2 p) const {
        instance out = in;
        const field_sample f = field_(p);
        out.position = p, out.rotation = f.rotation, out.scale = f.scale;
        return out;
    }

    /// Instances whose skeletons reach into the covering region of `g` (excluding `self`), in id order.
    [[nodiscard]] std::vector<std::uint32_t> neighbours_of(const placed& g, std::size_t self) const {
        std::vector<std::uint32_t> out;
        for (std::size_t j = 0; j < geo_.size(); ++j)
            if (j != self && overlapping(g, geo_[j])) out.push_back(static_cast<std::uint32_t>(j));
        return out;
    }
    /// The connectivity graph Pi (Algorithm 1, line 1) as adjacency lists.
    [[nodiscard]] std::vector<std::vector<std::uint32_t>> connectivity() const {
        std::vector<std::vector<std::uint32_t>> adj(geo_.size());
        for (std::size_t i = 0; i < geo_.size(); ++i)
            for (std::size_t j = i + 1; j < geo_.size(); ++j)
                if (overlapping(geo_[i], geo_[j])) adj[i].push_back(static_cast<std::uint32_t>(j)), adj[j].push_back(static_cast<std::uint32_t>(i));
        return adj;
    }
    /// The spacing rule of the moves (see spacing_kept): overlap limit as a fraction of the moving
    /// instance's covering area, and the factor on same-class overlaps (§4.1 rules (2) and §7.3).
    void set_spacing(double max_pair_overlap, double same_class_penalty) {
        if (!(max_pair_overlap > 0 && max_pair_overlap <= 1) || !(same_class_penalty >= 1))
            throw invalid_input("pattern spacing: max_pair_overlap must be in (0, 1] and same_class_penalty >= 1");
        max_pair_overlap_ = max_pair_overlap, same_class_penalty_ = same_class_penalty;
    }
    /// True iff instance i placed as `in` (geometry g, neighbours `now`) keeps the spacing that
    /// initialization set up (§4.1 rule (2)): its covering region overlaps no neighbour j by more
    /// than max_pair_overlap of its own covering area (divided by same_class_penalty when j is of
    /// its class), unless the overlap with j was already larger where i is now, in which case it
    /// may not grow. A limit of 1 (the default) is no limit: complete overlaps are allowed and
    /// merged (§3.5). With eq. 2 alone a limit was needed, since the matching energy, nearly flat
    /// in the overlap depth for dense elements (a spiral pair scores 0.6-0.8 mm from 1 mm to 15 mm
    /// apart), let the search stack elements three deep; the crossing term of pair_energy now
    /// does that job (synthesis_options::move_overlap_limit has the measurements).
    [[nodiscard]] bool spacing_kept(std::size_t i, const instance& in, const placed& g, std::span<const std::uint32_t> now) const {
        if (max_pair_overlap_ >= 1) return true;
        const double own = classes_[in.cls].covering_area * in.scale * in.scale;
        for (const std::uint32_t j : now) {
            if (!g.box.intersects(geo_[j].box)) continue;
            const double limit = max_pair_overlap_ / (instances_[j].cls == in.cls ? same_class_penalty_ : 1.0) * own;
            const double after = covering_overlap(g, geo_[j]);
            if (after <= limit) continue;
            if (after > covering_overlap(geo_[i], geo_[j]) * (1 + 1e-12)) return false;
        }
        return true;
    }

    /// Theta of one placed instance (boundary term times gamma_boundary).
    [[nodiscard]] double theta(const placed& g) const { return gamma_boundary_ > 0 ? gamma_boundary_ * boundary_term(g, boundary_, band_) : 0.0; }

    /// The crossing term of Theta (see pair_energy): mm added per transversal crossing of two
    /// connected skeletons (0: none), and the smallest angle (degrees) that counts as a crossing.
    static void check_crossing_penalty(double mm_per_crossing, double min_angle_deg) {
        if (!(mm_per_crossing >= 0 && std::isfinite(mm_per_crossing)) || !(min_angle_deg >= 0 && min_angle_deg <= 90))
            throw invalid_input("pattern crossing penalty: mm per crossing must be finite and >= 0, the angle in [0, 90] degrees");
    }
    void set_crossing_penalty(double mm_per_crossing, double min_angle_deg = 30.0) {
        check_crossing_penalty(mm_per_crossing, min_angle_deg);
        crossing_penalty_ = mm_per_crossing, crossing_cos_ = std::cos(min_angle_deg * std::numbers::pi / 180.0);
    }
    [[nodiscard]] double crossing_penalty() const noexcept { return crossing_penalty_; }
    [[nodiscard]] double crossing_min_angle_deg() const noexcept { return std::acos(crossing_cos_) * 180.0 / std::numbers::pi; }

    /// Energy of one connected pair: eq. 2 plus crossing_penalty per transversal crossing of their
    /// skeletons (matching.hpp, transversal_crossings). The crossing term is part of the paper's
    /// optional Theta (eq. 3): eq. 2 alone scores a pair by the mean distance between their
    /// vertices in the overlap, which for dense elements barely changes with the depth of the
    /// overlap (a spiral pair scores 0.6-0.8 mm from 1 mm to 15 mm apart), so a layout of strips
    /// cutting across each other scores as well as one of tangent contacts, where §3.4 asks for
    /// the latter. +inf for a pair whose skeletons do not reach into each other's covering region.
    [[nodiscard]] double pair_energy(const placed& a, const placed& b) const {
        const double d = pair_distance(a, b);
        if (crossing_penalty_ <= 0 || !std::isfinite(d)) return d;
        return d + crossing_penalty_ * static_cast<double>(transversal_crossings(a, b, crossing_cos_));
    }

    /// Local energy of instance geometry g against the instances `nbrs` (pair_energy summed, + Theta).
    [[nodiscard]] double local_energy(const placed& g, std::span<const std::uint32_t> nbrs) const {
        double e = theta(g);
        for (const std::uint32_t j : nbrs) e += pair_energy(g, geo_[j]);
        return e;
    }
    /// PME of eq. 3: pair_energy over connected pairs plus the boundary Theta.
    [[nodiscard]] double pattern_energy() const {
        const auto adj = connectivity();
        double e = 0;
        for (std::size_t i = 0; i < geo_.size(); ++i) {
            e += theta(geo_[i]);
            for (const std::uint32_t j : adj[i])
                if (j > i) e += pair_energy(geo_[i], geo_[j]);
        }
        return e;
    }
    // The planar pattern space (see the class comment).
    using snapshot_type = std::vector<instance>;
    [[nodiscard]] snapshot_type snapshot() const { return instances_; }
    void restore(snapshot_type in) { set_instances(std::move(in)); }
    [[nodiscard]] const instance& instance_at(std::size_t i) const noexcept { return instances_[i]; }
    /// Instance i's neighbourhood as a planar picture: here the state itself.
    struct identity_view {
        const pattern_state* s;
        std::size_t i;
        [[nodiscard]] const pattern_state& state() const noexcept { return *s; }
        [[nodiscard]] std::size_t index() const noexcept { return i; }
        /// Pattern-wide ids as ids of state() (nothing if one is not in the picture).
        [[nodiscard]] std::optional<std::vector<std::uint32_t>> to_local(std::span<const std::uint32_t> ids) const {
            return std::vector<std::uint32_t>(ids.begin(), ids.end());
        }
    };
    [[nodiscard]] identity_view view(std::size_t i) const noexcept { return {this, i}; }
    /// Replaces instance i by `in`, given in the frame of `v` (a view of i).
    void adopt(std::size_t i, const identity_view&, instance in) { update(i, std::move(in)); }
    [[nodiscard]] double max_pair_overlap() const noexcept { return max_pair_overlap_; }
    [[nodiscard]] double same_class_penalty() const noexcept { return same_class_penalty_; }
    [[nodiscard]] double gamma_boundary() const noexcept { return gamma_boundary_; }

    /// Number of connected pairs.
    [[nodiscard]] std::size_t pair_count() const {
        std::size_t n = 0;
        for (const auto& a : connectivity()) n += a.size();
        return n / 2;
    }

private:
    std::span<const element> classes_;
    std::vector<instance> instances_;
    std::vector<placed> geo_;
    any_field field_;
    local_domain domain_;
    double gamma_boundary_;
    double max_pair_overlap_ = 1.0, same_class_penalty_ = 1.5;  // no move limit (synthesis_options::move_overlap_limit)
    double crossing_penalty_ = 0.0, crossing_cos_ = std::cos(std::numbers::pi / 6);
    double band_ = 0;
    std::vector<vec2> boundary_;
    std::vector<vec2> boundary_positions_;
    std::vector<std::array<std::uint32_t, 2>> boundary_edges_;
};

/// What the synthesis drivers need of a pattern: its instances (instance_at(i): class and scale),
/// the connectivity graph and PME over the whole pattern, snapshots to undo an iteration, and per
/// instance a view: a pattern_state holding the instance (view.index()) and its neighbourhood in one
/// 2D frame, where the steps of part 1 run unchanged; adopt() takes an instance given in a view's
/// frame back into the pattern. pattern_state is the planar space; surface_space.hpp the other.
template <class S>
concept pattern_space = requires(S& s, const S& cs, std::size_t i, instance in) {
    { cs.size() } -> std::convertible_to<std::size_t>;
    { cs.classes() } -> std::convertible_to<std::span<const element>>;
    { cs.instance_at(i) } -> std::convertible_to<const instance&>;
    { cs.connectivity() } -> std::convertible_to<std::vector<std::vector<std::uint32_t>>>;
    { cs.pattern_energy() } -> std::convertible_to<double>;
    { cs.view(i).state() } -> std::convertible_to<const pattern_state&>;
    { cs.view(i).index() } -> std::convertible_to<std::size_t>;
    s.restore(cs.snapshot());
    s.adopt(i, cs.view(i), in);
};

/// Smooth connection hook (§4.3.2): given the state and an instance index, returns the deformed
/// instance to adopt, or nothing. Called once per moved instance.
using smooth_connection_fn = std::function<std::optional<instance>(const pattern_state&, std::size_t)>;

struct placement_options {
    int candidates = 24;              ///< random displacements tried per instance and iteration
    double step = 0.15;               ///< search radius, fraction of the instance's size (scale included)
    double step_decay = 0.8;          ///< radius factor per iteration
    int max_iterations = 8;
    double converged_translation = 0.002;  ///< stop when the summed translation / (n * mean size) falls below
    std::uint64_t seed = 1;
    smooth_connection_fn smooth_connection;  ///< optional (§4.3.2)
};

struct placement_report {
    int iterations = 0;
    double translation = 0.0;          ///< summed translation over all iterations, mm
    std::vector<double> energy;        ///< PME after each iteration
    std::size_t smooth_connections = 0;
};

namespace detail::placement {

// Independent sets of the connectivity graph (Algorithm 1, line 2).
[[nodiscard]] inline std::vector<std::vector<graph::vertex_id>> independent_sets(const std::vector<std::vector<std::uint32_t>>& adj) {
    std::vector<graph::edge_record<>> edges;
    for (std::size_t i = 0; i < adj.size(); ++i)
        for (const std::uint32_t j : adj[i])
            if (j > i) edges.push_back({static_cast<graph::vertex_id>(i), j, 1.0, {}});
    const auto g = graph::build_csr(adj.size(), std::span<const graph::edge_record<>>(edges));
    return graph::greedy_colouring(g, graph::largest_degree_first{}).sets;
}

struct move_result {
    instance best;
    bool moved = false;
    double translation = 0;
    std::vector<connection_record> records;
};

// STOCHASTICSEARCH (§4.3.1) for instance i: the best of the current position and `candidates`
// random displacements that keep every old neighbour.
// `stream` names the instance pattern-wide (its random numbers do not depend on the view).
[[nodiscard]] inline move_result stochastic_search(const pattern_state& s, std::size_t i, std::span<const std::uint32_t> nbrs, double radius,
                                                   int candidates, std::uint64_t seed, std::uint64_t iteration, std::uint64_t stream) {
    const instance& cur = s.instances()[i];
    move_result r{cur, false, 0, {}};
    double best = s.local_energy(s.geometry()[i], nbrs);
    counter_rng rng(seed, iteration, stream);
    auto record = [&](const instance& cand, const placed& g, std::span<const std::uint32_t> with) {
        for (const std::uint32_t j : with) {
            const double q = s.pair_energy(g, s.geometry()[j]);
            if (std::isfinite(q)) r.records.push_back({cand.cls, s.instances()[j].cls, to_local(cand, s.instances()[j].position), q});
        }
    };
    record(cur, s.geometry()[i], nbrs);
    for (int k = 0; k < candidates; ++k) {
        const double a = 2 * std::numbers::pi * rng.uniform(), d = radius * std::sqrt(rng.uniform());
        const vec2 p = cur.position + d * vec2(std::cos(a), std::sin(a));
        if (!s.domain().admits(cur.cls, p)) continue;
        const instance cand = s.moved(cur, p);
        const placed g = place(s.classes()[cand.cls], cand);
        const std::vector<std::uint32_t> now = s.neighbours_of(g, i);
        if (!std::includes(now.begin(), now.end(), nbrs.begin(), nbrs.end())) continue;  // hard constraint N_i ⊆ N'_i
        if (!s.spacing_kept(i, cand, g, now)) continue;  // D holds configurations the search may adopt
        record(cand, g, now);
        const double e = s.local_energy(g, now);
        if (e < best) best = e, r.best = cand, r.moved = true, r.translation = glm::distance(p, cur.position);
    }
    return r;
}

}  // namespace detail::placement

/// PLACEOPTIM (Algorithm 1) on `s`, appending every scored pair to `database`. The PME never
/// rises: an iteration that would raise it is undone and ends the optimization.
template <pattern_space S>
[[nodiscard]] placement_report place_optimize(S& s, connection_database& database, const placement_options& opt = {},
                                              const progress_span& progress = {}) {
    namespace dp = detail::placement;
    if (opt.candidates < 1 || !(opt.step > 0) || !(opt.step_decay > 0 && opt.step_decay <= 1) || opt.max_iterations < 0)
        throw invalid_input("placement: candidates >= 1, step > 0 and step_decay in (0, 1] are required");
    using view_type = decltype(s.view(0));
    placement_report rep;
    if (s.size() == 0) return rep;
    auto size_of = [&](std::size_t i) { return s.classes()[s.instance_at(i).cls].size * s.instance_at(i).scale; };
    double mean_size = 0;
    for (std::size_t i = 0; i < s.size(); ++i) mean_size += size_of(i);
    mean_size /= static_cast<double>(s.size());
    double step = opt.step;
    double energy = s.pattern_energy();
    for (int it = 0; it < opt.max_iterations; ++it) {
        auto before = s.snapshot();
        const auto adj = s.connectivity();
        const auto sets = dp::independent_sets(adj);
        double moved = 0;
        for (std::size_t si = 0; si < sets.size(); ++si) {
            const auto& set = sets[si];
            progress((it + static_cast<double>(si) / static_cast<double>(sets.size())) / opt.max_iterations, "placement");
            std::vector<dp::move_result> res(set.size());
            std::vector<std::optional<view_type>> views(set.size());
            parallel_for(0, set.size(), [&](std::size_t k) {
                const std::size_t i = set[k];
                views[k].emplace(s.view(i));
                const auto nbrs = views[k]->to_local(adj[i]);
                if (!nbrs) return;  // a neighbour outside the picture: i stays
                res[k] = dp::stochastic_search(views[k]->state(), views[k]->index(), *nbrs, step * size_of(i), opt.candidates, opt.seed,
                                               static_cast<std::uint64_t>(it), i);
            });
            for (std::size_t k = 0; k < set.size(); ++k) {
                database.insert(database.end(), res[k].records.begin(), res[k].records.end());
                if (res[k].moved) s.adopt(set[k], *views[k], std::move(res[k].best)), moved += res[k].translation;
            }
            views.clear();
            if (opt.smooth_connection) {  // SMOOTHCONNECTION (Algorithm 1, line 8), in instance order
                std::vector<std::optional<instance>> def(set.size());
                std::vector<std::optional<view_type>> fresh(set.size());
                parallel_for(0, set.size(), [&](std::size_t k) {
                    fresh[k].emplace(s.view(set[k]));
                    def[k] = opt.smooth_connection(fresh[k]->state(), fresh[k]->index());
                });
                for (std::size_t k = 0; k < set.size(); ++k)
                    if (def[k]) s.adopt(set[k], *fresh[k], std::move(*def[k])), ++rep.smooth_connections;
            }
        }
        // Same-set instances may become neighbours of each other, and deformations change shapes:
        // neither is in a local energy, so an iteration that raised the PME is undone.
        const double after = s.pattern_energy();
        ++rep.iterations;
        if (after > energy) {
            s.restore(std::move(before));
            rep.energy.push_back(energy);
            break;
        }
        energy = after;
        rep.translation += moved;
        rep.energy.push_back(energy);
        step *= opt.step_decay;
        if (moved < opt.converged_translation * mean_size * static_cast<double>(s.size())) break;
    }
    return rep;
}

/// Removes instances that fully overlap an earlier one of the same class (§3.5 "Discussion": only
/// one copy of entirely overlapped elements is kept): reference points closer than `tolerance`
/// times the size and rotations within 0.05 rad. Returns the number removed.
inline std::size_t remove_duplicates(pattern_state& s, double tolerance = 0.05) {
    std::vector<instance> kept;
    const auto& in = s.instances();
    for (const instance& a : in) {
        bool dup = false;
        for (const instance& b : kept)
            if (a.cls == b.cls && glm::distance(a.position, b.position) < tolerance * s.classes()[a.cls].size * a.scale &&
                std::abs(std::remainder(a.rotation - b.rotation, 2 * std::numbers::pi)) < 0.05)
                dup = true;
        if (!dup) kept.push_back(a);
    }
    const std::size_t removed = in.size() - kept.size();
    if (removed) s.set_instances(std::move(kept));
    return removed;
}

}  // namespace fabsynth::filigree
