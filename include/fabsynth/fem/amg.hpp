// SPDX-License-Identifier: MIT
#pragma once
/// @file amg.hpp  Smoothed-aggregation algebraic multigrid (SA-AMG) for assembled elasticity
/// matrices, used as the preconditioner of conjugate gradients (policy `amg_cg_solver`).
///
/// Method: Vanek, Mandel & Brezina, "Algebraic multigrid by smoothed aggregation for second and
/// fourth order elliptic problems", Computing 56 (1996). Unknowns are grouped in blocks (the DOFs
/// of one node); blocks are aggregated along strong couplings (||A_IJ||_F > theta sqrt(||A_II||_F
/// ||A_JJ||_F)); the tentative prolongator interpolates the near-nullspace (the rigid-body modes of
/// elasticity) exactly on each aggregate (a rank-revealing QR per aggregate); it is smoothed by one
/// damped Jacobi step, omega = 4 / (3 lambda_max(D^-1 A)); coarse matrices are Galerkin products
/// P^T A P. Smoother: Chebyshev polynomial of D^-1 A (the same pre and post, so the V-cycle is a
/// symmetric positive definite preconditioner). Coarsest level: sparse LDL^T.
///
/// Written here because no Debian-packaged AMG library works without MPI (hypre and PETSc need it);
/// direct factorizations of 3D solid meshes grow as n^2 in flops, AMG-preconditioned CG as n.
///
/// Everything is deterministic: aggregation is sequential in block order, the sparse products are
/// Eigen's (serial), matrix-vector products are split by rows with a fixed summation order.
///
/// Usage:
///   fabsynth::fem::sa_amg amg(A, block_start, rigid_modes);     // A: n x n SPD, both triangles
///   amg.precondition(r, z);                                      // z ~= A^-1 r (one V-cycle)
#include <Eigen/Core>
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/huge_pages.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/fem/detail/krylov.hpp"

namespace fabsynth::fem {

struct amg_options {
    double strength = 0.08;              ///< strong-coupling threshold theta on level 0, halved per level (Vanek et al.)
    std::size_t coarse_unknowns = 1500;  ///< direct LDL^T at or below this many unknowns
    int max_levels = 12;
    int smoothing_degree = 2;       ///< Chebyshev degree of each pre- and post-smoothing
    double smoothing_range = 30.0;  ///< the smoother targets the spectrum [lambda_max / range, lambda_max]
};

namespace detail {

/// y = M^T x for a column-major sparse M (one dot product per column, split over threads by
/// columns: deterministic). For a symmetric M this is M x.
inline void transposed_product(const Eigen::SparseMatrix<double>& M, const double* x, double* y) {
    const auto* outer = M.outerIndexPtr();
    const auto* inner = M.innerIndexPtr();
    const double* val = M.valuePtr();
    parallel_for(0, static_cast<std::size_t>(M.cols()), [&](std::size_t j) {
        double s = 0;
        for (auto k = outer[j]; k < outer[j + 1]; ++k) s += val[k] * x[inner[k]];
        y[j] = s;
    }, {.grain = 2048});
}

/// C = A B for column-major sparse A (m x k) and B (k x n): Gustavson's column-by-column product
/// with a dense accumulator. Consecutive columns of B with the same pattern (the coarse unknowns
/// of one aggregate) form a panel that walks A once, so A is read once per panel instead of once
/// per column. Panels are split over threads; every sum runs in the same order for any thread
/// count. (Eigen's product is serial and walks A per column.)
inline Eigen::SparseMatrix<double> sparse_product(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& B) {
    using SpMat = Eigen::SparseMatrix<double>;
    using Index = SpMat::StorageIndex;
    constexpr std::size_t max_width = 8;
    const std::size_t m = static_cast<std::size_t>(A.rows()), n = static_cast<std::size_t>(B.cols());
    const Index* bo = B.outerIndexPtr();
    const Index* bi = B.innerIndexPtr();
    const double* bv = B.valuePtr();
    const auto same_pattern = [&](std::size_t a, std::size_t b) {
        return bo[a + 1] - bo[a] == bo[b + 1] - bo[b] && std::equal(bi + bo[a], bi + bo[a + 1], bi + bo[b]);
    };
    std::vector<std::size_t> panel_start{0};
    for (std::size_t j = 1; j < n; ++j)
        if (j - panel_start.back() >= max_width || !same_pattern(panel_start.back(), j)) panel_start.push_back(j);
    panel_start.push_back(n);
    const std::size_t panels = panel_start.size() - 1;
    constexpr std::size_t panels_per_task = 64;
    const std::size_t tasks = (panels + panels_per_task - 1) / panels_per_task;
    struct piece {
        std::vector<Index> idx;
        std::vector<double> val;
        std::vector<std::size_t> len;
    };
    std::vector<piece> out(tasks);
    const Index* ao = A.outerIndexPtr();
    const Index* ai = A.innerIndexPtr();
    const double* av = A.valuePtr();
    parallel_for(0, tasks, [&](std::size_t t) {
        // slot[i]: position of row i in this panel's compact accumulator (-1 = not yet touched).
        std::vector<Index> slot(m, -1);
        std::vector<double> acc;
        std::vector<Index> pattern, order;
        piece& o = out[t];
        for (std::size_t p = t * panels_per_task; p < std::min(panels, (t + 1) * panels_per_task); ++p) {
            const std::size_t j0 = panel_start[p], w = panel_start[p + 1] - j0;
            for (Index q = bo[j0]; q < bo[j0 + 1]; ++q) {
                const Index k = bi[q];
                double bk[max_width];
                for (std::size_t c = 0; c < w; ++c) bk[c] = bv[bo[j0 + c] + (q - bo[j0])];
                for (Index r = ao[k]; r < ao[k + 1]; ++r) {
                    Index& s = slot[static_cast<std::size_t>(ai[r])];
                    if (s < 0) {
                        s = static_cast<Index>(pattern.size());
                        pattern.push_back(ai[r]);
                        acc.resize(acc.size() + max_width, 0.0);
                    }
                    double* a = &acc[static_cast<std::size_t>(s) * max_width];
                    for (std::size_t c = 0; c < w; ++c) a[c] += av[r] * bk[c];
                }
            }
            order = pattern;
            std::sort(order.begin(), order.end());
            for (std::size_t c = 0; c < w; ++c) {
                for (const Index i : order) o.idx.push_back(i), o.val.push_back(acc[static_cast<std::size_t>(slot[static_cast<std::size_t>(i)]) * max_width + c]);
                o.len.push_back(order.size());
            }
            for (const Index i : pattern) slot[static_cast<std::size_t>(i)] = -1;
            pattern.clear();
            acc.clear();
        }
    });
    std::size_t nnz = 0;
    for (const piece& o : out) nnz += o.val.size();
    SpMat C(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(n));
    C.resizeNonZeros(static_cast<Eigen::Index>(nnz));
    advise_huge_pages(C.innerIndexPtr(), nnz * sizeof(Index));
    advise_huge_pages(C.valuePtr(), nnz * sizeof(double));
    Index* outer = C.outerIndexPtr();
    std::size_t pos = 0, col = 0;
    outer[0] = 0;
    for (const piece& o : out) {
        std::copy(o.idx.begin(), o.idx.end(), C.innerIndexPtr() + pos);
        std::copy(o.val.begin(), o.val.end(), C.valuePtr() + pos);
        for (const std::size_t l : o.len) {
            outer[col + 1] = outer[col] + static_cast<Index>(l);
            ++col;
        }
        pos += o.val.size();
    }
    return C;
}

}  // namespace detail

/// SA-AMG hierarchy for a symmetric positive definite matrix (both triangles stored).
class sa_amg {
public:
    struct level {
        Eigen::SparseMatrix<double> A;            ///< this level's matrix (empty on level 0: see fine_)
        Eigen::SparseMatrix<double> P, R;         ///< prolongator to this level from the next (n x nc) and R = P^T
        std::vector<std::uint32_t> block_start;   ///< unknowns of block k: [block_start[k], block_start[k+1])
        std::vector<double> inv_diag;
        double lambda_max = 1;
        mutable std::vector<double> x, b, r, t;
        mutable detail::chebyshev_work work;
    };

    sa_amg() = default;

    /// A: n x n, symmetric positive definite, both triangles (kept by reference: it must outlive
    /// the hierarchy). block_start: block boundaries, 0 = block_start.front() < ... <
    /// block_start.back() = n (e.g. the free DOFs of each node). near_nullspace: n x k (k <= 6
    /// typically: the rigid-body modes restricted to the free DOFs). Throws invalid_input on
    /// inconsistent sizes, solver_error when a level is not positive definite.
    sa_amg(const Eigen::SparseMatrix<double>& A, std::vector<std::uint32_t> block_start, Eigen::MatrixXd near_nullspace,
           const amg_options& opt = {})
        : fine_(&A), opt_(opt) {
        const auto n = static_cast<std::size_t>(A.rows());
        if (A.cols() != A.rows() || block_start.empty() || block_start.front() != 0 || block_start.back() != n ||
            static_cast<std::size_t>(near_nullspace.rows()) != n || near_nullspace.cols() < 1)
            throw invalid_input("sa_amg: matrix, block boundaries and near-nullspace sizes disagree");
        for (std::size_t k = 1; k < block_start.size(); ++k)
            if (block_start[k] <= block_start[k - 1]) throw invalid_input("sa_amg: block boundaries must increase");
        build(std::move(block_start), std::move(near_nullspace));
    }

    /// z = M^-1 r: one V-cycle from a zero start (r, z: n entries). Uses the hierarchy's work
    /// vectors: not for concurrent calls on one object.
    void precondition(const std::vector<double>& r, std::vector<double>& z) const {
        levels_[0].b = r;
        vcycle(0);
        z = levels_[0].x;
    }

    [[nodiscard]] int num_levels() const noexcept { return static_cast<int>(levels_.size()); }
    /// Unknowns per level, finest first.
    [[nodiscard]] std::vector<std::size_t> level_sizes() const {
        std::vector<std::size_t> s;
        for (const level& L : levels_) s.push_back(L.inv_diag.size());
        return s;
    }
    /// Stored entries of the coarse matrices, prolongators and the coarsest factor.
    [[nodiscard]] double stored_entries() const {
        double c = 0;
        for (std::size_t l = 0; l < levels_.size(); ++l)
            c += static_cast<double>(levels_[l].A.nonZeros() + levels_[l].P.nonZeros() + levels_[l].R.nonZeros());
        return c + static_cast<double>(coarse_.matrixL().nestedExpression().nonZeros());
    }
    /// Re-reads the diagonal and the spectrum bound of the fine matrix after its values changed in
    /// place (same pattern), keeping the coarse levels: the V-cycle stays a symmetric positive
    /// definite preconditioner of the new matrix (cheaper than a new hierarchy; weaker if the
    /// change is large).
    void refresh_fine_level() {
        level& L = levels_[0];
        for (std::size_t i = 0; i < L.inv_diag.size(); ++i) {
            const double d = fine_->coeff(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i));
            if (!(d > 0) || !std::isfinite(d))
                throw solver_error("AMG: diagonal entry " + std::to_string(i) + " is " + std::to_string(d) +
                                   " (the stiffness matrix is singular or not positive definite)");
            L.inv_diag[i] = 1.0 / d;
        }
        L.lambda_max = estimate_lambda_max(0);
    }
    /// Stored nonzeros of all coarse matrices relative to the fine matrix's.
    [[nodiscard]] double operator_complexity() const {
        double c = 0;
        for (std::size_t l = 1; l < levels_.size(); ++l) c += static_cast<double>(levels_[l].A.nonZeros());
        return 1.0 + c / static_cast<double>(std::max<Eigen::Index>(1, fine_->nonZeros()));
    }

private:
    const Eigen::SparseMatrix<double>& matrix(std::size_t l) const { return l == 0 ? *fine_ : levels_[l].A; }

    void apply(std::size_t l, const std::vector<double>& x, std::vector<double>& y) const {
        y.resize(x.size());
        detail::transposed_product(matrix(l), x.data(), y.data());
    }

    void build(std::vector<std::uint32_t> blocks, Eigen::MatrixXd B) {
        double theta = opt_.strength;
        for (int depth = 0;; ++depth) {
            level L;
            L.block_start = std::move(blocks);
            if (depth > 0) L.A = std::move(pending_);
            const Eigen::SparseMatrix<double>& Al = depth == 0 ? *fine_ : L.A;
            const std::size_t n = static_cast<std::size_t>(Al.rows());
            L.inv_diag.resize(n);
            for (std::size_t i = 0; i < n; ++i) {
                const double d = Al.coeff(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i));
                if (!(d > 0) || !std::isfinite(d))
                    throw solver_error("AMG level " + std::to_string(depth) + ": diagonal entry " + std::to_string(i) + " is " +
                                       std::to_string(d) + " (the stiffness matrix is singular or not positive definite)");
                L.inv_diag[i] = 1.0 / d;
            }
            levels_.push_back(std::move(L));
            level& cur = levels_.back();
            cur.lambda_max = estimate_lambda_max(levels_.size() - 1);
            if (n <= opt_.coarse_unknowns || depth + 1 >= opt_.max_levels) {
                factor_coarsest();
                return;
            }
            std::vector<std::uint32_t> aggregate_of;
            const std::size_t num_aggregates = aggregate(levels_.size() - 1, theta, aggregate_of);
            if (num_aggregates * 2 > cur.block_start.size() - 1 && depth > 0) {  // coarsening stalled
                factor_coarsest();
                return;
            }
            std::vector<std::uint32_t> coarse_blocks;
            Eigen::MatrixXd Bc;
            const Eigen::SparseMatrix<double> T = tentative_prolongator(cur, aggregate_of, num_aggregates, B, coarse_blocks, Bc);
            const Eigen::SparseMatrix<double>& Af = matrix(levels_.size() - 1);
            const double omega = 4.0 / (3.0 * cur.lambda_max);
            Eigen::VectorXd scale(static_cast<Eigen::Index>(n));
            for (std::size_t i = 0; i < n; ++i) scale(static_cast<Eigen::Index>(i)) = omega * cur.inv_diag[i];
            const Eigen::SparseMatrix<double> AT = detail::sparse_product(Af, T);
            cur.P = T - scale.asDiagonal() * AT;
            cur.R = cur.P.transpose();
            const Eigen::SparseMatrix<double> AP = detail::sparse_product(Af, cur.P);
            const Eigen::SparseMatrix<double> Ac = detail::sparse_product(cur.R, AP);
            const Eigen::SparseMatrix<double> Act = Ac.transpose();
            pending_ = 0.5 * (Ac + Act);  // exact Galerkin product is symmetric; remove round-off asymmetry
            pending_.makeCompressed();
            blocks = std::move(coarse_blocks);
            B = std::move(Bc);
            theta *= 0.5;
        }
    }

    /// Largest eigenvalue of D^-1 A by 15 power iterations from a hashed start, times 1.1.
    [[nodiscard]] double estimate_lambda_max(std::size_t l) const {
        const level& L = levels_[l];
        const std::size_t n = L.inv_diag.size();
        std::vector<double> v(n), w(n);
        for (std::size_t i = 0; i < n; ++i) v[i] = hash_uniform(0xa36, static_cast<std::uint64_t>(i)) - 0.5;
        double lambda = 1;
        for (int it = 0; it < 15; ++it) {
            const double nv = std::sqrt(detail::dot(v, v));
            if (!(nv > 0)) return 1.0;
            for (double& e : v) e /= nv;
            apply(l, v, w);
            for (std::size_t i = 0; i < n; ++i) w[i] *= L.inv_diag[i];
            lambda = std::sqrt(detail::dot(w, w));
            std::swap(v, w);
        }
        return 1.1 * lambda;
    }

    /// Standard three-phase aggregation of the blocks of level l along strong couplings; returns
    /// the number of aggregates and the aggregate of each block.
    std::size_t aggregate(std::size_t l, double theta, std::vector<std::uint32_t>& aggregate_of) const {
        const level& L = levels_[l];
        const Eigen::SparseMatrix<double>& A = matrix(l);
        const std::size_t nb = L.block_start.size() - 1;
        std::vector<std::uint32_t> block_of(static_cast<std::size_t>(A.rows()));
        for (std::size_t k = 0; k < nb; ++k)
            for (std::uint32_t i = L.block_start[k]; i < L.block_start[k + 1]; ++i) block_of[i] = static_cast<std::uint32_t>(k);
        // Squared Frobenius norms of the blocks A_IJ, column block by column block.
        std::vector<std::size_t> strong_start(nb + 1, 0);
        std::vector<std::uint32_t> strong;
        std::vector<double> strength;
        std::vector<double> acc(nb, 0.0), diag(nb, 0.0);
        std::vector<std::uint32_t> touched;
        std::vector<std::vector<std::pair<std::uint32_t, double>>> norms(nb);
        for (std::size_t J = 0; J < nb; ++J) {
            for (std::uint32_t c = L.block_start[J]; c < L.block_start[J + 1]; ++c)
                for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
                    const std::uint32_t I = block_of[static_cast<std::size_t>(it.row())];
                    if (acc[I] == 0.0) touched.push_back(I);
                    acc[I] += it.value() * it.value();
                }
            std::sort(touched.begin(), touched.end());
            for (std::uint32_t I : touched) {
                if (I == J) diag[J] = std::sqrt(acc[I]);
                else norms[J].emplace_back(I, std::sqrt(acc[I]));
                acc[I] = 0.0;
            }
            touched.clear();
        }
        for (std::size_t J = 0; J < nb; ++J) {
            for (const auto& [I, a] : norms[J])
                if (a > theta * std::sqrt(diag[I] * diag[J])) strong.push_back(I), strength.push_back(a / std::sqrt(diag[I] * diag[J]));
            strong_start[J + 1] = strong.size();
        }
        constexpr std::uint32_t none = 0xffffffffu;
        aggregate_of.assign(nb, none);
        std::size_t count = 0;
        // Phase 1: a block whose strong neighbours are all free seeds an aggregate with them.
        for (std::size_t i = 0; i < nb; ++i) {
            if (aggregate_of[i] != none) continue;
            bool free = true;
            for (std::size_t k = strong_start[i]; k < strong_start[i + 1] && free; ++k) free = aggregate_of[strong[k]] == none;
            if (!free) continue;
            aggregate_of[i] = static_cast<std::uint32_t>(count);
            for (std::size_t k = strong_start[i]; k < strong_start[i + 1]; ++k) aggregate_of[strong[k]] = static_cast<std::uint32_t>(count);
            ++count;
        }
        // Phase 2: remaining blocks join the phase-1 aggregate they are most strongly coupled to.
        const std::vector<std::uint32_t> phase1 = aggregate_of;
        for (std::size_t i = 0; i < nb; ++i) {
            if (phase1[i] != none) continue;
            double best = 0;
            for (std::size_t k = strong_start[i]; k < strong_start[i + 1]; ++k)
                if (phase1[strong[k]] != none && strength[k] > best) best = strength[k], aggregate_of[i] = phase1[strong[k]];
        }
        // Phase 3: what is left forms aggregates with its still free strong neighbours.
        for (std::size_t i = 0; i < nb; ++i) {
            if (aggregate_of[i] != none) continue;
            aggregate_of[i] = static_cast<std::uint32_t>(count);
            for (std::size_t k = strong_start[i]; k < strong_start[i + 1]; ++k)
                if (aggregate_of[strong[k]] == none) aggregate_of[strong[k]] = static_cast<std::uint32_t>(count);
            ++count;
        }
        return count;
    }

    /// Tentative prolongator: on each aggregate, an orthonormal basis of the near-nullspace rows
    /// (rank-revealing QR, so aggregates of few unknowns get fewer coarse unknowns); fills the
    /// coarse block boundaries and the coarse near-nullspace (the R factors).
    static Eigen::SparseMatrix<double> tentative_prolongator(const level& L, const std::vector<std::uint32_t>& aggregate_of,
                                                             std::size_t num_aggregates, const Eigen::MatrixXd& B,
                                                             std::vector<std::uint32_t>& coarse_blocks, Eigen::MatrixXd& Bc) {
        const std::size_t nb = L.block_start.size() - 1, n = L.block_start.back();
        const Eigen::Index k = B.cols();
        std::vector<std::vector<std::uint32_t>> members(num_aggregates);
        for (std::size_t b = 0; b < nb; ++b) members[aggregate_of[b]].push_back(static_cast<std::uint32_t>(b));
        std::vector<Eigen::Triplet<double>> entries;
        entries.reserve(n * static_cast<std::size_t>(k));
        std::vector<Eigen::MatrixXd> coarse_rows;
        coarse_blocks.assign(1, 0);
        for (std::size_t g = 0; g < num_aggregates; ++g) {
            std::vector<std::uint32_t> rows;
            for (std::uint32_t b : members[g])
                for (std::uint32_t i = L.block_start[b]; i < L.block_start[b + 1]; ++i) rows.push_back(i);
            Eigen::MatrixXd Bg(static_cast<Eigen::Index>(rows.size()), k);
            for (std::size_t r = 0; r < rows.size(); ++r) Bg.row(static_cast<Eigen::Index>(r)) = B.row(rows[r]);
            Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Bg);
            qr.setThreshold(1e-10);
            const Eigen::Index rank = std::max<Eigen::Index>(1, qr.rank());
            const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(Bg.rows(), rank);
            const Eigen::MatrixXd Rg =
                Eigen::MatrixXd(qr.matrixR().topRows(rank).triangularView<Eigen::Upper>()) * qr.colsPermutation().transpose();
            const std::uint32_t c0 = coarse_blocks.back();
            for (std::size_t r = 0; r < rows.size(); ++r)
                for (Eigen::Index c = 0; c < rank; ++c) entries.emplace_back(rows[r], c0 + c, Q(static_cast<Eigen::Index>(r), c));
            coarse_blocks.push_back(c0 + static_cast<std::uint32_t>(rank));
            coarse_rows.push_back(Rg);
        }
        Bc.resize(coarse_blocks.back(), k);
        for (std::size_t g = 0; g < num_aggregates; ++g) Bc.middleRows(coarse_blocks[g], coarse_rows[g].rows()) = coarse_rows[g];
        Eigen::SparseMatrix<double> T(static_cast<Eigen::Index>(n), coarse_blocks.back());
        T.setFromTriplets(entries.begin(), entries.end());
        return T;
    }

    /// Sparse LDL^T of the coarsest matrix (sparse, so that a level where coarsening stalled
    /// cannot ask for a huge dense matrix); a non-positive pivot means a singular stiffness matrix.
    void factor_coarsest() {
        const Eigen::SparseMatrix<double>& Ac = matrix(levels_.size() - 1);
        coarse_.compute(Ac);
        const bool positive = coarse_.info() == Eigen::Success && coarse_.vectorD().size() == Ac.rows() &&
                              coarse_.vectorD().minCoeff() > 1e-13 * coarse_.vectorD().cwiseAbs().maxCoeff();
        if (!positive)
            throw solver_error("AMG: the coarsest matrix (" + std::to_string(Ac.rows()) +
                               " unknowns) is not positive definite: the stiffness matrix is singular (a mechanism: missing "
                               "supports, a loose element or a hinge)");
    }

    /// Chebyshev smoothing of A x = b on level l (detail/krylov.hpp); x = 0 on entry when zero_start.
    void smooth(std::size_t l, bool zero_start) const {
        const level& L = levels_[l];
        detail::chebyshev_smooth([&](const std::vector<double>& v, std::vector<double>& y) { apply(l, v, y); }, L.inv_diag, L.lambda_max,
                                 opt_.smoothing_range, opt_.smoothing_degree, L.b, L.x, zero_start, L.work, [](std::size_t) { return true; });
    }

    void vcycle(std::size_t l) const {
        const level& L = levels_[l];
        const std::size_t n = L.inv_diag.size();
        if (l + 1 == levels_.size()) {
            const Eigen::Map<const Eigen::VectorXd> b(L.b.data(), static_cast<Eigen::Index>(n));
            const Eigen::VectorXd x = coarse_.solve(b);
            L.x.assign(x.data(), x.data() + n);
            return;
        }
        L.x.assign(n, 0.0);
        smooth(l, true);
        apply(l, L.x, L.r);
        parallel_for(0, n, [&](std::size_t i) { L.r[i] = L.b[i] - L.r[i]; }, {.grain = 16384});
        const level& C = levels_[l + 1];
        C.b.resize(static_cast<std::size_t>(L.P.cols()));
        detail::transposed_product(L.P, L.r.data(), C.b.data());  // restriction P^T r
        vcycle(l + 1);
        L.t.resize(n);
        detail::transposed_product(L.R, C.x.data(), L.t.data());  // prolongation P x_c
        parallel_for(0, n, [&](std::size_t i) { L.x[i] += L.t[i]; }, {.grain = 16384});
        smooth(l, false);
    }

    const Eigen::SparseMatrix<double>* fine_ = nullptr;
    amg_options opt_;
    std::vector<level> levels_;
    Eigen::SparseMatrix<double> pending_;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> coarse_;
};

}  // namespace fabsynth::fem
