// SPDX-License-Identifier: MIT
#pragma once
/// @file offsets.hpp  Global vertical positioning of a chosen piece sequence (Zhou et al. 2014, §4.1).
///
/// Pieces eta_0..eta_N are placed side by side along the band; piece i slides across the band by
/// delta_i. Junction k joins piece k to piece k+1 (and, on a closed curve, junction N joins piece N
/// back to piece 0). tau_k is the junction's optimal relative offset (match_portals, portal_cost.hpp: aligning the
/// left portal endpoints of the right piece on the right ones of the left piece) and w_k its weight
/// (the paper: the number of portal endpoints M_r of the left piece). The offsets minimise
///
///     E(delta) = sum_k w_k (delta_k + tau_k - delta_{k+1})^2
///
/// with delta_0 = 0 and, on an open curve, delta_N = 0 (both pattern ends on the curve); on a
/// closed curve the sum includes the closing junction (indices mod N+1) and only delta_0 = 0.
///
/// Gap the paper leaves open: a junction without portals (w = 0) ties nothing, so a run of pieces
/// linked to neither fixed piece has no defined position. Such a floating block is centred on the
/// curve (its mean offset is 0), which is the minimiser of E plus the term (sum_{block} delta)^2 --
/// added only for floating blocks, so it does not change the solution anywhere else.
///
/// Solved by a sparse Cholesky factorisation (Eigen SimplicialLDLT) of the normal equations, which
/// form a weighted path (or cycle) Laplacian: O(N).
///
/// Usage:
///   std::vector<double> tau{0.5, -1.0, 0.25}, w{2, 4, 2};       // 3 junctions, 4 pieces
///   auto delta = fabsynth::vector_pattern::solve_offsets(tau, w, false);  // delta[0] == delta[3] == 0
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/union_find.hpp"

namespace fabsynth::vector_pattern {

/// Offsets delta_0..delta_N (mm) for N+1 pieces. Open curve: tau.size() == weight.size() == N
/// junctions; closed curve: N+1 junctions (the last one closes the loop). Throws invalid_input for
/// size mismatches, non-finite values or negative weights; solver_error if the factorisation fails.
[[nodiscard]] inline std::vector<double> solve_offsets(std::span<const double> tau, std::span<const double> weight,
                                                       bool closed) {
    if (tau.size() != weight.size())
        throw invalid_input("solve_offsets: " + std::to_string(tau.size()) + " offsets but " +
                            std::to_string(weight.size()) + " weights");
    for (std::size_t k = 0; k < tau.size(); ++k) {
        if (!std::isfinite(tau[k])) throw invalid_input("solve_offsets: tau[" + std::to_string(k) + "] is not finite");
        if (!(std::isfinite(weight[k]) && weight[k] >= 0.0))
            throw invalid_input("solve_offsets: weight[" + std::to_string(k) + "] must be finite and >= 0");
    }
    if (closed && tau.empty()) throw invalid_input("solve_offsets: a closed sequence needs at least one junction");
    const std::size_t n = closed ? tau.size() : tau.size() + 1;  // pieces
    std::vector<double> delta(n, 0.0);
    std::vector<char> fixed(n, 0);
    fixed[0] = 1;
    fixed[n - 1] = fixed[n - 1] || !closed;
    // Unknown numbering.
    std::vector<long> col(n, -1);
    long m = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (!fixed[i]) col[i] = m++;
    if (m == 0) return delta;

    // Blocks of pieces tied by weighted junctions; a block holding no fixed piece floats.
    union_find blocks(n);
    auto find = [&](std::size_t x) { return blocks.find(static_cast<union_find::id>(x)); };
    auto junction = [&](std::size_t k) { return std::pair<std::size_t, std::size_t>{k, (k + 1) % n}; };
    for (std::size_t k = 0; k < tau.size(); ++k)
        if (weight[k] > 0.0) {
            auto [a, b] = junction(k);
            blocks.unite(static_cast<union_find::id>(a), static_cast<union_find::id>(b));
        }
    std::vector<char> anchored(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        if (fixed[i]) anchored[find(i)] = 1;

    std::vector<Eigen::Triplet<double>> trip;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
    for (std::size_t k = 0; k < tau.size(); ++k) {
        const double w = weight[k];
        if (w == 0.0) continue;
        auto [a, b] = junction(k);
        // d/d delta_a: w (delta_a - delta_b + tau) ; d/d delta_b: -w (delta_a - delta_b + tau)
        if (col[a] >= 0) {
            trip.emplace_back(col[a], col[a], w);
            rhs[col[a]] -= w * tau[k];
            if (col[b] >= 0) trip.emplace_back(col[a], col[b], -w);
        }
        if (col[b] >= 0) {
            trip.emplace_back(col[b], col[b], w);
            rhs[col[b]] += w * tau[k];
            if (col[a] >= 0) trip.emplace_back(col[b], col[a], -w);
        }
    }
    // Floating blocks: add (sum_{block} delta)^2 (weight 1 per pair), pinning the mean at 0.
    std::vector<std::vector<long>> floating(n);
    for (std::size_t i = 0; i < n; ++i)
        if (!anchored[find(i)]) floating[find(i)].push_back(col[i]);
    for (const auto& block : floating)
        for (long a : block)
            for (long b : block) trip.emplace_back(a, b, 1.0);

    Eigen::SparseMatrix<double> A(m, m);
    A.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
    if (solver.info() != Eigen::Success) throw solver_error("solve_offsets: factorisation of the offset system failed");
    const Eigen::VectorXd x = solver.solve(rhs);
    if (solver.info() != Eigen::Success) throw solver_error("solve_offsets: solving the offset system failed");
    for (std::size_t i = 0; i < n; ++i)
        if (col[i] >= 0) delta[i] = x[col[i]];
    return delta;
}

}  // namespace fabsynth::vector_pattern
