#pragma once
/// @file sequence_solver.hpp  Generic dynamic-programming solver for assembling a sequence of
/// pieces (Zhou et al. 2014, "Topology-constrained synthesis of vector patterns", §3.5-§3.7).
///
/// Problem. Pieces 0..n-1 have widths w_i > 0 (mm). Find a sequence eta_0..eta_N minimising
///   F(eta) = sum_i D(eta_i, eta_{i+1})            (+ D(eta_N, eta_0) for a closed curve)
/// subject to: every consecutive pair is compatible (transition policy); the run's state (state
/// policy, e.g. a topology descriptor) satisfies the constraint policy at the end; the length
/// l = sum w_{eta_i} is within epsilon of the target L, where epsilon starts at `epsilon` and grows
/// by `epsilon_growth` only while no valid sequence is found, never beyond `epsilon_max` (a request
/// met only farther from L is refused with no_solution).
///
/// Table. Sparse, keyed by (length bucket floor(l / q), last piece, state) (+ first piece on closed
/// curves); each entry keeps the cheapest run reaching its key, with its exact length, accumulated
/// offset Delta and a back pointer. Layers are filled in increasing length (every width >= q, so a
/// transition always moves to a later layer). Deviation from the paper, on purpose: the paper keys
/// by the *number* of pieces and stores the length in the entry, which can drop the only run of the
/// right length; keying by length makes the DP exact: when every width is a multiple of q, the
/// returned cost equals the brute-force optimum over all sequences of length <= L + epsilon_max
/// (with band_height = inf and autocorrelation_weight = 0; the tests check this). The default q is
/// the shortest width (exact for uniform slicing); with uneven widths, runs whose lengths fall in
/// one bucket compete, as all runs of one piece count do in the paper; a smaller q refines this at
/// a proportional cost in time and memory.
///
/// Heuristics kept from the paper (the result then is valid but may not be optimal):
///  - offset drift (§3.6.2): runs whose accumulated optimal offset Delta leaves (-H/2, H/2) are
///    dropped; only the cheapest run per key keeps its Delta.
///  - autocorrelation penalty (§3.7): beta * A(eta) is added to the cost of partial runs, with
///    A = max over lags j of sum_i exp(-|eta_i - eta_{i+j}| / sigma). The paper's formula lets
///    j = 0, where the sum is always the run length (it would dominate every other lag), so lags
///    start at 1; lags are limited to `autocorrelation_window` so an entry stores O(window) sums.
///  - closed curves: cycles are searched in the table with the first piece kept in the key; by
///    rotation, each cycle is generated once starting at its smallest piece index (costs and
///    topology are invariant under rotation).
///
/// Complexity: O(E * s) transitions for E table entries and s compatible successors per piece,
/// each O(1) expected (one state-policy extend, one hash probe) plus O(window) with beta > 0.
/// E <= (L + epsilon_max) / q * n * S (* n on closed curves) for S reachable states, usually far
/// fewer. Memory: ~48 bytes per entry (+ 6 * window with beta > 0) plus the open layers' hash tables;
/// the whole table is kept for backtracking. `max_entries` bounds it (invalid_input beyond).
///
/// Determinism: single-threaded; layers are processed in increasing length, entries in creation
/// order, successors in increasing piece index; a key keeps the first-created run among equal
/// costs. Nothing depends on hash-table iteration order, so results are bit-identical run to run.
///
/// Policies (C++20 concepts below): transition_cost_policy (D, compatibility, optimal offsets;
/// transition_table holds precomputed values, portal_transition_table computes §3.6.1's
/// D = alpha d_match + (1 - alpha) d_tangent), sequence_state_policy (how a run's state evolves;
/// topology::descriptor_policy, or `stateless`), sequence_constraint_policy (pruning and acceptance;
/// topology::constraints, or `unconstrained`).
///
/// Usage:
///   auto table = fabsynth::dp::portal_transition_table(piece_portals);        // §3.6.1, alpha = 0.8
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
/// (closed curves; nullopt = cannot close), hash(s) consistent with ==. Called once per
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

/// State policy with no state: plain sequence assembly (every run may end, every loop closes).
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

/// One side of a piece as the matching cost sees it (§3.3): the heights y (mm, along the band's
/// V axis, top to bottom, two endpoints per portal) and the boundary tangents g at those endpoints
/// (any non-zero length; normalised before use).
struct portal_side {
    std::vector<double> heights;
    std::vector<vec2> tangents;
};

/// Both sides of a piece.
struct piece_portals {
    portal_side left, right;
};

/// The three terms of §3.6.1 for piece j following piece i.
struct portal_match {
    double d_match = 0;    ///< min over tau of mean squared endpoint height difference (mm^2)
    double d_tangent = 0;  ///< sum_k |1 - g_r,i^k . g_l,j^k|
    double offset = 0;     ///< optimal tau: shift of j (mm) aligning its left endpoints on i's right ones
};

/// Matching terms between the right side of i and the left side of j (same endpoint count M).
/// tau minimising (1/M) sum (y_l,j - y_r,i + tau)^2 is the mean of y_r,i - y_l,j, and the minimum
/// is the variance of the differences. M = 0 gives zeros. Throws invalid_input on size mismatch,
/// non-finite values or zero tangents.
[[nodiscard]] inline portal_match match_portals(const portal_side& right_of_i, const portal_side& left_of_j) {
    const std::size_t m = right_of_i.heights.size();
    if (left_of_j.heights.size() != m)
        throw invalid_input("portal match: sides have " + std::to_string(m) + " and " +
                            std::to_string(left_of_j.heights.size()) + " portal endpoints");
    portal_match r;
    if (m == 0) return r;
    double mean = 0;
    for (std::size_t k = 0; k < m; ++k) mean += right_of_i.heights[k] - left_of_j.heights[k];
    mean /= static_cast<double>(m);
    double var = 0;
    for (std::size_t k = 0; k < m; ++k) {
        const double d = left_of_j.heights[k] - right_of_i.heights[k] + mean;
        var += d * d;
    }
    r.d_match = var / static_cast<double>(m);
    r.offset = mean;
    for (std::size_t k = 0; k < m; ++k) {
        const vec2 a = right_of_i.tangents[k], b = left_of_j.tangents[k];
        r.d_tangent += std::abs(1.0 - glm::dot(a, b) / (glm::length(a) * glm::length(b)));
    }
    return r;
}

/// Transition table of §3.6.1 over all pairs with equal endpoint counts (M_r,i == M_l,j):
/// D = alpha d_match + (1 - alpha) d_tangent (alpha = 0.8 in the paper), offset = optimal tau.
/// Throws invalid_input on malformed sides (height/tangent count mismatch, odd endpoint counts,
/// non-finite values, zero tangents) or alpha outside [0, 1]. O(n^2 M).
[[nodiscard]] inline transition_table portal_transition_table(std::span<const piece_portals> pieces,
                                                              double alpha = 0.8) {
    if (!(alpha >= 0.0 && alpha <= 1.0)) throw invalid_input("portal transition table: alpha must be in [0, 1]");
    auto check_side = [](const portal_side& s, std::size_t i, const char* which) {
        const std::string name = "portal transition table: piece " + std::to_string(i) + " " + which + " side";
        if (s.heights.size() != s.tangents.size())
            throw invalid_input(name + " has " + std::to_string(s.heights.size()) + " heights but " +
                                std::to_string(s.tangents.size()) + " tangents");
        if (s.heights.size() % 2 != 0) throw invalid_input(name + " has an odd number of portal endpoints");
        for (std::size_t k = 0; k < s.heights.size(); ++k) {
            if (!std::isfinite(s.heights[k])) throw invalid_input(name + ": height " + std::to_string(k) + " is not finite");
            if (!all_finite(s.tangents[k]) || glm::length(s.tangents[k]) == 0.0)
                throw invalid_input(name + ": tangent " + std::to_string(k) + " is zero or not finite");
        }
    };
    for (std::size_t i = 0; i < pieces.size(); ++i) check_side(pieces[i].left, i, "left"), check_side(pieces[i].right, i, "right");
    transition_table t(pieces.size());
    for (std::size_t i = 0; i < pieces.size(); ++i)
        for (std::size_t j = 0; j < pieces.size(); ++j) {
            if (pieces[i].right.heights.size() != pieces[j].left.heights.size()) continue;
            const portal_match m = match_portals(pieces[i].right, pieces[j].left);
            t.set(i, j, alpha * m.d_match + (1.0 - alpha) * m.d_tangent, m.offset);
        }
    return t;
}

// ---------------------------------------------------------------------------------------------
// Options and result

/// Options of solve_sequence (lengths in mm).
struct sequence_options {
    double target_length = 0;            ///< L > 0
    double epsilon = 0;                  ///< initial tolerance |l - L| <= epsilon; 0 = 0.05 L (§3.5)
    double epsilon_growth = 1.25;        ///< tolerance factor while nothing is found (§3.6.3), > 1
    double epsilon_max = 0;              ///< hard cap on the tolerance; 0 = 0.2 L
    double band_height = std::numeric_limits<double>::infinity();  ///< H: keep |Delta| < H / 2
    double autocorrelation_weight = 0;   ///< beta (§3.7); 0 = off
    double autocorrelation_sigma = 0.5;  ///< sigma of §3.7, > 0
    std::size_t autocorrelation_window = 8;   ///< lags 1..window enter A (>= 1)
    bool cyclic = false;                 ///< closed curve: the last piece connects back to the first
    std::vector<std::size_t> first_pieces{};  ///< open curves: allowed eta_0 (empty = any)
    std::vector<std::size_t> last_pieces{};   ///< open curves: allowed eta_N (empty = any)
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
    double cost = 0;                  ///< F(eta), including D(eta_N, eta_0) on closed curves
    double penalty = 0;               ///< beta * A(eta) (0 when beta = 0)
    double length = 0;                ///< sum of the widths (mm)
    double epsilon = 0;               ///< tolerance that was needed, <= epsilon_max
    State state{};                    ///< state of the run eta_0..eta_N
    std::optional<CycleSummary> cycle;  ///< closed curves: summary after closing the loop
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
}  // namespace detail

// ---------------------------------------------------------------------------------------------
// The solver

/// Solves the sequence problem described in the file comment.
/// @param widths       n piece widths (mm), finite and > 0
/// @param transitions  n x n compatibility, costs D and offsets tau
/// @param states       state policy (mutable: it may memoise)
/// @param constraints  constraint policy
/// @param opt          target length, tolerances, band height, autocorrelation, open/closed, limits
/// @param progress     called with the fraction of the length range processed
/// @throws invalid_input for malformed input or when the table would exceed opt.max_entries;
///         no_solution when no sequence meets the constraints within epsilon_max of the target.
template <transition_cost_policy T, sequence_state_policy P, class C, progress_callback F = no_progress>
    requires sequence_constraint_policy<C, P>
[[nodiscard]] sequence_result<typename P::state, typename P::cycle_summary> solve_sequence(
    std::span<const double> widths, const T& transitions, P& states, const C& constraints,
    const sequence_options& opt, F&& progress = {}) {
    using state_t = typename P::state;
    constexpr std::uint32_t no_pred = 0xffffffffu;
    const std::size_t n = widths.size();

    // ---- validate
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
    if (!(opt.band_height > 0.0)) throw invalid_input("sequence solver: band_height must be > 0 (may be infinite)");
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
    if (opt.cyclic && (!opt.first_pieces.empty() || !opt.last_pieces.empty()))
        throw invalid_input("sequence solver: first_pieces / last_pieces apply to open curves only");
    if (opt.max_entries == 0 || opt.max_entries >= no_pred) throw invalid_input("sequence solver: max_entries out of range");
    if constexpr (requires { constraints.validate(states); }) constraints.validate(states);  // e.g. contradictory targets

    // ---- successor lists (ascending piece index: the deterministic tie-break order)
    struct successor {
        std::uint32_t piece;
        std::uint16_t piece16;
        double cost, offset;
    };
    std::vector<std::vector<successor>> succ(n);
    std::vector<std::uint8_t> is_last(n, opt.last_pieces.empty() ? 1 : 0);
    for (std::size_t i : opt.last_pieces) is_last[i] = 1;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            if (!transitions.compatible(i, j)) continue;
            const double c = transitions.cost(i, j), o = transitions.offset(i, j);
            if (!(std::isfinite(c) && c >= 0.0) || !std::isfinite(o))
                throw invalid_input("sequence solver: transition (" + std::to_string(i) + ", " + std::to_string(j) +
                                    ") has a non-finite or negative cost, or a non-finite offset");
            succ[i].push_back({static_cast<std::uint32_t>(j), static_cast<std::uint16_t>(j), c, o});
        }

    // ---- table
    struct entry {
        state_t state;
        double cost;    // F of the run
        double total;   // F + beta * A: what the DP minimises per key
        double length;  // exact sum of widths
        float drift;    // accumulated offset Delta (only compared against H / 2)
        std::uint16_t piece, first;
        std::uint32_t pred;
    };
    detail::chunked_store<entry> entries;
    const std::size_t window = beta > 0.0 ? opt.autocorrelation_window : 0;
    detail::chunked_store<float> lags(std::max<std::size_t>(window, 1));  // lag sums per entry (beta > 0)
    // Last `window` pieces of each entry's run, most recent first (no pointer chasing per transition).
    detail::chunked_store<std::uint16_t> recent(std::max<std::size_t>(window, 1));
    std::vector<double> kernel;  // exp(-d / sigma) for index distances d
    if (window) {
        kernel.resize(n);
        for (std::size_t d = 0; d < n; ++d) kernel[d] = std::exp(-static_cast<double>(d) / opt.autocorrelation_sigma);
    }
    const double half_band = opt.band_height / 2.0;
    // Open layers live in a ring indexed by bucket: a transition moves at most ceil(max width / q)
    // buckets ahead, so ring_size slots never collide.
    double max_w = 0;
    for (double w : widths) max_w = std::max(max_w, w);
    const std::uint64_t last_bucket = static_cast<std::uint64_t>(std::floor(l_max / q));
    const double ring_span = std::ceil(max_w / q) + 2.0;
    if (ring_span > double(1u << 16) || double(last_bucket) > double(1u << 27))
        throw invalid_input("sequence solver: too many length buckets (longest width / length_resolution = " +
                            std::to_string(max_w / q) + ", target / length_resolution = " + std::to_string(l_max / q) +
                            "); raise length_resolution");
    const auto ring_size = static_cast<std::size_t>(std::min(ring_span, double(last_bucket) + 2.0));
    std::vector<detail::index_table> ring(ring_size);
    std::size_t pending_bytes = 0;
    sequence_stats stats;
    auto bucket_of = [q](double l) { return static_cast<std::uint64_t>(std::floor(l / q)); };
    auto key_hash = [&](std::uint32_t piece, std::uint32_t first, const state_t& s) {
        return static_cast<std::uint32_t>(hash64(static_cast<std::uint64_t>(states.hash(s)), piece, first));
    };
    auto update_peak = [&] {
        const std::size_t bytes = entries.memory_bytes() + (window ? lags.memory_bytes() + recent.memory_bytes() : 0) + pending_bytes +
                                  ring.capacity() * sizeof(detail::index_table) + detail::policy_bytes(states);
        stats.peak_bytes = std::max(stats.peak_bytes, bytes);
    };
    // Inserts or improves the entry for (bucket, piece, first, state). Returns its index or no_pred.
    auto offer = [&](const entry& e, std::uint64_t bucket) -> std::uint32_t {
        detail::index_table& layer = ring[bucket % ring_size];
        const std::uint32_t h = key_hash(e.piece, e.first, e.state);
        const std::uint32_t found = layer.find(h, [&](std::uint32_t idx) {
            const entry& o = *entries[idx];
            return o.piece == e.piece && o.first == e.first && o.state == e.state;
        });
        if (found != detail::index_table::none) {
            // Strictly cheaper wins; on ties the earlier-created run stays (deterministic order).
            if (e.total < entries[found]->total) {
                *entries[found] = e;
                return found;
            }
            return no_pred;
        }
        if (entries.size() >= opt.max_entries)
            throw invalid_input("sequence solver: the DP table exceeds max_entries = " + std::to_string(opt.max_entries) +
                                " (target length " + std::to_string(L) + " mm, length resolution " + std::to_string(q) +
                                " mm); raise max_entries or length_resolution");
        const std::size_t before = layer.memory_bytes();
        const auto idx = static_cast<std::uint32_t>(entries.push_back(e));
        if (window) lags.push_back(0.0f), recent.push_back(0xffff);
        layer.insert(h, idx);
        pending_bytes += layer.memory_bytes() - before;
        ++stats.entries;
        return idx;
    };

    // ---- roots: one-piece runs
    for (std::size_t s = 0; s < n; ++s) {
        if (!opt.cyclic && !opt.first_pieces.empty() &&
            std::find(opt.first_pieces.begin(), opt.first_pieces.end(), s) == opt.first_pieces.end())
            continue;
        if (widths[s] > l_max) continue;
        std::optional<state_t> st = states.start(s);
        if (!st || !constraints.viable(states, *st)) continue;
        const std::uint32_t at = offer(entry{*st, 0.0, 0.0, widths[s], 0.0f, static_cast<std::uint16_t>(s),
                                             static_cast<std::uint16_t>(opt.cyclic ? s : 0), no_pred},
                                       bucket_of(widths[s]));
        if (window && at != no_pred) recent[at][0] = static_cast<std::uint16_t>(s);
    }

    // ---- fill layers in increasing length
    struct candidate {
        std::uint32_t index;
        double distance, total, cost;
        std::optional<typename P::cycle_summary> cycle;
    };
    std::vector<candidate> candidates;
    std::vector<std::uint16_t> new_recent(window);
    std::vector<float> new_lags(window);
    for (std::uint64_t bucket = 0; bucket <= last_bucket + 1; ++bucket) {
        detail::index_table layer;
        layer.swap(ring[bucket % ring_size]);
        if (layer.size() == 0) continue;
        pending_bytes -= layer.memory_bytes();
        // Creation order (entry indices only grow): the deterministic processing order.
        const std::vector<std::uint32_t> members = layer.indices();
        layer = detail::index_table();
        ++stats.layers;
        update_peak();
        report_progress(progress, std::min(1.0, static_cast<double>(bucket) / static_cast<double>(last_bucket + 1)),
                        "sequence DP");
        for (const std::uint32_t idx : members) {
            const entry e = *entries[idx];  // copy: an improvement below may not alias it, but be safe
            const double distance = std::abs(e.length - L);
            if (distance <= eps_max) {
                if (!opt.cyclic) {
                    if (is_last[e.piece] && constraints.accept_open(states, e.state))
                        candidates.push_back({idx, distance, e.total, e.cost, std::nullopt});
                } else if (transitions.compatible(e.piece, e.first)) {
                    if (auto z = states.close(e.state); z && constraints.accept_cycle(states, *z)) {
                        const double closing = transitions.cost(e.piece, e.first);
                        candidates.push_back({idx, distance, e.total + closing, e.cost + closing, *z});
                    }
                }
            }
            const std::uint16_t* history = window ? recent[idx] : nullptr;  // 0xffff = before the start
            for (const successor& s : succ[e.piece]) {
                if (opt.cyclic && s.piece < e.first) continue;  // cycles start at their smallest piece
                const double length = e.length + widths[s.piece];
                if (length > l_max) continue;
                ++stats.transitions;
                const double drift = static_cast<double>(e.drift) + s.offset;
                if (!(std::abs(drift) < half_band)) continue;
                std::optional<state_t> st = states.extend(e.state, s.piece);
                if (!st || !constraints.viable(states, *st)) continue;
                entry next{*st, e.cost + s.cost, e.cost + s.cost, length, static_cast<float>(drift),
                           static_cast<std::uint16_t>(s.piece), e.first, idx};
                if (window) {
                    float a = 0.0f;
                    const float* old = lags[idx];
                    for (std::size_t lag = 1; lag <= window; ++lag) {
                        float v = old[lag - 1];
                        if (history[lag - 1] != 0xffff) {
                            const std::uint32_t other = history[lag - 1];
                            v += static_cast<float>(kernel[other > s.piece ? other - s.piece : s.piece - other]);
                        }
                        new_lags[lag - 1] = v;
                        a = std::max(a, v);
                    }
                    next.total = next.cost + beta * static_cast<double>(a);
                }
                // Always a later layer, even if rounding put l + w in the bucket of l (w >= q).
                const std::uint32_t at = offer(next, std::max(bucket_of(length), bucket + 1));
                if (window && at != no_pred) {
                    std::copy(new_lags.begin(), new_lags.end(), lags[at]);
                    new_recent[0] = s.piece16;
                    std::copy(history, history + window - 1, new_recent.begin() + 1);
                    std::copy(new_recent.begin(), new_recent.end(), recent[at]);
                }
            }
        }
    }
    update_peak();
    stats.candidates = candidates.size();

    // ---- choose: smallest grown epsilon that admits a candidate, then the cheapest one
    if (candidates.empty())
        throw no_solution("sequence solver: no sequence of the " + std::to_string(n) +
                          " pieces meets the constraints with a length within " + std::to_string(eps_max) +
                          " mm of the target " + std::to_string(L) + " mm" +
                          (opt.cyclic ? " as a closed loop" : ""));
    double d_min = std::numeric_limits<double>::infinity();
    for (const candidate& c : candidates) d_min = std::min(d_min, c.distance);
    double eps = eps0;
    while (eps < d_min && eps < eps_max) eps = std::min(eps * opt.epsilon_growth, eps_max);
    const candidate* best = nullptr;
    for (const candidate& c : candidates) {
        if (c.distance > eps) continue;
        if (!best || c.total < best->total || (c.total == best->total && c.distance < best->distance)) best = &c;
    }
    FABSYNTH_ASSERT(best != nullptr);

    // ---- backtrack
    sequence_result<state_t, typename P::cycle_summary> r;
    for (std::uint32_t k = best->index; k != no_pred; k = entries[k]->pred) r.pieces.push_back(entries[k]->piece);
    std::reverse(r.pieces.begin(), r.pieces.end());
    r.offsets.assign(r.pieces.size(), 0.0);
    for (std::size_t i = 1; i < r.pieces.size(); ++i)
        r.offsets[i] = r.offsets[i - 1] + transitions.offset(r.pieces[i - 1], r.pieces[i]);
    const entry& last = *entries[best->index];
    r.cost = best->cost;
    r.penalty = best->total - best->cost;
    r.length = last.length;
    r.epsilon = eps;
    r.state = last.state;
    r.cycle = best->cycle;
    r.stats = stats;
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
