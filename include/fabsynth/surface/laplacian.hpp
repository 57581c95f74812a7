// SPDX-License-Identifier: MIT
#pragma once
/// @file laplacian.hpp  The cotangent Laplacian of a triangle mesh and harmonic interpolation
/// of per-vertex values from constrained vertices (Pinkall & Polthier 1993; Meyer, Desbrun,
/// Schroeder & Barr 2003): the building block of harmonic maps and of smooth fields interpolated
/// from sparse user constraints (filigree-synthesis.md §7.2 direction fields,
/// topology-constrained-vector-patterns.md §6.3 surface parameterization).
///
/// Usage:
///   Eigen::SparseMatrix<double> L = fabsynth::cotan_laplacian(mesh);   // V x V, rows sum to 0
///   std::vector<std::uint32_t> fixed{0, 17};
///   Eigen::MatrixXd at_fixed(2, 3);  // one row per fixed vertex, any number of columns
///   Eigen::MatrixXd x = fabsynth::harmonic_interpolation(mesh, fixed, at_fixed);  // V x 3
///
/// Weights: w_ij = (cot alpha_ij + cot beta_ij) / 2 over the one or two faces of edge ij, the
/// angles opposite the edge; L_ij = w_ij (i != j), L_ii = -sum_j w_ij, so L is symmetric with zero
/// row sums and -L is positive semi-definite when no weight is negative. Negative weights (obtuse
/// angles summing above pi) are clamped to 0 so that harmonic interpolation keeps the maximum
/// principle (each value is a convex combination of the constraints); this is documented rather
/// than hidden because it makes L the Laplacian of a slightly different metric on badly shaped
/// meshes. Degenerate faces (zero area) contribute nothing.
///
/// harmonic_interpolation solves L_ff x_f = -L_fc x_c for the free vertices f (Eigen's
/// SimplicialLDLT on -L_ff). A free vertex in a connected component without any fixed vertex has
/// no determined value: such vertices get NaN, and the caller decides (they are listed by
/// undetermined_vertices()). Vertices no face uses count as such components.
///
/// Errors: invalid_input naming the input for a face indexing a missing vertex, a non-finite
/// vertex, a fixed vertex out of range or given twice, a row count that differs from the fixed
/// count or a non-finite fixed value; solver_error if the factorization fails.
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth {

/// The cotangent Laplacian (see the file comment), V x V.
[[nodiscard]] inline Eigen::SparseMatrix<double> cotan_laplacian(const triangle_mesh& m) {
    const std::size_t nv = m.num_vertices();
    for (std::size_t v = 0; v < nv; ++v) {
        const vec3 x = m.vertices[v];
        if (!(std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z)))
            throw invalid_input("cotan_laplacian: vertex " + std::to_string(v) + " is not finite");
    }
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(m.num_faces() * 6);
    for (std::size_t f = 0; f < m.num_faces(); ++f) {
        const auto& c = m.faces[f];
        for (const std::uint32_t v : c)
            if (v >= nv) throw invalid_input("cotan_laplacian: face " + std::to_string(f) + " indexes a missing vertex (" + std::to_string(v) + ")");
        const double area2 = glm::length(face_normal_area2(m, f));
        if (!(area2 > 0)) continue;
        for (int k = 0; k < 3; ++k) {  // the angle at corner k is opposite edge (k+1, k+2)
            const std::uint32_t a = c[k], i = c[(k + 1) % 3], j = c[(k + 2) % 3];
            const vec3 u = m.vertices[i] - m.vertices[a], w = m.vertices[j] - m.vertices[a];
            const double cot = glm::dot(u, w) / area2;  // cos / sin, |u x w| = 2 area
            t.emplace_back(i, j, 0.5 * cot);
            t.emplace_back(j, i, 0.5 * cot);
        }
    }
    Eigen::SparseMatrix<double> off(static_cast<Eigen::Index>(nv), static_cast<Eigen::Index>(nv));
    off.setFromTriplets(t.begin(), t.end());  // sums the two faces of an interior edge
    std::vector<Eigen::Triplet<double>> out;
    std::vector<double> diag(nv, 0.0);
    for (Eigen::Index col = 0; col < off.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(off, col); it; ++it) {
            const double w = std::max(0.0, it.value());  // clamped: see the file comment
            if (w == 0.0) continue;
            out.emplace_back(static_cast<int>(it.row()), static_cast<int>(it.col()), w);
            diag[static_cast<std::size_t>(it.row())] -= w;
        }
    for (std::size_t v = 0; v < nv; ++v)
        if (diag[v] != 0.0) out.emplace_back(static_cast<int>(v), static_cast<int>(v), diag[v]);
    Eigen::SparseMatrix<double> L(static_cast<Eigen::Index>(nv), static_cast<Eigen::Index>(nv));
    L.setFromTriplets(out.begin(), out.end());
    return L;
}

/// Vertices whose connected component (through faces) holds no vertex of `fixed`.
[[nodiscard]] inline std::vector<std::uint32_t> undetermined_vertices(const triangle_mesh& m, std::span<const std::uint32_t> fixed) {
    union_find uf(m.num_vertices());
    for (const auto& f : m.faces) uf.unite(f[0], f[1]), uf.unite(f[1], f[2]);
    std::vector<std::uint8_t> anchored(m.num_vertices(), 0);
    for (const std::uint32_t v : fixed)
        if (v < m.num_vertices()) anchored[uf.find(v)] = 1;
    std::vector<std::uint32_t> out;
    for (std::uint32_t v = 0; v < m.num_vertices(); ++v)
        if (!anchored[uf.find(v)]) out.push_back(v);
    return out;
}

/// Harmonic interpolation (see the file comment): one row per vertex, the columns of `at_fixed`
/// (row k = the value at fixed[k]); NaN rows for undetermined vertices.
[[nodiscard]] inline Eigen::MatrixXd harmonic_interpolation(const triangle_mesh& m, std::span<const std::uint32_t> fixed, const Eigen::MatrixXd& at_fixed) {
    const std::size_t nv = m.num_vertices();
    if (static_cast<std::size_t>(at_fixed.rows()) != fixed.size())
        throw invalid_input("harmonic_interpolation: " + std::to_string(at_fixed.rows()) + " value rows for " + std::to_string(fixed.size()) +
                            " fixed vertices");
    if (!at_fixed.allFinite()) throw invalid_input("harmonic_interpolation: a fixed value is not finite");
    constexpr std::uint32_t free_slot = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> fixed_row(nv, free_slot);
    for (std::size_t k = 0; k < fixed.size(); ++k) {
        if (fixed[k] >= nv)
            throw invalid_input("harmonic_interpolation: fixed vertex " + std::to_string(fixed[k]) + " out of range for " + std::to_string(nv) + " vertices");
        if (fixed_row[fixed[k]] != free_slot) throw invalid_input("harmonic_interpolation: vertex " + std::to_string(fixed[k]) + " is fixed twice");
        fixed_row[fixed[k]] = static_cast<std::uint32_t>(k);
    }
    const Eigen::SparseMatrix<double> L = cotan_laplacian(m);
    Eigen::MatrixXd x = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(nv), at_fixed.cols(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t k = 0; k < fixed.size(); ++k) x.row(fixed[k]) = at_fixed.row(static_cast<Eigen::Index>(k));
    // free unknowns: vertices of anchored components that are not fixed
    std::vector<std::uint8_t> undetermined(nv, 0);
    for (const std::uint32_t v : undetermined_vertices(m, fixed)) undetermined[v] = 1;
    std::vector<std::int64_t> unknown(nv, -1);
    Eigen::Index n = 0;
    for (std::size_t v = 0; v < nv; ++v)
        if (fixed_row[v] == free_slot && !undetermined[v]) unknown[v] = n++;
    if (n == 0) return x;
    std::vector<Eigen::Triplet<double>> a;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, at_fixed.cols());
    for (Eigen::Index col = 0; col < L.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(L, col); it; ++it) {
            const auto r = static_cast<std::size_t>(it.row()), c = static_cast<std::size_t>(it.col());
            if (unknown[r] < 0) continue;
            if (unknown[c] >= 0) a.emplace_back(unknown[r], unknown[c], -it.value());
            else if (fixed_row[c] != free_slot) rhs.row(unknown[r]) += it.value() * at_fixed.row(fixed_row[c]);
        }
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(a.begin(), a.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
    if (solver.info() != Eigen::Success) throw solver_error("harmonic_interpolation: the Laplacian of the free vertices could not be factorized");
    const Eigen::MatrixXd xf = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !xf.allFinite()) throw solver_error("harmonic_interpolation: the solve failed");
    for (std::size_t v = 0; v < nv; ++v)
        if (unknown[v] >= 0) x.row(static_cast<Eigen::Index>(v)) = xf.row(unknown[v]);
    return x;
}

}  // namespace fabsynth
