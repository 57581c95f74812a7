// SPDX-License-Identifier: MIT
#pragma once
/// @file synthesis.hpp  Topology-constrained synthesis of a vector pattern along a band, in band
/// coordinates (Zhou et al. 2014, §3.5-§4), and rectangles by synthesizing twice (§6.2).
///
/// Phases of synthesize_along(exemplar, options), each a function in detail:: that can be called
/// and tested alone; synthesize_along is check_options + prepare_pieces + the retry driver
/// synthesize_prepared, which runs phases 2-7 until the result validates:
///  1. prepare_pieces: slice the exemplar into pieces (§5): topology-driven Reeb slicing by default
///     (§5.2), with the thin-portal filter (§5.2.1), or uniform slicing (§5.1); add the band-end
///     copies of P_0 and P_t for open curves (see below).
///  2. junction_costs: the DP's transition table, D = alpha d_match + (1 - alpha) d_tangent
///     (alpha = 0.8) by vector_pattern/portal_cost.hpp, the one place that cost is computed.
///  3. solve_piece_sequence: the piece sequence eta by dp::solve_sequence with topology descriptors
///     (§3.4-§3.6): epsilon starting at 0.05 L and growing by 1.25 while nothing is found, never
///     beyond epsilon_max (0.2 L by default: a request met only farther from L is refused with
///     no_solution), drift bound H, optional autocorrelation penalty beta (§3.7). Open curves
///     start with P_0 and end with P_t; closed curves search a closed sequence (a cycle of pieces,
///     the closing junction included) and set delta_0 = 0.
///  4. piece_offsets: offsets delta by the weighted least squares of §4.1 (vector_pattern/offsets.hpp).
///  5. junction_targets, deform_pieces: gap stitching by LRI deformation of the piece boundaries
///     (§4.2, vector_pattern/stitching.hpp): every piece is first stretched along u by L / l
///     (l = sum of the chosen widths), so the pattern spans [0, L] exactly and the deformation only
///     closes the portal mismatch of each junction. (The paper lets the LRI deformation absorb
///     L - l at the junctions; LRI keeps edge lengths, so a compressed sequence buckles and its
///     chains cross their neighbours.)
///  6. merge_band: final contours by a Clipper union (§4.3, vector_pattern/contours.hpp).
///  7. validate_band: pieces do not overlap and no hole leaves its outline (merged area = sum of
///     signed ring areas up to Clipper rounding, 1e-8 relative), every ring simple, and the
///     components/holes counted on the final polygons (glued at the seam for closed curves) equal
///     to the request. A failure is retried (retry_state, see "Validation failures" below); after
///     max_attempts it is a solver_error (that would be a bug; a wrong pattern is never returned).
///
/// Closed, and closed loop (two different things):
///  - `closed` (synthesis_options, band_topology, solve_offsets, dp::sequence_options): the curve
///    is a closed curve, so the band is periodic in u with period L and its two ends u = 0 and
///    u = L are glued; the piece sequence is closed too (its last piece is followed by its first).
///    The opposite is *open*: two free band ends.
///  - `closed_loop` (synthesis_options, topology::constraints): on a closed curve, some component
///    of the pattern winds around the whole loop (a ring, Fig. 6, top); a closed band can be
///    connected end to end without that. band_counts::rings counts such components.
///
/// Band coordinates: u along the curve in [0, L]; v across, v = y - y_c where y_c is the vertical
/// centre of the exemplar's bounding box (no flip: v grows where the exemplar's y grows, e.g. down
/// on screen for SVG input). Orientation as vector_pattern::exemplar: outer rings positive shoelace area,
/// holes negative, in (u, v).
///
/// Decisions where the paper is silent (documented here on purpose):
///  - Band ends of open curves. The bundled bands are cut through material at both ends, so P_0 has
///    portals on its left and P_t on its right. For an open curve those are the pattern's own flat
///    ends, not open connections: the DP uses copies of P_0 and P_t whose outer-end portals are
///    removed from the descriptor (so "no open portal" and the counts refer to the finished pattern).
///  - Reeb grouping distance. The paper's 0.2 W chains all events of a repetitive band into one group
///    (no cut); by default the distance starts at 0.2 W and is halved until the slicing has at least
///    `min_pieces` pieces (an exemplar without topology events, e.g. one simple zigzag, falls back to
///    uniform slicing with pieces half the exemplar height wide).
///  - Seed (§3.7 variety). seed = 0 uses the paper's costs; another seed multiplies each D(i, j) by
///    1 + seed_variation * h(seed, i, j) with h a counter-based hash in [0, 1): different seeds give
///    different, equally valid patterns, and the same seed gives byte-identical output.
///  - Rings with no portal (holes, islands) are translated with the chains nearest to them (see
///    stitching.hpp).
///  - Validation failures. The junctions to blame are located (blamed_junctions) and exactly those
///    transitions are banned in the next DP pass (same costs); costs are perturbed by derived seeds
///    only when no junction is to blame, or when the bans leave no sequence (they are then dropped).
///    The retries are a safety net; how often they are needed is measured by the tests' sweep and
///    benchmarks/README.md.
///
/// Usage:
///   auto ex = fabsynth::vector_pattern::exemplar_from_svg(fabsynth::io::read_svg("data/vector/vine.svg"));
///   auto r = fabsynth::vector_pattern::synthesize_along(ex, {.length = 700, .components = 1, .holes = 12});
///   // r.polygons in (u, v), u in [0, 700]; r.sequence, r.offsets; r.dp_seconds
///   auto rect = fabsynth::vector_pattern::synthesize_rectangle(ex, {.width = 300, .height = 200, .components = 1});
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/dp/sequence_solver.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/vector_pattern/contours.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"
#include "fabsynth/vector_pattern/offsets.hpp"
#include "fabsynth/vector_pattern/pieces.hpp"
#include "fabsynth/vector_pattern/portal_cost.hpp"
#include "fabsynth/vector_pattern/reeb_slicing.hpp"
#include "fabsynth/vector_pattern/stitching.hpp"
#include "fabsynth/topology/descriptor.hpp"

namespace fabsynth::vector_pattern {

/// How the exemplar is sliced (§5).
enum class slicing_method {
    reeb,    ///< §5.2 topology-driven (default)
    uniform  ///< §5.1 uniform_lines equally spaced lines
};

/// Options of synthesize_along (lengths in the exemplar's units, mm by convention).
struct synthesis_options {
    double length = 0.0;        ///< target length L along u (> 0)
    double band_height = 0.0;   ///< H: pieces slide by delta in (-H/2, H/2); 0 = the exemplar's height
    bool closed = false;        ///< closed curve: the band is periodic in u with period L (see the file comment)
    std::optional<std::uint32_t> components{};  ///< exact number of connected components (glued, if closed)
    std::optional<std::uint32_t> holes{};       ///< exact number of holes
    bool closed_loop = false;   ///< closed curves: some component must wind around the loop (Fig. 6; file comment)
    std::uint64_t seed = 0;     ///< variety (see the file comment); same seed -> identical result
    double seed_variation = 0.25;  ///< relative cost perturbation for seed != 0, in [0, 1]

    slicing_method slicing = slicing_method::reeb;
    double group_distance = 0.0;   ///< Reeb grouping distance; 0 = automatic (see the file comment)
    std::size_t min_pieces = 8;    ///< automatic grouping: fewest pieces wanted
    std::size_t uniform_lines = 0; ///< uniform slicing: t lines (0 = the whole exemplar is one piece)
    double min_portal_width = 0.0; ///< §5.2.1 thin-portal threshold (Reeb slicing)

    double alpha = 0.8;            ///< §3.6.1 weight of d_match
    double beta = 0.0;             ///< §3.7 autocorrelation weight (0 = off)
    double sigma = 0.5;            ///< §3.7 sigma
    double epsilon = 0.0;          ///< initial length tolerance; 0 = 0.05 L (§3.5)
    double epsilon_max = 0.0;      ///< largest tolerance; 0 = 0.2 L
    std::size_t max_entries = std::size_t{1} << 22;  ///< DP table limit (bounded time and memory)
    bool optimize_offsets = true;  ///< false: every delta = 0 (pieces stay on their exemplar rows)
    std::size_t max_attempts = 16; ///< DP + stitching passes before solver_error (>= 1; see synthesize_along)
};

/// Result in band coordinates (see the file comment).
struct synthesis_result {
    std::vector<polygon_with_holes> polygons;  ///< final geometry, u in [0, L]
    std::vector<std::size_t> sequence;         ///< chosen pieces eta (indices into the sliced pieces)
    std::vector<double> offsets;               ///< final delta per placed piece (mm)
    std::size_t input_pieces = 0;              ///< pieces the exemplar was sliced into
    double dp_seconds = 0.0;                   ///< wall time of the DP
    std::size_t dp_peak_bytes = 0;             ///< peak memory of the DP table
    std::size_t dp_entries = 0;                ///< DP table entries
    double cost = 0.0;                         ///< F(eta) (+ penalty)
    double achieved_length = 0.0;              ///< l = sum of piece widths before stitching
    double epsilon = 0.0;                      ///< tolerance that was needed
    std::uint32_t components = 0, holes = 0;   ///< counted on the final polygons (glued, if closed)
    std::uint32_t rings = 0;                   ///< closed curves: components winding around the loop
    double v_centre = 0.0;                     ///< exemplar y mapped to v = 0
    std::vector<double> cuts;                  ///< slicing positions used
    std::size_t attempts = 0;                  ///< DP + geometry passes needed (see max_attempts)
};

namespace detail {

/// Stitched geometry that does not realise the DP's topology (retried, see synthesize_along).
class geometry_mismatch : public solver_error {
public:
    using solver_error::solver_error;
};

inline void check_options(const exemplar& ex, const synthesis_options& o) {
    if (ex.polygons.empty() || ex.bounds.empty() || !(ex.width() > 0.0) || !(ex.height() > 0.0))
        throw invalid_input("synthesize_along: empty or degenerate exemplar");
    if (!(std::isfinite(o.length) && o.length > 0.0))
        throw invalid_input("synthesize_along: length must be finite and > 0, got " + std::to_string(o.length));
    if (!(o.band_height >= 0.0) || std::isnan(o.band_height))
        throw invalid_input("synthesize_along: band_height must be >= 0 (0 = exemplar height), got " + std::to_string(o.band_height));
    if (o.components && *o.components == 0)
        throw invalid_input("synthesize_along: components = 0 asks for an empty pattern; use >= 1");
    if (o.closed_loop && !o.closed) throw invalid_input("synthesize_along: closed_loop needs a closed curve");
    if (!(o.alpha >= 0.0 && o.alpha <= 1.0)) throw invalid_input("synthesize_along: alpha must be in [0, 1]");
    if (!(o.seed_variation >= 0.0 && o.seed_variation <= 1.0)) throw invalid_input("synthesize_along: seed_variation must be in [0, 1]");
    if (!(std::isfinite(o.group_distance) && o.group_distance >= 0.0))
        throw invalid_input("synthesize_along: group_distance must be finite and >= 0");
    if (!(std::isfinite(o.min_portal_width) && o.min_portal_width >= 0.0))
        throw invalid_input("synthesize_along: min_portal_width must be finite and >= 0");
    if (o.min_pieces < 1 || o.min_pieces > 4096) throw invalid_input("synthesize_along: min_pieces must be in [1, 4096]");
    if (o.max_attempts < 1 || o.max_attempts > 64) throw invalid_input("synthesize_along: max_attempts must be in [1, 64]");
    if (o.uniform_lines > 4096) throw invalid_input("synthesize_along: uniform_lines must be <= 4096");
}

/// Cut positions for the options (see the file comment).
inline std::vector<double> choose_cuts(const exemplar& ex, const synthesis_options& o) {
    if (o.slicing == slicing_method::uniform) return uniform_cuts(ex, o.uniform_lines);
    if (o.group_distance > 0.0)
        return reeb_slicing(ex, {.group_distance = o.group_distance, .min_portal_width = o.min_portal_width}).cuts;
    double g = 0.2 * ex.width();
    for (int k = 0; k < 16; ++k, g *= 0.5) {
        const reeb_result r = reeb_slicing(ex, {.group_distance = g, .min_portal_width = o.min_portal_width});
        if (r.events.empty()) break;
        if (r.cuts.size() + 1 >= o.min_pieces) return r.cuts;
    }
    // No topology event (or too few): uniform pieces about half the exemplar height wide.
    const double t = std::clamp(std::round(ex.width() / (0.5 * ex.height())) - 1.0, double(o.min_pieces) - 1.0, 256.0);
    return uniform_cuts(ex, static_cast<std::size_t>(t));
}

/// Copy of a piece descriptor with one or both outer sides removed (band ends of open curves).
inline topology::descriptor strip_sides(const piece& p, bool strip_left, bool strip_right) {
    std::vector<std::uint32_t> l, r;
    std::vector<char> touches(p.polygons.size(), 0);
    if (!strip_left)
        for (const portal& q : p.left) l.push_back(q.component), touches[q.component] = 1;
    if (!strip_right)
        for (const portal& q : p.right) r.push_back(q.component), touches[q.component] = 1;
    const auto enclosed = static_cast<std::uint32_t>(std::count(touches.begin(), touches.end(), 0));
    return topology::descriptor(l, r, enclosed, p.holes());
}

inline vec2 mean_tangent(vec2 a, vec2 b) {
    const vec2 s = a + b;
    const double l = glm::length(s);
    return l > 1e-12 ? s / l : a;
}

/// Junctions to blame for a stitched geometry that failed validation. rings[i] belongs to placed
/// piece owner[i] (0..placed-1); junction k joins placed pieces k and k+1 (k + 1 = 0 for the
/// closing junction of a closed curve). A piece whose own rings are not simple, overlap each other
/// or leave [0, L] blames the junction(s) on its sides; two pieces whose material overlaps blame the
/// junctions between them (the shorter way round for a closed curve). Empty when no piece-local
/// defect is found (e.g. a topology mismatch of otherwise clean pieces).
inline std::vector<std::size_t> blamed_junctions(const std::vector<ring2>& rings, const std::vector<std::size_t>& owner,
                                                 std::size_t placed, bool closed, double length, const clip_grid& grid,
                                                 double tolerance) {
    const std::size_t junctions = closed ? placed : placed - 1;
    std::vector<char> blamed(junctions, 0);
    auto blame_sides = [&](std::size_t k) {
        if (k < junctions) blamed[k] = 1;                        // right side of piece k
        if (k > 0) blamed[k - 1] = 1;                            // left side
        else if (closed && junctions > 0) blamed[junctions - 1] = 1;
    };
    std::vector<std::vector<ring2>> own(placed);
    for (std::size_t i = 0; i < rings.size(); ++i) own[owner[i]].push_back(rings[i]);
    std::vector<box2> box(placed);
    for (std::size_t k = 0; k < placed; ++k) {
        double sum = 0.0;
        bool simple = true;
        for (const ring2& r : own[k]) {
            sum += signed_area(r);
            simple = simple && is_simple(r);
            for (const vec2& q : r) box[k].extend(q);
        }
        if (!simple || std::abs(area(merge_contours(own[k], length, grid)) - sum) > tolerance) blame_sides(k);
    }
    for (std::size_t a = 0; a < placed; ++a)
        for (std::size_t b = a + 1; b < placed; ++b) {
            if (!box[a].intersects(box[b])) continue;
            const double shared = area(polygon_boolean(clip_op::intersection, own[a], fill_rule::nonzero, own[b],
                                                       fill_rule::nonzero, grid, false));
            if (!(shared > tolerance)) continue;
            // Junctions a..b-1 (forward) or b..a-1 through the seam (closed curves), the shorter way.
            const bool forward = !closed || (b - a) <= placed - (b - a);
            if (forward)
                for (std::size_t k = a; k < b; ++k) blamed[k] = 1;
            else
                for (std::size_t k = b; k != a; k = (k + 1) % placed) blamed[k] = 1;
        }
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < junctions; ++k)
        if (blamed[k]) out.push_back(k);
    return out;
}

// ---------------------------------------------------------------------------------------------
// Phases of synthesize_along, in order. Each one is a function of the previous phases' results.

/// A piece of the DP's alphabet: an original piece, or (open curves) a band-end copy of P_0 or P_t
/// with its outer side removed from the descriptor (see the file comment).
struct dp_piece {
    std::size_t original;  ///< index into the sliced pieces
    bool strip_left, strip_right;
};

/// Phase 1 (prepare_pieces): the sliced exemplar and the DP's view of it. DP indices run over
/// `dp`; `widths`, `descriptors` are per DP piece; `first` / `last` (open curves) are the DP
/// pieces allowed at the two ends.
struct prepared_pieces {
    std::vector<double> cuts;                       ///< slicing positions (mm)
    std::vector<piece> pieces;                      ///< P_0..P_t
    std::vector<dp_piece> dp;                       ///< the originals, then the band-end copies
    std::vector<double> widths;                     ///< width of every DP piece (mm)
    std::vector<topology::descriptor> descriptors;  ///< descriptor of every DP piece
    std::vector<std::size_t> first, last;           ///< open curves: allowed eta_0 / eta_N
    double v_centre = 0.0;                          ///< exemplar y mapped to v = 0
    double band_height = 0.0;                       ///< H (the option, or the exemplar's height)
};

/// Phase 1: slices the exemplar (choose_cuts, slice) and builds the DP pieces: the originals, plus
/// for open curves the band-end copies of P_0 and P_t (one copy stripped on both sides when the
/// exemplar is one piece).
[[nodiscard]] inline prepared_pieces prepare_pieces(const exemplar& ex, const synthesis_options& opt) {
    prepared_pieces pp;
    pp.cuts = choose_cuts(ex, opt);
    pp.pieces = slice(ex, pp.cuts);
    pp.v_centre = 0.5 * (ex.bounds.lo.y + ex.bounds.hi.y);
    pp.band_height = opt.band_height > 0.0 ? opt.band_height : ex.height();
    const std::size_t n = pp.pieces.size();
    for (std::size_t i = 0; i < n; ++i) pp.dp.push_back({i, false, false});
    if (!opt.closed) {
        if (n == 1) {
            pp.dp.push_back({0, true, true});
            pp.first = pp.last = {n};
        } else {
            pp.dp.push_back({0, true, false});
            pp.dp.push_back({n - 1, false, true});
            pp.first = {n};
            pp.last = {n + 1};
        }
    }
    for (const dp_piece& d : pp.dp) {
        const piece& p = pp.pieces[d.original];
        pp.widths.push_back(p.width());
        pp.descriptors.push_back(d.strip_left || d.strip_right ? strip_sides(p, d.strip_left, d.strip_right) : p.descriptor());
    }
    return pp;
}

/// DP transitions (i, j) excluded from an attempt.
using transition_set = std::set<std::pair<std::size_t, std::size_t>>;

/// Cost perturbation of one attempt: seed 0 = the paper's costs (see the file comment).
struct cost_variation {
    std::uint64_t seed = 0;
    double variation = 0.0;
};

/// Phase 2: the DP's transition table over the DP pieces: portal_cost (portal_cost.hpp) for every
/// pair with matching endpoint counts, except transitions out of a right band end, into a left
/// band end, or banned; with seed != 0 each cost is multiplied by 1 + variation * h(seed, i, j).
[[nodiscard]] inline dp::transition_table junction_costs(const prepared_pieces& pp, const synthesis_options& opt,
                                                         const transition_set& banned, cost_variation cv) {
    const std::size_t nd = pp.dp.size();
    dp::transition_table table(nd);
    for (std::size_t i = 0; i < nd; ++i) {
        if (pp.dp[i].strip_right) continue;  // nothing follows a right band end
        const portal_side ri = portal_side_of(pp.pieces[pp.dp[i].original], piece_side::right);
        for (std::size_t j = 0; j < nd; ++j) {
            if (pp.dp[j].strip_left) continue;  // nothing precedes a left band end
            if (banned.count({i, j})) continue;
            const portal_side lj = portal_side_of(pp.pieces[pp.dp[j].original], piece_side::left);
            if (ri.heights.size() != lj.heights.size()) continue;
            const portal_transition t = portal_cost(ri, lj, opt.alpha);
            double cost = t.cost;
            if (cv.seed != 0) cost *= 1.0 + cv.variation * hash_uniform(cv.seed, pp.dp[i].original, pp.dp[j].original);
            table.set(i, j, cost, t.offset);
        }
    }
    return table;
}

/// What dp::solve_sequence returns for descriptor states.
using sequence_solution = dp::sequence_result<topology::descriptor_policy::state, topology::loop_closure>;

/// Phase 3 output: the DP's sequence (DP indices) and the wall time it took.
struct chosen_sequence {
    sequence_solution solution;
    double seconds = 0.0;
};

/// Phase 3: the piece sequence eta by dp::solve_sequence with topology descriptors (§3.4-§3.6):
/// the topology request, length L within epsilon..epsilon_max, drift bound H (off without offset
/// optimisation), autocorrelation beta, open (band ends first / last) or closed. Throws
/// no_solution when no sequence meets the request.
[[nodiscard]] inline chosen_sequence solve_piece_sequence(const prepared_pieces& pp, const dp::transition_table& table,
                                                          const synthesis_options& opt, const progress_span& progress = {}) {
    const topology::constraints want{opt.components, opt.holes, opt.closed_loop};
    auto policy = topology::descriptor_policy::for_constraints(pp.descriptors, want);
    dp::sequence_options so;
    so.target_length = opt.length;
    so.epsilon = opt.epsilon;
    so.epsilon_max = opt.epsilon_max;
    so.offset_range = opt.optimize_offsets ? pp.band_height : std::numeric_limits<double>::infinity();
    so.autocorrelation_weight = opt.beta;
    so.autocorrelation_sigma = opt.sigma;
    so.closed = opt.closed;
    so.first_pieces = pp.first;
    so.last_pieces = pp.last;
    so.max_entries = opt.max_entries;
    const auto t0 = std::chrono::steady_clock::now();
    chosen_sequence c{dp::solve_sequence(std::span<const double>(pp.widths), table, policy, want, so, progress), 0.0};
    c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return c;
}

/// Phase 4 (§4.1): offsets delta of the placed pieces `placed` (DP indices) by the weighted least
/// squares of offsets.hpp: tau = the table's optimal offset of each junction, weight = the portal
/// endpoints on its left piece's right side. All zero without offset optimisation.
[[nodiscard]] inline std::vector<double> piece_offsets(const prepared_pieces& pp, const dp::transition_table& table,
                                                       const std::vector<std::size_t>& placed, const synthesis_options& opt) {
    const std::size_t N1 = placed.size();
    std::vector<double> tau, weight;
    const std::size_t junctions = opt.closed ? N1 : N1 - 1;
    for (std::size_t k = 0; k < junctions; ++k) {
        const std::size_t a = placed[k], b = placed[(k + 1) % N1];
        tau.push_back(table.offset(a, b));
        weight.push_back(static_cast<double>(pp.pieces[pp.dp[a].original].heights(piece_side::right).size()));
    }
    std::vector<double> delta(N1, 0.0);
    if (opt.optimize_offsets) delta = solve_offsets(tau, weight, opt.closed);
    return delta;
}

/// Phase 5a output: where every placed piece goes and what its portal endpoints must meet.
struct stitch_targets {
    std::vector<double> u;  ///< u of the junctions: piece k spans [u[k], u[k + 1]], u[0] = 0, u[N+1] = L
    double u_scale = 1.0;   ///< L / l: every piece is stretched along u by this
    std::vector<std::vector<endpoint_target>> left, right;  ///< per placed piece, per portal endpoint
};

/// Phase 5a (§4.2): junction positions and endpoint targets. The junctions are spread by the
/// stretch L / l (l = achieved length); each junction's targets are the averages of the two
/// matching endpoints (offsets applied, v = y - v_centre) and of their tangents, stretched alike;
/// the two ends of an open curve keep the band-end pieces' own endpoints at u = 0 and u = L.
[[nodiscard]] inline stitch_targets junction_targets(const prepared_pieces& pp, const std::vector<std::size_t>& placed,
                                                     const std::vector<double>& delta, double achieved_length,
                                                     const synthesis_options& opt) {
    const double L = opt.length;
    const std::size_t N1 = placed.size();
    const std::size_t junctions = opt.closed ? N1 : N1 - 1;
    stitch_targets st;
    st.u.assign(N1 + 1, 0.0);
    {
        double cum = 0.0;
        for (std::size_t k = 0; k < N1; ++k) {
            st.u[k] = L * (cum / achieved_length);
            cum += pp.widths[placed[k]];
        }
        st.u[N1] = L;
        st.u[0] = 0.0;
    }
    const double yc = pp.v_centre;
    // Every piece is stretched by L / l along u before stitching (see stitching.hpp), so the
    // junction targets only carry the portal mismatch; tangents are stretched alike.
    st.u_scale = L / achieved_length;
    const double u_scale = st.u_scale;
    auto stretched = [&](vec2 g) { return mean_tangent(vec2(g.x * u_scale, g.y), vec2(g.x * u_scale, g.y)); };
    auto piece_at = [&](std::size_t k) -> const piece& { return pp.pieces[pp.dp[placed[k]].original]; };
    st.left.resize(N1);
    st.right.resize(N1);
    auto own = [&](std::size_t k, piece_side s, double at_u) {
        const piece& p = piece_at(k);
        std::vector<endpoint_target> t;
        const auto h = p.heights(s);
        const auto g = p.tangents(s);
        for (std::size_t e = 0; e < h.size(); ++e) t.push_back({vec2(at_u, h[e] + delta[k] - yc), stretched(g[e])});
        return t;
    };
    for (std::size_t k = 0; k < junctions; ++k) {
        const std::size_t a = k, b = (k + 1) % N1;
        const piece &pa = piece_at(a), &pb = piece_at(b);
        const auto ha = pa.heights(piece_side::right), hb = pb.heights(piece_side::left);
        const auto ga = pa.tangents(piece_side::right), gb = pb.tangents(piece_side::left);
        FABSYNTH_ASSERT(ha.size() == hb.size());
        const double ua = st.u[k + 1], ub = (b == 0) ? 0.0 : st.u[k + 1];
        for (std::size_t e = 0; e < ha.size(); ++e) {
            const double v = 0.5 * ((ha[e] + delta[a]) + (hb[e] + delta[b])) - yc;
            const vec2 g = stretched(mean_tangent(ga[e], gb[e]));
            st.right[a].push_back({vec2(ua, v), g});
            st.left[b].push_back({vec2(ub, v), g});
        }
    }
    if (!opt.closed) {
        st.left[0] = own(0, piece_side::left, 0.0);
        st.right[N1 - 1] = own(N1 - 1, piece_side::right, L);
    }
    return st;
}

/// Phase 5b output: the stitched rings of all placed pieces, and the placed piece owning each.
struct stitched_rings {
    std::vector<ring2> rings;
    std::vector<std::size_t> owner;  ///< rings[i] belongs to placed piece owner[i]
};

/// Phase 5b (§4.2): deforms every placed piece onto its targets by LRI (stitching.hpp), with one
/// pre-factorised piece_boundary per original piece reused for all its copies; a side's placement
/// shift is its mean endpoint correction (delta - v_centre on a side without portals).
[[nodiscard]] inline stitched_rings deform_pieces(const prepared_pieces& pp, const std::vector<std::size_t>& placed,
                                                  const std::vector<double>& delta, const stitch_targets& st) {
    const double yc = pp.v_centre;
    stitched_rings out;
    std::map<std::size_t, piece_boundary> boundaries;
    for (std::size_t k = 0; k < placed.size(); ++k) {
        const std::size_t pi = pp.dp[placed[k]].original;
        auto it = boundaries.find(pi);
        if (it == boundaries.end()) it = boundaries.emplace(pi, piece_boundary(pp.pieces[pi], st.u_scale)).first;
        const piece& p = pp.pieces[pi];
        auto mean_shift = [&](const std::vector<endpoint_target>& t, piece_side s) {
            const auto h = p.heights(s);
            if (h.empty()) return delta[k] - yc;
            double m = 0.0;
            for (std::size_t e = 0; e < h.size(); ++e) m += t[e].position.y - h[e];
            return m / static_cast<double>(h.size());
        };
        const piece_placement place{st.u[k], st.u[k + 1], mean_shift(st.left[k], piece_side::left),
                                    mean_shift(st.right[k], piece_side::right)};
        for (ring2& r : it->second.deform(st.left[k], st.right[k], place)) out.rings.push_back(std::move(r)), out.owner.push_back(k);
    }
    return out;
}

/// Phase 6 output: the final contours and the Clipper grid they were merged on.
struct merged_band {
    std::vector<polygon_with_holes> polygons;
    clip_grid grid;
};

/// Phase 6 (§4.3): one Clipper grid for the stitched rings (with [0, L] and a margin across), and
/// their union clipped to [0, L] (contours.hpp).
[[nodiscard]] inline merged_band merge_band(const stitched_rings& s, double L) {
    box2 bb;
    for (const ring2& r : s.rings)
        for (const vec2& q : r) bb.extend(q);
    bb.extend(vec2(0.0, 0.0)).extend(vec2(L, 0.0));
    const double margin = std::max(1.0, bb.size().y);
    bb.extend(vec2(L, bb.hi.y + margin)).extend(vec2(0.0, bb.lo.y - margin));
    merged_band m{{}, clip_grid::for_bounds(bb)};
    m.polygons = merge_contours(s.rings, L, m.grid, &s.owner);
    return m;
}

/// Phase 7: validation of the merged band (see the file comment). Throws geometry_mismatch when
/// the pieces overlap or leave [0, L] (merged area != sum of the rings' signed areas, beyond
/// Clipper rounding), a contour is not simple, the closed band's cuts differ, or the counted
/// topology is not the request. Returns the counts otherwise.
[[nodiscard]] inline band_counts validate_band(const stitched_rings& s, const std::vector<polygon_with_holes>& polygons,
                                               const synthesis_options& opt) {
    // Stitched pieces may only touch along their shared portals: any overlap (a deformed chain
    // or a rigidly moved island reaching into a neighbour) or material pushed outside [0, L]
    // makes the merged area smaller than the sum of the pieces' areas.
    double pieces_area = 0.0;
    for (const ring2& r : s.rings) pieces_area += signed_area(r);
    const double merged_area = area(polygons);
    if (!(std::abs(merged_area - pieces_area) <= 1e-8 * std::max(1.0, pieces_area)))  // Clipper rounding only
        throw geometry_mismatch("synthesize_along: stitched pieces overlap (merged area " + std::to_string(merged_area) +
                                " vs " + std::to_string(pieces_area) + ")");
    for (const polygon_with_holes& p : polygons) {
        bool ok = is_simple(p.outer);
        for (const ring2& h : p.holes) ok = ok && is_simple(h);
        if (!ok) throw geometry_mismatch("synthesize_along: a stitched contour is not simple");
    }
    band_counts counts;
    try {
        counts = band_topology(polygons, opt.length, opt.closed);
    } catch (const solver_error& e) {
        throw geometry_mismatch(e.what());
    }
    if ((opt.components && counts.components != *opt.components) || (opt.holes && counts.holes != *opt.holes) ||
        (opt.closed_loop && counts.rings == 0))
        throw geometry_mismatch("synthesize_along: the stitched pattern has " + std::to_string(counts.components) +
                                " components and " + std::to_string(counts.holes) +
                                " holes, not what the topology solver guaranteed");
    return counts;
}

/// The retry rule of synthesize_along (file comment, "Validation failures"): after a geometry
/// mismatch, the blamed junctions' transitions are banned with the same costs; when nothing is to
/// blame, or the bans exclude every sequence (they are then dropped), the costs are perturbed by
/// seeds derived from opt.seed, more strongly with every perturbation. Deterministic.
class retry_state {
public:
    /// Seed and variation of the next attempt's costs.
    [[nodiscard]] cost_variation next_attempt(const synthesis_options& opt) {
        if (perturb_) ++perturbations_;
        if (perturbations_ == 0) return {opt.seed, opt.seed_variation};
        return {hash64(opt.seed, perturbations_), std::max(opt.seed_variation, 0.25 * double(perturbations_))};
    }
    [[nodiscard]] const transition_set& banned() const noexcept { return banned_; }
    [[nodiscard]] const std::string& last_error() const noexcept { return last_error_; }

    /// The DP found no sequence: false if nothing was banned (the request itself is impossible),
    /// else the bans are dropped and the next attempt perturbs the costs.
    [[nodiscard]] bool drop_bans() {
        if (banned_.empty()) return false;
        last_error_ += "; no sequence avoids the " + std::to_string(banned_.size()) + " banned junction(s)";
        banned_.clear();
        perturb_ = true;
        return true;
    }

    /// The stitched geometry of `placed` (DP indices) failed validation with `what`: bans the
    /// transitions of the blamed junctions (blamed_junctions); perturbs the costs if none is blamed.
    void blame(const std::string& what, const stitched_rings& s, const clip_grid& grid, const std::vector<std::size_t>& placed,
               const synthesis_options& opt) {
        last_error_ = what;
        // Retry without exactly the junctions that failed (same seed, so the result stays the
        // optimum of the remaining transitions); perturb the costs only if no junction is to blame.
        double pieces_area = 0.0;
        for (const ring2& r : s.rings) pieces_area += std::abs(signed_area(r));
        const std::vector<std::size_t> blamed = blamed_junctions(s.rings, s.owner, placed.size(), opt.closed, opt.length, grid,
                                                                 1e-6 * std::max(1.0, pieces_area));
        for (std::size_t k : blamed) banned_.insert({placed[k], placed[(k + 1) % placed.size()]});
        perturb_ = blamed.empty();
    }

private:
    std::string last_error_;
    transition_set banned_;          // DP transitions (i, j) stitching failed to realise
    std::size_t perturbations_ = 0;  // retries that fell back to perturbed costs
    bool perturb_ = false;
};

/// The retry driver over phases 2-7: at most opt.max_attempts passes, then solver_error.
/// `progress` receives the DP's layers (the first 80% of the span; a retry starts over) and the
/// stitching of each attempt.
[[nodiscard]] inline synthesis_result synthesize_prepared(const prepared_pieces& pp, const synthesis_options& opt, const progress_span& progress = {}) {
    retry_state retry;
    for (std::size_t attempt = 0; attempt < opt.max_attempts; ++attempt) {
        const cost_variation costs = retry.next_attempt(opt);
        const dp::transition_table table = junction_costs(pp, opt, retry.banned(), costs);
        std::optional<chosen_sequence> chosen;
        try {
            chosen.emplace(solve_piece_sequence(pp, table, opt, progress.part(0.0, 0.8)));
        } catch (const no_solution&) {
            if (!retry.drop_bans()) throw;  // nothing banned: the request itself is impossible
            continue;
        }
        const sequence_solution& sol = chosen->solution;
        synthesis_result res;
        res.cuts = pp.cuts;
        res.input_pieces = pp.pieces.size();
        res.v_centre = pp.v_centre;
        res.attempts = attempt + 1;
        res.dp_seconds = chosen->seconds;
        res.dp_peak_bytes = sol.stats.peak_bytes;
        res.dp_entries = sol.stats.entries;
        res.cost = sol.cost + sol.penalty;
        res.achieved_length = sol.length;
        res.epsilon = sol.epsilon;
        for (std::size_t k : sol.pieces) res.sequence.push_back(pp.dp[k].original);
        progress(0.8, "offsets and stitching");
        res.offsets = piece_offsets(pp, table, sol.pieces, opt);
        const stitch_targets targets = junction_targets(pp, sol.pieces, res.offsets, sol.length, opt);
        const stitched_rings stitched = deform_pieces(pp, sol.pieces, res.offsets, targets);
        merged_band merged = merge_band(stitched, opt.length);
        try {
            const band_counts counts = validate_band(stitched, merged.polygons, opt);
            res.polygons = std::move(merged.polygons);
            res.components = counts.components;
            res.holes = counts.holes;
            res.rings = counts.rings;
            return res;
        } catch (const geometry_mismatch& e) {
            retry.blame(e.what(), stitched, merged.grid, sol.pieces, opt);
        }
    }
    throw solver_error(retry.last_error() + " after " + std::to_string(opt.max_attempts) + " attempts (internal error)");
}

}  // namespace detail

/// Synthesizes a band pattern of length opt.length (see the file comment): check_options, then
/// prepare_pieces, then the retry driver synthesize_prepared over junction_costs,
/// solve_piece_sequence, piece_offsets, junction_targets, deform_pieces, merge_band and
/// validate_band (all in detail::). Throws invalid_input for bad options or exemplar,
/// no_solution when the topology/length request cannot be met (including a length shorter than
/// the shortest valid sequence, and a request met only beyond epsilon_max), solver_error if the
/// produced geometry fails validation in every attempt.
/// `progress` (optional) is called from the DP's layers and between the phases; a caller's callback
/// returning false there throws fabsynth::cancelled.
[[nodiscard]] inline synthesis_result synthesize_along(const exemplar& ex, const synthesis_options& opt, const progress_span& progress = {}) {
    detail::check_options(ex, opt);
    progress(0.0, "cut the exemplar");
    return detail::synthesize_prepared(detail::prepare_pieces(ex, opt), opt, progress.part(0.05, 1.0));
}

/// Options of synthesize_rectangle (§6.2).
struct rectangle_options {
    double width = 0.0, height = 0.0;         ///< W along u, H along v (> 0)
    std::optional<std::uint32_t> components{};  ///< exact components of the final rectangle
    std::optional<std::uint32_t> holes{};       ///< exact holes of the final rectangle
    std::uint64_t seed = 0;
    synthesis_options base{};                 ///< slicing, alpha, beta, epsilon... for both passes
};

/// §6.2: synthesis along u to width W (unconstrained topology, offsets off so that the band's rows
/// stay put), the result rotated by 90 degrees and used as the exemplar of a second synthesis, to
/// height H, which carries the components/holes constraints (the final pattern is the second
/// synthesis' output, so the constraints hold exactly). Offsets are off in the second pass too: a
/// slide would move material past u = 0 or u = W. Result in (u, v), u in [0, W], v in [0, H]; the
/// final polygons are clipped to that rectangle and recounted (a mismatch is a solver_error).
[[nodiscard]] inline synthesis_result synthesize_rectangle(const exemplar& ex, const rectangle_options& opt, const progress_span& progress = {}) {
    if (!(std::isfinite(opt.width) && opt.width > 0.0 && std::isfinite(opt.height) && opt.height > 0.0))
        throw invalid_input("synthesize_rectangle: width and height must be finite and > 0");
    synthesis_options a = opt.base;
    a.length = opt.width;
    a.closed = false;
    a.closed_loop = false;
    a.components.reset();
    a.holes.reset();
    a.seed = opt.seed;
    a.optimize_offsets = false;
    const synthesis_result first = synthesize_along(ex, a, progress.part(0.0, 0.5));
    // Rotate (u, v) -> (x, y) = (v, -u): a proper rotation, so orientations are kept.
    std::vector<exemplar_shape> shapes;
    for (const polygon_with_holes& p : first.polygons) {
        exemplar_shape s;
        auto rot = [](const ring2& r) {
            std::vector<vec2> o;
            for (const vec2& q : r) o.emplace_back(q.y, -q.x);
            return o;
        };
        s.subpaths.push_back(rot(p.outer));
        for (const ring2& h : p.holes) s.subpaths.push_back(rot(h));
        shapes.push_back(std::move(s));
    }
    if (shapes.empty()) throw no_solution("synthesize_rectangle: the first pass produced no material");
    const exemplar rotated = make_exemplar(shapes);
    synthesis_options b = opt.base;
    b.length = opt.height;
    b.closed = false;
    b.closed_loop = false;
    b.components = opt.components;
    b.holes = opt.holes;
    b.seed = opt.seed == 0 ? 0 : opt.seed + 1;
    b.optimize_offsets = false;
    synthesis_result second = synthesize_along(rotated, b, progress.part(0.5, 1.0));
    // Back: second pass (u2, v2) with y = v2 + c2 = -u1, so u = -(v2 + c2), v = u2. Proper rotation.
    const double c2 = second.v_centre;
    std::vector<ring2> rings;
    for (const polygon_with_holes& p : second.polygons) {
        auto back = [&](const ring2& r) {
            ring2 o;
            for (const vec2& q : r) o.emplace_back(-(q.y + c2), q.x);
            return o;
        };
        rings.push_back(back(p.outer));
        for (const ring2& h : p.holes) rings.push_back(back(h));
    }
    box2 bb;
    for (const ring2& r : rings)
        for (const vec2& q : r) bb.extend(q);
    bb.extend(vec2(0.0, 0.0)).extend(vec2(opt.width, opt.height));
    const clip_grid grid = clip_grid::for_bounds(bb);
    const ring2 rect{{0.0, 0.0}, {opt.width, 0.0}, {opt.width, opt.height}, {0.0, opt.height}};
    second.polygons = polygon_boolean(clip_op::intersection, rings, fill_rule::nonzero, {rect}, fill_rule::nonzero, grid);
    const double sw = grid.snap(opt.width), sh = grid.snap(opt.height);
    for (polygon_with_holes& p : second.polygons)
        for (ring2* r : [&] {
                 std::vector<ring2*> v{&p.outer};
                 for (ring2& h : p.holes) v.push_back(&h);
                 return v;
             }())
            for (vec2& q : *r) {
                if (q.x == sw) q.x = opt.width;
                if (q.y == sh) q.y = opt.height;
            }
    const band_counts counts = band_topology(second.polygons, opt.height, false);
    if ((opt.components && counts.components != *opt.components) || (opt.holes && counts.holes != *opt.holes))
        throw solver_error("synthesize_rectangle: clipping the result to the rectangle changed its topology (internal error)");
    second.components = counts.components;
    second.holes = counts.holes;
    second.v_centre = 0.0;
    return second;
}

}  // namespace fabsynth::vector_pattern
