// SPDX-License-Identifier: MIT
#pragma once
/// @file voxel_multigrid.hpp  Geometric multigrid-preconditioned CG for voxel elasticity (internal).
///
/// Level 0 is the matrix-free voxel operator. Level 1 is the exact Galerkin operator P^T A P of
/// trilinear prolongation, built voxel-block by voxel-block from the 8 precomputed child matrices
/// P_c^T K P_c (so a coarse voxel matrix is a density-weighted sum of 8 fixed matrices); deeper
/// levels are Galerkin products of 27-point block stencils. Smoother: Chebyshev polynomial of the
/// Jacobi-preconditioned operator (degree d pre and post, so the V-cycle is symmetric and can
/// precondition CG). Coarsest level: sparse LDL^T (Eigen) with a relative 1e-10 diagonal shift so
/// that the semidefinite systems of periodic problems stay factorizable.
///
/// Fixed DOFs are Galerkin-exact when they sit on nodes that survive coarsening (whole grid planes
/// such as a clamped face, or a single pinned node at even coordinates); other fixed sets give a
/// slightly weaker, still symmetric positive definite, preconditioner.
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/fem/detail/voxel_operators.hpp"

namespace fabsynth::fem::detail {

/// Sparse LDL^T of a stencil operator's free DOFs (the coarsest level, or a whole small problem).
class stencil_direct_solver {
public:
    stencil_direct_solver() = default;
    explicit stencil_direct_solver(const stencil_operator& A, double shift = 1e-10) { factor(A, shift); }

    void factor(const stencil_operator& A, double shift) {
        const std::size_t ndof = A.state.size();
        compact_.assign(ndof, -1);
        int m = 0;
        for (std::size_t d = 0; d < ndof; ++d)
            if (A.state[d] == dof_free) compact_[d] = m++;
        n_ = m;
        std::vector<Eigen::Triplet<double>> trip;
        trip.reserve(static_cast<std::size_t>(m) * 81);
        double trace = 0;
        for (std::size_t n = 0; n < A.nodes.count(); ++n) {
            for (int slot = 0; slot < 27; ++slot) {
                const std::int32_t q = A.nbr[27 * n + static_cast<std::size_t>(slot)];
                if (q < 0) continue;
                const double* B = A.block(n, slot);
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) {
                        const int i = compact_[3 * n + static_cast<std::size_t>(r)], j = compact_[3 * static_cast<std::size_t>(q) + static_cast<std::size_t>(c)];
                        if (i >= 0 && j >= 0 && B[3 * r + c] != 0.0) trip.emplace_back(i, j, B[3 * r + c]);
                        if (i >= 0 && i == j) trace += B[3 * r + c];
                    }
            }
        }
        const double s = m > 0 ? shift * trace / m : 0.0;
        for (int i = 0; i < m; ++i) trip.emplace_back(i, i, s);
        Eigen::SparseMatrix<double> K(m, m);
        K.setFromTriplets(trip.begin(), trip.end());
        if (m == 0) return;
        ldlt_ = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>();
        ldlt_->compute(K);
        if (ldlt_->info() != Eigen::Success)
            throw solver_error("voxel FEM: coarse LDL^T factorization of " + std::to_string(m) + " DOFs failed");
    }
    /// x = A^-1 b on free DOFs, 0 elsewhere.
    void solve(const std::vector<double>& b, std::vector<double>& x) const {
        std::fill(x.begin(), x.end(), 0.0);
        if (n_ == 0) return;
        Eigen::VectorXd bb(n_);
        for (std::size_t d = 0; d < compact_.size(); ++d)
            if (compact_[d] >= 0) bb(compact_[d]) = b[d];
        const Eigen::VectorXd xx = ldlt_->solve(bb);
        for (std::size_t d = 0; d < compact_.size(); ++d)
            if (compact_[d] >= 0) x[d] = xx(compact_[d]);
    }
    [[nodiscard]] int size() const noexcept { return n_; }

private:
    std::vector<int> compact_;
    int n_ = 0;
    std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>> ldlt_;
};

/// Tuning of the multigrid preconditioner.
struct multigrid_settings {
    int smoothing_degree = 2;           ///< Chebyshev degree of pre- and post-smoothing
    double smoothing_range = 20.0;      ///< smooths eigenvalues in [lmax / range, lmax] of D^-1 A
    std::size_t coarsest_dofs = 6000;   ///< stop coarsening below this many DOFs
    int max_levels = 12;
};

/// The multigrid hierarchy over a fine voxel operator (which must outlive it).
class voxel_multigrid {
public:
    struct level {
        grid_transfer down;    // to the next coarser level
        stencil_operator op;   // unused on level 0 (matrix-free)
        std::vector<std::uint8_t> state;
        std::vector<double> inv_diag;
        double lmax = 1;
        std::vector<double> b, x, r, d;
    };

    /// `levels` = number of levels to build (>= 1), including the fine one. With more than one
    /// level the fine voxel counts must be even (level 1 is built from 2x2x2 voxel blocks) and,
    /// for non-periodic grids, divisible by 2^(levels-1); periodic stencil levels may be odd.
    voxel_multigrid(const voxel_operator& fine, int levels, const multigrid_settings& s) : fine_(&fine), settings_(s) {
        levels_.resize(static_cast<std::size_t>(levels));
        levels_[0].state = fine.state;
        if (levels == 1) {
            // Whole problem solved directly.
            stencil_operator st = assemble_stencil(fine.cells, fine.active, [&](std::size_t e, int a, bool& any) {
                const std::int32_t v = fine.voxel_index[e];
                any = v >= 0;
                const double sc = any ? fine.scale[static_cast<std::size_t>(v)] : 0.0;
                return Eigen::Matrix<double, 3, 24>(sc * fine.element->rows[static_cast<std::size_t>(a)]);
            });
            st.state = fine.state;
            st.apply_mask();
            direct_.factor(st, 1e-10);
            return;
        }
        ivec3 cells = fine.cells;
        for (std::size_t l = 1; l < levels_.size(); ++l) {
            level& C = levels_[l];
            const level& F = levels_[l - 1];
            const node_set& Fn = nodes(l - 1);
            levels_[l - 1].down = grid_transfer(Fn.box);
            node_set active = coarse_nodes(levels_[l - 1].down, Fn);
            const ivec3 ccells = cells / 2;  // only used for l == 1 (the fine grid has even voxel counts)
            if (l == 1) {
                C.op = assemble_stencil(ccells, std::move(active), [&](std::size_t E, int a, bool& any) {
                    Eigen::Matrix<double, 3, 24> R = Eigen::Matrix<double, 3, 24>::Zero();
                    const ivec3 cE(static_cast<int>(E % static_cast<std::size_t>(ccells.x)),
                                   static_cast<int>((E / static_cast<std::size_t>(ccells.x)) % static_cast<std::size_t>(ccells.y)),
                                   static_cast<int>(E / (static_cast<std::size_t>(ccells.x) * static_cast<std::size_t>(ccells.y))));
                    for (int c = 0; c < 8; ++c) {
                        const double sc = fine.scale_at(2 * cE + ivec3(voxel_corner[c][0], voxel_corner[c][1], voxel_corner[c][2]));
                        if (sc == 0.0) continue;
                        any = true;
                        R.noalias() += sc * fine.element->child[static_cast<std::size_t>(c)].middleRows(3 * a, 3);
                    }
                    return R;
                });
            } else {
                C.op = galerkin(levels_[l - 1].op, levels_[l - 1].down, std::move(active));
            }
            // A coarse DOF is user-fixed iff the fine DOF at the same place is.
            for (std::size_t n = 0; n < C.op.nodes.count(); ++n) {
                const std::int32_t fn = Fn.at(2 * C.op.nodes.pos[n]);
                if (fn < 0) continue;
                for (int d = 0; d < 3; ++d)
                    if (F.state[3 * static_cast<std::size_t>(fn) + static_cast<std::size_t>(d)] == dof_fixed)
                        C.op.state[3 * n + static_cast<std::size_t>(d)] = dof_fixed;
            }
            C.op.apply_mask();
            C.state = C.op.state;
            cells = ccells;
        }
        direct_.factor(levels_.back().op, 1e-10);
        for (std::size_t l = 0; l + 1 < levels_.size(); ++l) {
            level& L = levels_[l];
            const std::vector<double> diag = l == 0 ? fine.diagonal() : L.op.diagonal();
            L.inv_diag.resize(diag.size());
            for (std::size_t i = 0; i < diag.size(); ++i) L.inv_diag[i] = L.state[i] == dof_free && diag[i] > 0 ? 1.0 / diag[i] : 1.0;
            L.lmax = estimate_lmax(l);
        }
        for (std::size_t l = 0; l < levels_.size(); ++l) {
            level& L = levels_[l];
            const std::size_t n = 3 * nodes(l).count();
            L.b.assign(n, 0.0), L.x.assign(n, 0.0), L.r.assign(n, 0.0), L.d.assign(n, 0.0);
        }
    }

    /// The active nodes of level l (level 0: the fine operator's).
    [[nodiscard]] const node_set& nodes(std::size_t l) const noexcept { return l == 0 ? fine_->active : levels_[l].op.nodes; }
    [[nodiscard]] int num_levels() const noexcept { return static_cast<int>(levels_.size()); }
    [[nodiscard]] const std::vector<level>& levels() const noexcept { return levels_; }
    [[nodiscard]] int coarsest_dofs() const noexcept { return direct_.size(); }

    /// z = M^-1 r (one V-cycle; the exact inverse when there is a single level).
    void precondition(const std::vector<double>& r, std::vector<double>& z) {
        if (levels_.size() == 1) {
            direct_.solve(r, z);
            return;
        }
        levels_[0].b = r;
        vcycle(0);
        z = levels_[0].x;
    }

private:
    void apply(std::size_t l, const std::vector<double>& x, std::vector<double>& y) const {
        if (l == 0) fine_->apply(x, y);
        else levels_[l].op.apply(x, y);
    }

    /// Largest eigenvalue of D^-1 A by 12 power iterations, times 1.2 for safety.
    double estimate_lmax(std::size_t l) {
        level& L = levels_[l];
        const std::size_t n = L.inv_diag.size();
        std::vector<double> v(n), w(n);
        // the start vector is a function of the box DOF (3 box index + component), not of the
        // compact numbering, so it does not depend on which nodes are active elsewhere
        for (std::size_t i = 0; i < n; ++i) {
            const ivec3 p = nodes(l).pos[i / 3];
            const std::uint64_t box_dof = 3 * nodes(l).box.index(p.x, p.y, p.z) + i % 3;
            v[i] = L.state[i] == dof_free ? hash_uniform(0x5eed, box_dof) - 0.5 : 0.0;
        }
        double lambda = 1;
        for (int it = 0; it < 12; ++it) {
            const double nv = std::sqrt(dot(v, v));
            if (!(nv > 0)) return 1.0;
            for (auto& e : v) e /= nv;
            apply(l, v, w);
            for (std::size_t i = 0; i < n; ++i) w[i] = L.state[i] == dof_free ? w[i] * L.inv_diag[i] : 0.0;
            lambda = std::sqrt(dot(w, w));
            std::swap(v, w);
        }
        return 1.2 * lambda;
    }

    /// Chebyshev smoothing of A x = b on level l (detail/krylov.hpp); x is 0 on entry when `zero_start`.
    void smooth(std::size_t l, bool zero_start) {
        level& L = levels_[l];
        if (work_.size() < levels_.size()) work_.resize(levels_.size());
        chebyshev_smooth([&](const std::vector<double>& v, std::vector<double>& y) { apply(l, v, y); }, L.inv_diag, L.lmax,
                         settings_.smoothing_range, settings_.smoothing_degree, L.b, L.x, zero_start, work_[l],
                         [&](std::size_t i) { return L.state[i] == dof_free; });
    }

    std::vector<double>& scratch(std::size_t l) {
        if (scratch_.size() < levels_.size()) scratch_.resize(levels_.size());
        auto& s = scratch_[l];
        if (s.size() != levels_[l].x.size()) s.assign(levels_[l].x.size(), 0.0);
        return s;
    }

    void vcycle(std::size_t l) {
        level& L = levels_[l];
        if (l + 1 == levels_.size()) {
            direct_.solve(L.b, L.x);
            return;
        }
        std::fill(L.x.begin(), L.x.end(), 0.0);
        smooth(l, true);
        apply(l, L.x, L.r);
        parallel_for(0, L.r.size(), [&](std::size_t i) { L.r[i] = L.state[i] == dof_free ? L.b[i] - L.r[i] : 0.0; }, {.grain = 16384});
        level& C = levels_[l + 1];
        restrict_to(L.down, nodes(l), nodes(l + 1), L.r, C.state, C.b);
        vcycle(l + 1);
        std::vector<double>& corr = scratch(l);
        prolongate(L.down, nodes(l), nodes(l + 1), C.x, L.state, corr);
        parallel_for(0, L.x.size(), [&](std::size_t i) { L.x[i] += corr[i]; }, {.grain = 16384});
        smooth(l, false);
    }

    const voxel_operator* fine_;
    multigrid_settings settings_;
    std::vector<level> levels_;
    std::vector<std::vector<double>> scratch_;
    std::vector<chebyshev_work> work_;
    stencil_direct_solver direct_;
};

}  // namespace fabsynth::fem::detail
