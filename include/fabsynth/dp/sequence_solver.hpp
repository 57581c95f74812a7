// SPDX-License-Identifier: MIT
#pragma once
/// @file sequence_solver.hpp  Generic dynamic-programming solver for assembling a sequence of
/// pieces (after Zhou et al. 2014, "Topology-constrained synthesis of vector patterns", §3.5-§3.7;
/// nothing here is specific to vector patterns: their portal cost is vector_pattern/portal_cost.hpp).
///
/// Problem. Pieces 0..n-1 have widths w_i > 0 (mm). Find a sequence eta_0..eta_N minimising
///   F(eta) = sum_i D(eta_i, eta_{i+1})            (+ D(eta_N, eta_0) for a closed sequence)
/// subject to: every consecutive pair is compatible (transition policy); the run's state (state
/// policy, e.g. a topology descriptor) satisfies the constraint policy at the end; the length
/// l = sum w_{eta_i} is within epsilon of the target L, where epsilon starts at `epsilon` and grows
/// by `epsilon_growth` only while no valid sequence is found, never beyond `epsilon_max` (a request
/// met only farther from L is refused with no_solution).
///
/// Open and closed. An *open* sequence has two ends (optionally restricted to `first_pieces` /
/// `last_pieces`); a *closed* one (`closed = true`) is a cycle: its last piece is followed by its
/// first, that transition's cost is part of F, and the state policy's close() summarises the run
/// glued onto itself (`cycle_summary`), which the constraint policy accepts or not.
///
/// Table. Sparse, keyed by (length bucket floor(l / q), last piece, state) (+ first piece on closed
/// sequences); each entry keeps the cheapest run reaching its key, with its exact length, accumulated
/// offset Delta and a back pointer. Layers are filled in increasing length (every width >= q, so a
/// transition always moves to a later layer). Deviation from the paper, on purpose: the paper keys
/// by the *number* of pieces and stores the length in the entry, which can drop the only run of the
/// right length; keying by length makes the DP exact: when every width is a multiple of q, the
/// returned cost equals the brute-force optimum over all sequences of length <= L + epsilon_max
/// (with offset_range = inf and autocorrelation_weight = 0; the tests check this). The default q is
/// the shortest width (exact for uniform slicing); with uneven widths, runs whose lengths fall in
/// one bucket compete, as all runs of one piece count do in the paper; a smaller q refines this at
/// a proportional cost in time and memory.
///
/// Heuristics kept from the paper (the result then is valid but may not be optimal):
///  - offset drift (§3.6.2): runs whose accumulated optimal offset Delta leaves (-H/2, H/2)
///    (H = offset_range, the paper's band height) are dropped; only the cheapest run per key keeps
///    its Delta.
///  - autocorrelation penalty (§3.7): beta * A(eta) is added to the cost of partial runs, with
///    A = max over lags j of sum_i exp(-|eta_i - eta_{i+j}| / sigma). The paper's formula lets
///    j = 0, where the sum is always the run length (it would dominate every other lag), so lags
///    start at 1; lags are limited to `autocorrelation_window` so an entry stores O(window) sums.
///  - closed sequences: cycles are searched in the table with the first piece kept in the key; by
///    rotation, each cycle is generated once starting at its smallest piece index (costs and
///    states are invariant under rotation).
///
/// Phases of solve_sequence (detail::, each callable on its own): check_inputs (options checked,
/// defaults resolved) -> successor_lists -> a sequence_table seeded by add_roots and filled by
/// fill_layers, which collects the complete sequences met (open_candidate: backtracking starts from
/// an accepted end; cycle_candidate: a run closing back onto its first piece) -> grown_epsilon and
/// cheapest_within choose one -> backtrack and accumulated_offsets read it back.
///
/// Complexity: O(E * s) transitions for E table entries and s compatible successors per piece,
/// each O(1) expected (one state-policy extend, one hash probe) plus O(window) with beta > 0.
/// E <= (L + epsilon_max) / q * n * S (* n on closed sequences) for S reachable states, usually far
/// fewer. Memory: ~48 bytes per entry (+ 6 * window with beta > 0) plus the open layers' hash tables;
/// the whole table is kept for backtracking. `max_entries` bounds it (invalid_input beyond).
///
/// Determinism: single-threaded; layers are processed in increasing length, entries in creation
/// order, successors in increasing piece index; a key keeps the first-created run among equal
/// costs. Nothing depends on hash-table iteration order, so results are bit-identical run to run.
///
/// Policies (C++20 concepts below): transition_cost_policy (D, compatibility, optimal offsets;
/// transition_table holds precomputed values), sequence_state_policy (how a run's state evolves;
/// topology::descriptor_policy, or `stateless`), sequence_constraint_policy (pruning and acceptance;
/// topology::constraints, or `unconstrained`).
///
/// Usage:
///   fabsynth::dp::transition_table table(n);   // or vector_pattern::portal_transition_table(portals)
///   table.set(0, 1, /*cost=*/0.5, /*offset=*/0.1);  // ... for every compatible pair
///   fabsynth::topology::constraints want{.components = 1, .holes = 0};
///   auto topo = fabsynth::topology::descriptor_policy::for_constraints(piece_descriptors, want);
///   auto r = fabsynth::dp::solve_sequence(widths, table, topo, want, {.target_length = 300.0});
///   // r.pieces = eta, r.offsets = accumulated optimal offsets, r.length, r.cost
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/dp/detail/chunked_store.hpp"
#include "fabsynth/dp/detail/index_table.hpp"

namespace fabsynth::dp {

// ---------------------------------------------------------------------------------------------
// Policies

/// Transition costs between pieces: size() pieces; compatible(i, j) says whether j may follow i;
/// cost(i, j) = D(i, j) >= 0 and offset(i, j) = optimal vertical offset of j relative to i (mm),
/// read only for compatible pairs. Queried O(n^2) times up front, so any cost is fine.
template <class T>
concept transition_cost_policy = requires(const T& t, std::size_t i, std::size_t j) {
    { t.size() } -> std::convertible_to<std::size_t>;
    { t.compatible(i, j) } -> std::convertible_to<bool>;
    { t.cost(i, j) } -> std::convertible_to<double>;
    { t.offset(i, j) } -> std::convertible_to<double>;
};

/// State of a run of pieces: start(i) for the run (i), extend(s, j) for the run followed by j
/// (nullopt = j cannot follow), close(s) = summary once the run's end is joined to its start
/// (closed sequences; nullopt = cannot close), hash(s) consistent with ==. Called once per
/// transition: should be O(1) amortised (memoise, as topology::descriptor_policy does).
template <class P>
concept sequence_state_policy = requires(P& p, const typename P::state& s, std::size_t piece) {
    typename P::state;
    typename P::cycle_summary;
    requires std::copyable<typename P::state> && std::equality_comparable<typename P::state>;
    { p.start(piece) } -> std::same_as<std::optional<typename P::state>>;
    { p.extend(s, piece) } -> std::same_as<std::optional<typename P::state>>;
    { p.close(s) } -> std::same_as<std::optional<typename P::cycle_summary>>;
    { p.hash(s) } -> std::convertible_to<std::uint64_t>;
};

/// Constraints on a run's state: viable(p, s) false = prune (no extension can be accepted),
/// accept_open(p, s) = an open sequence may end here, accept_cycle(p, z) = a closed one is valid.
/// An optional c.validate(p) is called once before solving (throw invalid_input for impossible targets).
template <class C, class P>
concept sequence_constraint_policy =
    sequence_state_policy<P> &&
    requires(const C& c, const P& p, const typename P::state& s, const typename P::cycle_summary& z) {
        { c.viable(p, s) } -> std::convertible_to<bool>;
        { c.accept_open(p, s) } -> std::convertible_to<bool>;
        { c.accept_cycle(p, z) } -> std::convertible_to<bool>;
    };

/// State policy with no state: plain sequence assembly (every run may end, every cycle closes).
struct stateless {
    struct state {
        friend bool operator==(const state&, const state&) = default;
    };
    struct cycle_summary {};
    [[nodiscard]] std::optional<state> start(std::size_t) const { return state{}; }
    [[nodiscard]] std::optional<state> extend(const state&, std::size_t) const { return state{}; }
    [[nodiscard]] std::optional<cycle_summary> close(const state&) const { return cycle_summary{}; }
    [[nodiscard]] std::uint64_t hash(const state&) const noexcept { return 0; }
};

/// Constraint policy accepting everything.
struct unconstrained {
    template <class P, class S>
    [[nodiscard]] bool viable(const P&, const S&) const noexcept { return true; }
    template <class P, class S>
    [[nodiscard]] bool accept_open(const P&, const S&) const noexcept { return true; }
    template <class P, class Z>
    [[nodiscard]] bool accept_cycle(const P&, const Z&) const noexcept { return true; }
};

// ---------------------------------------------------------------------------------------------
// Precomputed transition tables

/// Dense n x n table of transition costs and offsets (satisfies transition_cost_policy).
/// Pairs start incompatible; set() makes one compatible. O(n^2) memory (24 bytes per pair).
class transition_table {
public:
    transition_table() = default;
    explicit transition_table(std::size_t n) : n_(n), cost_(n * n, inf), offset_(n * n, 0.0) {
        if (n > 1u << 15) throw invalid_input("transition table: " + std::to_string(n) + " pieces is more than 32768");
    }
    /// Makes j a valid successor of i with cost D >= 0 and optimal offset tau (both finite).
    void set(std::size_t i, std::size_t j, double cost, double offset = 0.0) {
        check(i, j);
        if (!(std::isfinite(cost) && cost >= 0.0))
            throw invalid_input("transition table: cost(" + std::to_string(i) + ", " + std::to_string(j) +
                                ") must be finite and >= 0, got " + std::to_string(cost));
        if (!std::isfinite(offset))
            throw invalid_input("transition table: offset(" + std::to_string(i) + ", " + std::to_string(j) +
                                ") must be finite");
        cost_[i * n_ + j] = cost;
        offset_[i * n_ + j] = offset;
    }
    /// Makes j an invalid successor of i.
    void forbid(std::size_t i, std::size_t j) {
        check(i, j);
        cost_[i * n_ + j] = inf;
    }
    [[nodiscard]] std::size_t size() const noexcept { return n_; }
    [[nodiscard]] bool compatible(std::size_t i, std::size_t j) const noexcept { return cost_[i * n_ + j] != inf; }
    [[nodiscard]] double cost(std::size_t i, std::size_t j) const noexcept { return cost_[i * n_ + j]; }
    [[nodiscard]] double offset(std::size_t i, std::size_t j) const noexcept { return offset_[i * n_ + j]; }

private:
    static constexpr double inf = std::numeric_limits<double>::infinity();
    void check(std::size_t i, std::size_t j) const {
        if (i >= n_ || j >= n_)
            throw invalid_input("transition table: pair (" + std::to_string(i) + ", " + std::to_string(j) +
                                ") out of range for " + std::to_string(n_) + " pieces");
    }
    std::size_t n_ = 0;
    std::vector<double> cost_, offset_;
};

// ---------------------------------------------------------------------------------------------
// Options and result

/// Options of solve_sequence (lengths in mm).
struct sequence_options {
    double target_length = 0;            ///< L > 0
    double epsilon = 0;                  ///< initial tolerance |l - L| <= epsilon; 0 = 0.05 L (§3.5)
    double epsilon_growth = 1.25;        ///< tolerance factor while nothing is found (§3.6.3), > 1
    double epsilon_max = 0;              ///< hard cap on the tolerance; 0 = 0.2 L
    double offset_range = std::numeric_limits<double>::infinity();  ///< H: keep the accumulated offset |Delta| < H / 2
    double autocorrelation_weight = 0;   ///< beta (§3.7); 0 = off
    double autocorrelation_sigma = 0.5;  ///< sigma of §3.7, > 0
    std::size_t autocorrelation_window = 8;   ///< lags 1..window enter A (>= 1)
    bool closed = false;                 ///< closed sequence: the last piece connects back to the first
    std::vector<std::size_t> first_pieces{};  ///< open sequences: allowed eta_0 (empty = any)
    std::vector<std::size_t> last_pieces{};   ///< open sequences: allowed eta_N (empty = any)
    double length_resolution = 0;        ///< q: length bucket width, <= shortest width; 0 = shortest width
    std::size_t max_entries = std::size_t{1} << 22;  ///< table size limit (~48 bytes per entry, + 6 per lag)
};

/// Work and memory of one solve.
struct sequence_stats {
    std::size_t entries = 0;      ///< table entries created
    std::size_t transitions = 0;  ///< extensions tried
    std::size_t layers = 0;       ///< non-empty length buckets
    std::size_t candidates = 0;   ///< complete valid sequences within epsilon_max met
    std::size_t peak_bytes = 0;   ///< peak bytes held by the table, layer hash tables and policy memo
};

/// Best sequence found.
template <class State, class CycleSummary>
struct sequence_result {
    std::vector<std::size_t> pieces;  ///< eta_0..eta_N
    std::vector<double> offsets;      ///< accumulated optimal offsets Delta_i (mm), Delta_0 = 0
    double cost = 0;                  ///< F(eta), including D(eta_N, eta_0) on closed sequences
    double penalty = 0;               ///< beta * A(eta) (0 when beta = 0)
    double length = 0;                ///< sum of the widths (mm)
    double epsilon = 0;               ///< tolerance that was needed, <= epsilon_max
    State state{};                    ///< state of the run eta_0..eta_N
    std::optional<CycleSummary> cycle;  ///< closed sequences: summary after closing the cycle
    sequence_stats stats;
};

namespace detail {
template <class P>
std::size_t policy_bytes(const P& p) {
    if constexpr (requires { { p.memory_bytes() } -> std::convertible_to<std::size_t>; })
        return p.memory_bytes();
    else
        return 0;
}

/// Back pointer of a run's first entry (and "no entry" in general).
inline constexpr std::uint32_t no_pred = 0xffffffffu;

// ---- phase 1: inputs checked, defaults resolved

/// The solve's numbers once the options are checked and their defaults resolved.
struct solve_limits {
    std::size_t pieces = 0;       ///< n
    double target = 0;            ///< L
    double epsilon = 0;           ///< initial tolerance
    double epsilon_max = 0;       ///< largest tolerance
    double resolution = 0;        ///< q, the length bucket width
    double longest = 0;           ///< l_max = L + epsilon_max: no run grows past it
    double beta = 0;              ///< autocorrelation weight
    std::size_t window = 0;       ///< lags carried per entry (0 when beta = 0)
};

/// Validates widths, transitions and options (throws invalid_input naming what is wrong) and
/// resolves the defaults of epsilon, epsilon_max and length_resolution.
template <transition_cost_policy T>
solve_limits check_inputs(std::span<const double> widths, const T& transitions, const sequence_options& opt) {
    const std::size_t n = widths.size();
    if (n == 0) throw invalid_input("sequence solver: no pieces");
    if (n > 0xffff) throw invalid_input("sequence solver: " + std::to_string(n) + " pieces is more than 65535");
    if (transitions.size() != n)
        throw invalid_input("sequence solver: transition policy has " + std::to_string(transitions.size()) +
                            " pieces but " + std::to_string(n) + " widths were given");
    double min_w = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i) {
        if (!(std::isfinite(widths[i]) && widths[i] > 0.0))
            throw invalid_input("sequence solver: width of piece " + std::to_string(i) + " must be finite and > 0, got " +
                                std::to_string(widths[i]));
        min_w = std::min(min_w, widths[i]);
    }
    const double L = opt.target_length;
    if (!(std::isfinite(L) && L > 0.0))
        throw invalid_input("sequence solver: target_length must be finite and > 0, got " + std::to_string(L));
    const double eps0 = opt.epsilon == 0.0 ? 0.05 * L : opt.epsilon;
    const double eps_max = opt.epsilon_max == 0.0 ? std::max(0.2 * L, eps0) : opt.epsilon_max;
    if (!(std::isfinite(eps0) && eps0 > 0.0)) throw invalid_input("sequence solver: epsilon must be finite and > 0");
    if (!(std::isfinite(eps_max) && eps_max >= eps0))
        throw invalid_input("sequence solver: epsilon_max (" + std::to_string(eps_max) + ") must be finite and >= epsilon (" +
                            std::to_string(eps0) + ")");
    if (!(std::isfinite(opt.epsilon_growth) && opt.epsilon_growth > 1.0))
        throw invalid_input("sequence solver: epsilon_growth must be finite and > 1");
    if (!(opt.offset_range > 0.0)) throw invalid_input("sequence solver: offset_range must be > 0 (may be infinite)");
    const double beta = opt.autocorrelation_weight;
    if (!(std::isfinite(beta) && beta >= 0.0)) throw invalid_input("sequence solver: autocorrelation_weight must be finite and >= 0");
    if (beta > 0.0) {
        if (!(std::isfinite(opt.autocorrelation_sigma) && opt.autocorrelation_sigma > 0.0))
            throw invalid_input("sequence solver: autocorrelation_sigma must be finite and > 0");
        if (opt.autocorrelation_window < 1 || opt.autocorrelation_window > 1024)
            throw invalid_input("sequence solver: autocorrelation_window must be in [1, 1024]");
    }
    const double q = opt.length_resolution == 0.0 ? min_w : opt.length_resolution;
    if (!(std::isfinite(q) && q > 0.0 && q <= min_w))
        throw invalid_input("sequence solver: length_resolution must be in (0, shortest width = " + std::to_string(min_w) +
                            "], got " + std::to_string(q));
    const double l_max = L + eps_max;
    if (l_max / q > 1e15) throw invalid_input("sequence solver: target_length / length_resolution is too large");
    auto check_list = [n](const std::vector<std::size_t>& v, const char* name) {
        for (std::size_t i : v)
            if (i >= n)
                throw invalid_input(std::string("sequence solver: ") + name + " holds piece " + std::to_string(i) +
                                    " but there are " + std::to_string(n) + " pieces");
    };
    check_list(opt.first_pieces, "first_pieces");
    check_list(opt.last_pieces, "last_pieces");
    if (opt.closed && (!opt.first_pieces.empty() || !opt.last_pieces.empty()))
        throw invalid_input("sequence solver: first_pieces / last_pieces apply to open sequences only");
    if (opt.max_entries == 0 || opt.max_entries >= no_pred) throw invalid_input("sequence solver: max_entries out of range");
    return {n, L, eps0, eps_max, q, l_max, beta, beta > 0.0 ? opt.autocorrelation_window : 0};
}

// ---- phase 2: successor lists

/// A compatible transition i -> piece with its cost and offset.
struct successor {
    std::uint32_t piece;
    std::uint16_t piece16;
    double cost, offset;
};

/// For every piece, its compatible successors in ascending piece index (the deterministic
/// tie-break order). Throws invalid_input for a non-finite or negative cost, a non-finite offset.
template <transition_cost_policy T>
std::vector<std::vector<successor>> successor_lists(const T& transitions, std::size_t n) {
    std::vector<std::vector<successor>> succ(n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            if (!transitions.compatible(i, j)) continue;
            const double c = transitions.cost(i, j), o = transitions.offset(i, j);
            if (!(std::isfinite(c) && c >= 0.0) || !std::isfinite(o))
                throw invalid_input("sequence solver: transition (" + std::to_string(i) + ", " + std::to_string(j) +
                                    ") has a non-finite or negative cost, or a non-finite offset");
            succ[i].push_back({static_cast<std::uint32_t>(j), static_cast<std::uint16_t>(j), c, o});
        }
    return succ;
}

// ---- phase 3: the table

/// The sparse DP table of the file comment: entries keyed by (length bucket, last piece, first
/// piece (closed sequences), state), each the cheapest run reaching its key with a back pointer,
/// plus the autocorrelation lag sums and recent pieces of every entry (beta > 0). The entries
/// stay for backtracking; only the open layers (a ring of hash tables indexed by bucket) are
/// transient. Not copyable (the layers index into the entries).
template <class State>
class sequence_table {
public:
    static constexpr std::uint32_t no_pred = detail::no_pred;
    static constexpr std::uint16_t before_start = 0xffff;  ///< recent-piece slot before the run's start

    struct entry {
        State state;
        double cost;    // F of the run
        double total;   // F + beta * A: what the DP minimises per key
        double length;  // exact sum of widths
        float drift;    // accumulated offset Delta (only compared against H / 2)
        std::uint16_t piece, first;
        std::uint32_t pred;
    };

    /// Throws invalid_input when the lengths need too many buckets.
    sequence_table(std::span<const double> widths, const solve_limits& lim, std::size_t max_entries)
        : lim_(lim), max_entries_(max_entries), lags_(std::max<std::size_t>(lim.window, 1)),
          recent_(std::max<std::size_t>(lim.window, 1)) {
        // Open layers live in a ring indexed by bucket: a transition moves at most ceil(max width / q)
        // buckets ahead, so ring_size slots never collide.
        double max_w = 0;
        for (double w : widths) max_w = std::max(max_w, w);
        last_bucket_ = static_cast<std::uint64_t>(std::floor(lim.longest / lim.resolution));
        const double ring_span = std::ceil(max_w / lim.resolution) + 2.0;
        if (ring_span > double(1u << 16) || double(last_bucket_) > double(1u << 27))
            throw invalid_input("sequence solver: too many length buckets (longest width / length_resolution = " +
                                std::to_string(max_w / lim.resolution) + ", target / length_resolution = " +
                                std::to_string(lim.longest / lim.resolution) + "); raise length_resolution");
        ring_.resize(static_cast<std::size_t>(std::min(ring_span, double(last_bucket_) + 2.0)));
    }
    sequence_table(const sequence_table&) = delete;
    sequence_table& operator=(const sequence_table&) = delete;

    [[nodiscard]] std::uint64_t bucket_of(double l) const { return static_cast<std::uint64_t>(std::floor(l / lim_.resolution)); }
    [[nodiscard]] std::uint64_t last_bucket() const noexcept { return last_bucket_; }
    [[nodiscard]] const entry& operator[](std::uint32_t i) const { return *entries_[i]; }
    [[nodiscard]] std::size_t window() const noexcept { return lim_.window; }
    [[nodiscard]] float* lags(std::uint32_t i) { return lags_[i]; }
    [[nodiscard]] std::uint16_t* recent(std::uint32_t i) { return recent_[i]; }
    [[nodiscard]] sequence_stats& stats() noexcept { return stats_; }

    /// Inserts or improves the entry for (bucket, piece, first, state); `state_hash` hashes e.state.
    /// Returns its index, or no_pred when an existing run of that key is as cheap or cheaper.
    /// Throws invalid_input beyond max_entries.
    std::uint32_t offer(const entry& e, std::uint64_t bucket, std::uint64_t state_hash) {
        detail::index_table& layer = ring_[bucket % ring_.size()];
        const auto h = static_cast<std::uint32_t>(hash64(state_hash, e.piece, e.first));
        const std::uint32_t found = layer.find(h, [&](std::uint32_t idx) {
            const entry& o = *entries_[idx];
            return o.piece == e.piece && o.first == e.first && o.state == e.state;
        });
        if (found != detail::index_table::none) {
            // Strictly cheaper wins; on ties the earlier-created run stays (deterministic order).
            if (e.total < entries_[found]->total) {
                *entries_[found] = e;
                return found;
            }
            return no_pred;
        }
        if (entries_.size() >= max_entries_)
            throw invalid_input("sequence solver: the DP table exceeds max_entries = " + std::to_string(max_entries_) +
                                " (target length " + std::to_string(lim_.target) + " mm, length resolution " +
                                std::to_string(lim_.resolution) + " mm); raise max_entries or length_resolution");
        const std::size_t before = layer.memory_bytes();
        const auto idx = static_cast<std::uint32_t>(entries_.push_back(e));
        if (lim_.window) lags_.push_back(0.0f), recent_.push_back(before_start);
        layer.insert(h, idx);
        pending_bytes_ += layer.memory_bytes() - before;
        ++stats_.entries;
        return idx;
    }

    /// Takes the layer of `bucket` out of the ring: its entry indices in creation order (the
    /// deterministic processing order), empty if the layer holds none.
    std::vector<std::uint32_t> take_layer(std::uint64_t bucket) {
        detail::index_table layer;
        layer.swap(ring_[bucket % ring_.size()]);
        if (layer.size() == 0) return {};
        pending_bytes_ -= layer.memory_bytes();
        ++stats_.layers;
        return layer.indices();
    }

    /// Records the peak memory so far (entries, lag rows, open layers and the state policy's memo).
    void update_peak(std::size_t policy_bytes) {
        const std::size_t bytes = entries_.memory_bytes() +
                                  (lim_.window ? lags_.memory_bytes() + recent_.memory_bytes() : 0) + pending_bytes_ +
                                  ring_.capacity() * sizeof(detail::index_table) + policy_bytes;
        stats_.peak_bytes = std::max(stats_.peak_bytes, bytes);
    }

private:
    solve_limits lim_;
    std::size_t max_entries_;
    detail::chunked_store<entry> entries_;
    detail::chunked_store<float> lags_;  // lag sums per entry (beta > 0)
    // Last `window` pieces of each entry's run, most recent first (no pointer chasing per transition).
    detail::chunked_store<std::uint16_t> recent_;
    std::vector<detail::index_table> ring_;
    std::uint64_t last_bucket_ = 0;
    std::size_t pending_bytes_ = 0;
    sequence_stats stats_;
};

/// A complete valid sequence met during the fill, within epsilon_max of the target.
template <class CycleSummary>
struct candidate {
    std::uint32_t index;  ///< its last entry
    double distance;      ///< |l - L|
    double total, cost;   ///< what is minimised, and F (closing transition included when closed)
    std::optional<CycleSummary> cycle;
};

/// Seeds the table with the one-piece runs: every allowed first piece (open sequences:
/// first_pieces, if given) that fits and whose state is viable.
template <sequence_state_policy P, class C>
void add_roots(sequence_table<typename P::state>& table, std::span<const double> widths, P& states, const C& constraints,
               const sequence_options& opt, const solve_limits& lim) {
    using entry = typename sequence_table<typename P::state>::entry;
    for (std::size_t s = 0; s < lim.pieces; ++s) {
        if (!opt.closed && !opt.first_pieces.empty() &&
            std::find(opt.first_pieces.begin(), opt.first_pieces.end(), s) == opt.first_pieces.end())
            continue;
        if (widths[s] > lim.longest) continue;
        std::optional<typename P::state> st = states.start(s);
        if (!st || !constraints.viable(states, *st)) continue;
        const std::uint32_t at = table.offer(entry{*st, 0.0, 0.0, widths[s], 0.0f, static_cast<std::uint16_t>(s),
                                                   static_cast<std::uint16_t>(opt.closed ? s : 0), table.no_pred},
                                             table.bucket_of(widths[s]), static_cast<std::uint64_t>(states.hash(*st)));
        if (table.window() && at != table.no_pred) table.recent(at)[0] = static_cast<std::uint16_t>(s);
    }
}

/// Open sequences (backtracking from an end): the run at `idx` may end here if its last piece is
/// an allowed last piece and the constraints accept its state.
template <class P, class C>
std::optional<candidate<typename P::cycle_summary>> open_candidate(const typename sequence_table<typename P::state>::entry& e,
                                                                   std::uint32_t idx, double distance, P& states,
                                                                   const C& constraints,
                                                                   const std::vector<std::uint8_t>& is_last) {
    if (is_last[e.piece] && constraints.accept_open(states, e.state))
        return candidate<typename P::cycle_summary>{idx, distance, e.total, e.cost, std::nullopt};
    return std::nullopt;
}

/// Closed sequences (cycle search): the run at `idx` closes if its last piece may be followed by
/// its first one and the state policy's closing summary is accepted; the closing transition's
/// cost is added.
template <transition_cost_policy T, class P, class C>
std::optional<candidate<typename P::cycle_summary>> cycle_candidate(const typename sequence_table<typename P::state>::entry& e,
                                                                    std::uint32_t idx, double distance, const T& transitions,
                                                                    P& states, const C& constraints) {
    if (!transitions.compatible(e.piece, e.first)) return std::nullopt;
    if (auto z = states.close(e.state); z && constraints.accept_cycle(states, *z)) {
        const double closing = transitions.cost(e.piece, e.first);
        return candidate<typename P::cycle_summary>{idx, distance, e.total + closing, e.cost + closing, *z};
    }
    return std::nullopt;
}

/// Fills the layers in increasing length: every entry is first offered as a candidate (open_candidate
/// or cycle_candidate, within epsilon_max of the target), then extended by each compatible successor
/// that keeps the run within l_max, its drift within (-H/2, H/2) and its state viable; with beta > 0
/// the successor's lag sums and recent pieces are updated and beta * A enters its total.
/// Returns the candidates in the order met.
template <transition_cost_policy T, sequence_state_policy P, class C, class F>
std::vector<candidate<typename P::cycle_summary>> fill_layers(sequence_table<typename P::state>& table,
                                                              std::span<const double> widths, const T& transitions,
                                                              const std::vector<std::vector<successor>>& succ, P& states,
                                                              const C& constraints, const sequence_options& opt,
                                                              const solve_limits& lim, F& progress) {
    using entry = typename sequence_table<typename P::state>::entry;
    std::vector<std::uint8_t> is_last(lim.pieces, opt.last_pieces.empty() ? 1 : 0);
    for (std::size_t i : opt.last_pieces) is_last[i] = 1;
    const std::size_t window = lim.window;
    std::vector<double> kernel;  // exp(-d / sigma) for index distances d
    if (window) {
        kernel.resize(lim.pieces);
        for (std::size_t d = 0; d < lim.pieces; ++d) kernel[d] = std::exp(-static_cast<double>(d) / opt.autocorrelation_sigma);
    }
    const double half_range = opt.offset_range / 2.0;
    std::vector<candidate<typename P::cycle_summary>> candidates;
    std::vector<std::uint16_t> new_recent(window);
    std::vector<float> new_lags(window);
    const std::uint64_t last_bucket = table.last_bucket();
    for (std::uint64_t bucket = 0; bucket <= last_bucket + 1; ++bucket) {
        const std::vector<std::uint32_t> members = table.take_layer(bucket);
        if (members.empty()) continue;
        table.update_peak(policy_bytes(states));
        report_progress(progress, std::min(1.0, static_cast<double>(bucket) / static_cast<double>(last_bucket + 1)),
                        "sequence DP");
        for (const std::uint32_t idx : members) {
            const entry e = table[idx];  // copy: an improvement below may not alias it, but be safe
            const double distance = std::abs(e.length - lim.target);
            if (distance <= lim.epsilon_max) {
                auto c = opt.closed ? cycle_candidate(e, idx, distance, transitions, states, constraints)
                                    : open_candidate(e, idx, distance, states, constraints, is_last);
                if (c) candidates.push_back(std::move(*c));
            }
            const std::uint16_t* history = window ? table.recent(idx) : nullptr;
            for (const successor& s : succ[e.piece]) {
                if (opt.closed && s.piece < e.first) continue;  // cycles start at their smallest piece
                const double length = e.length + widths[s.piece];
                if (length > lim.longest) continue;
                ++table.stats().transitions;
                const double drift = static_cast<double>(e.drift) + s.offset;
                if (!(std::abs(drift) < half_range)) continue;
                std::optional<typename P::state> st = states.extend(e.state, s.piece);
                if (!st || !constraints.viable(states, *st)) continue;
                entry next{*st, e.cost + s.cost, e.cost + s.cost, length, static_cast<float>(drift),
                           static_cast<std::uint16_t>(s.piece), e.first, idx};
                if (window) {
                    float a = 0.0f;
                    const float* old = table.lags(idx);
                    for (std::size_t lag = 1; lag <= window; ++lag) {
                        float v = old[lag - 1];
                        if (history[lag - 1] != table.before_start) {
                            const std::uint32_t other = history[lag - 1];
                            v += static_cast<float>(kernel[other > s.piece ? other - s.piece : s.piece - other]);
                        }
                        new_lags[lag - 1] = v;
                        a = std::max(a, v);
                    }
                    next.total = next.cost + lim.beta * static_cast<double>(a);
                }
                // Always a later layer, even if rounding put l + w in the bucket of l (w >= q).
                const std::uint32_t at = table.offer(next, std::max(table.bucket_of(length), bucket + 1),
                                                     static_cast<std::uint64_t>(states.hash(next.state)));
                if (window && at != table.no_pred) {
                    std::copy(new_lags.begin(), new_lags.end(), table.lags(at));
                    new_recent[0] = s.piece16;
                    std::copy(history, history + window - 1, new_recent.begin() + 1);
                    std::copy(new_recent.begin(), new_recent.end(), table.recent(at));
                }
            }
        }
    }
    table.update_peak(policy_bytes(states));
    table.stats().candidates = candidates.size();
    return candidates;
}

// ---- phase 4: epsilon growth and the choice

/// The tolerance actually needed: epsilon grown by `growth` from eps0 until it admits the
/// candidate nearest to the target, never beyond eps_max (§3.6.3).
template <class Candidate>
double grown_epsilon(const std::vector<Candidate>& candidates, double eps0, double eps_max, double growth) {
    double d_min = std::numeric_limits<double>::infinity();
    for (const Candidate& c : candidates) d_min = std::min(d_min, c.distance);
    double eps = eps0;
    while (eps < d_min && eps < eps_max) eps = std::min(eps * growth, eps_max);
    return eps;
}

/// The cheapest candidate within eps (ties: nearer to the target, then the first met); nullptr if none.
template <class Candidate>
const Candidate* cheapest_within(const std::vector<Candidate>& candidates, double eps) {
    const Candidate* best = nullptr;
    for (const Candidate& c : candidates) {
        if (c.distance > eps) continue;
        if (!best || c.total < best->total || (c.total == best->total && c.distance < best->distance)) best = &c;
    }
    return best;
}

// ---- phase 5: backtracking

/// The pieces eta_0..eta_N of the run ending at `last`, by following the back pointers.
template <class State>
std::vector<std::size_t> backtrack(const sequence_table<State>& table, std::uint32_t last) {
    std::vector<std::size_t> pieces;
    for (std::uint32_t k = last; k != table.no_pred; k = table[k].pred) pieces.push_back(table[k].piece);
    std::reverse(pieces.begin(), pieces.end());
    return pieces;
}

/// Accumulated optimal offsets Delta_i along a sequence (Delta_0 = 0).
template <transition_cost_policy T>
std::vector<double> accumulated_offsets(const std::vector<std::size_t>& pieces, const T& transitions) {
    std::vector<double> offsets(pieces.size(), 0.0);
    for (std::size_t i = 1; i < pieces.size(); ++i) offsets[i] = offsets[i - 1] + transitions.offset(pieces[i - 1], pieces[i]);
    return offsets;
}
}  // namespace detail

// ---------------------------------------------------------------------------------------------
// The solver

/// Solves the sequence problem described in the file comment.
/// @param widths       n piece widths (mm), finite and > 0
/// @param transitions  n x n compatibility, costs D and offsets tau
/// @param states       state policy (mutable: it may memoise)
/// @param constraints  constraint policy
/// @param opt          target length, tolerances, offset range, autocorrelation, open/closed, limits
/// @param progress     called with the fraction of the length range processed
/// @throws invalid_input for malformed input or when the table would exceed opt.max_entries;
///         no_solution when no sequence meets the constraints within epsilon_max of the target.
template <transition_cost_policy T, sequence_state_policy P, class C, progress_callback F = no_progress>
    requires sequence_constraint_policy<C, P>
[[nodiscard]] sequence_result<typename P::state, typename P::cycle_summary> solve_sequence(
    std::span<const double> widths, const T& transitions, P& states, const C& constraints,
    const sequence_options& opt, F&& progress = {}) {
    using table_t = detail::sequence_table<typename P::state>;
    const detail::solve_limits lim = detail::check_inputs(widths, transitions, opt);
    if constexpr (requires { constraints.validate(states); }) constraints.validate(states);  // e.g. contradictory targets
    const auto succ = detail::successor_lists(transitions, lim.pieces);

    table_t table(widths, lim, opt.max_entries);
    detail::add_roots(table, widths, states, constraints, opt, lim);
    const auto candidates = detail::fill_layers(table, widths, transitions, succ, states, constraints, opt, lim, progress);
    if (candidates.empty())
        throw no_solution("sequence solver: no sequence of the " + std::to_string(lim.pieces) +
                          " pieces meets the constraints with a length within " + std::to_string(lim.epsilon_max) +
                          " mm of the target " + std::to_string(lim.target) + " mm" + (opt.closed ? " as a closed sequence" : ""));

    const double eps = detail::grown_epsilon(candidates, lim.epsilon, lim.epsilon_max, opt.epsilon_growth);
    const auto* best = detail::cheapest_within(candidates, eps);
    FABSYNTH_ASSERT(best != nullptr);

    sequence_result<typename P::state, typename P::cycle_summary> r;
    r.pieces = detail::backtrack(table, best->index);
    r.offsets = detail::accumulated_offsets(r.pieces, transitions);
    const auto& last = table[best->index];
    r.cost = best->cost;
    r.penalty = best->total - best->cost;
    r.length = last.length;
    r.epsilon = eps;
    r.state = last.state;
    r.cycle = best->cycle;
    r.stats = table.stats();
    return r;
}

/// Plain sequence assembly without state or constraints.
template <transition_cost_policy T>
[[nodiscard]] sequence_result<stateless::state, stateless::cycle_summary> solve_sequence(
    std::span<const double> widths, const T& transitions, const sequence_options& opt) {
    stateless s;
    return solve_sequence(widths, transitions, s, unconstrained{}, opt);
}

}  // namespace fabsynth::dp
