// SPDX-License-Identifier: MIT
#pragma once
/// @file portal_cost.hpp  The transition cost between two vector-pattern pieces (Zhou et al. 2014,
/// §3.6.1): how well the right side of piece i matches the left side of piece j.
///
/// Both sides carry the same number M of portal endpoints (two per portal, top to bottom), with
/// heights y (mm, along the band's V axis) and boundary tangents g. Piece j may slide by tau
/// across the band; the matching terms are
///   d_match   = min over tau of (1/M) sum_k (y_l,j^k - y_r,i^k + tau)^2  (the variance of the
///               height differences; the minimiser tau is their mean),
///   d_tangent = sum_k |1 - g_r,i^k . g_l,j^k|  (tangents normalised),
/// and the cost is D = alpha d_match + (1 - alpha) d_tangent (alpha = 0.8 in the paper). Pieces
/// whose endpoint counts differ cannot follow each other (no cost).
///
/// This is the one place the cost is computed: synthesize_along builds its DP table with
/// portal_cost (adding its band-end, ban and seed rules, see synthesis.hpp), and
/// portal_transition_table fills a dp::transition_table for all pairs of a piece list.
///
/// Usage:
///   auto c = fabsynth::vector_pattern::portal_cost(portals_of(pieces[i]).right,
///                                                  portals_of(pieces[j]).left, 0.8);  // c.cost, c.offset
///   auto table = fabsynth::vector_pattern::portal_transition_table(piece_portals_list);  // for dp::solve_sequence
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/dp/sequence_solver.hpp"
#include "fabsynth/vector_pattern/pieces.hpp"

namespace fabsynth::vector_pattern {

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

/// The portal sides of a sliced piece (pieces.hpp: heights and unit tangents per side).
[[nodiscard]] inline portal_side portal_side_of(const piece& p, piece_side s) { return {p.heights(s), p.tangents(s)}; }
[[nodiscard]] inline piece_portals portals_of(const piece& p) {
    return {portal_side_of(p, piece_side::left), portal_side_of(p, piece_side::right)};
}

/// The three terms of §3.6.1 for piece j following piece i.
struct portal_match {
    double d_match = 0;    ///< min over tau of mean squared endpoint height difference (mm^2)
    double d_tangent = 0;  ///< sum_k |1 - g_r,i^k . g_l,j^k|
    double offset = 0;     ///< optimal tau: shift of j (mm) aligning its left endpoints on i's right ones
};

/// Matching terms between the right side of i and the left side of j (same endpoint count M).
/// tau minimising (1/M) sum (y_l,j - y_r,i + tau)^2 is the mean of y_r,i - y_l,j, and the minimum
/// is the variance of the differences. M = 0 gives zeros. Throws invalid_input on a size mismatch.
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

/// Cost D and optimal offset tau of one transition.
struct portal_transition {
    double cost = 0;    ///< D = alpha d_match + (1 - alpha) d_tangent
    double offset = 0;  ///< optimal tau (mm)
};

/// §3.6.1 cost of piece j following piece i (same endpoint count; alpha in [0, 1], not checked here).
[[nodiscard]] inline portal_transition portal_cost(const portal_side& right_of_i, const portal_side& left_of_j, double alpha) {
    const portal_match m = match_portals(right_of_i, left_of_j);
    return {alpha * m.d_match + (1.0 - alpha) * m.d_tangent, m.offset};
}

/// Transition table of §3.6.1 over all pairs with equal endpoint counts (M_r,i == M_l,j), for
/// dp::solve_sequence: cost D = portal_cost, offset = optimal tau. Throws invalid_input on
/// malformed sides (height/tangent count mismatch, odd endpoint counts, non-finite values, zero
/// tangents) or alpha outside [0, 1]. O(n^2 M).
[[nodiscard]] inline dp::transition_table portal_transition_table(std::span<const piece_portals> pieces, double alpha = 0.8) {
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
    dp::transition_table t(pieces.size());
    for (std::size_t i = 0; i < pieces.size(); ++i)
        for (std::size_t j = 0; j < pieces.size(); ++j) {
            if (pieces[i].right.heights.size() != pieces[j].left.heights.size()) continue;
            const portal_transition c = portal_cost(pieces[i].right, pieces[j].left, alpha);
            t.set(i, j, c.cost, c.offset);
        }
    return t;
}

}  // namespace fabsynth::vector_pattern
