// SPDX-License-Identifier: MIT
#pragma once
/// @file linear_backends.hpp  Runtime-chosen linear solvers behind fem::solve_context (internal).
///
/// Every backend turns the reduced stiffness matrix A (free DOFs, both triangles stored) into an
/// operator x ~= A^-1 b: exactly for the direct ones (LDL^T, CHOLMOD), approximately for the
/// preconditioners that conjugate gradients runs with (incomplete Cholesky, Jacobi, SA-AMG).
/// analyze() sees only the pattern, factorize() the values, so a context with a fixed pattern
/// analyses once. A failed factorization throws singular_unknown naming the reduced unknown.
#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#if defined(FABSYNTH_HAS_METIS)
#include <iostream>  // Eigen/MetisSupport uses std::cerr without including it
#include <Eigen/MetisSupport>
#endif
#if defined(FABSYNTH_HAS_CHOLMOD)
#include <Eigen/CholmodSupport>
#endif

#include <signal.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/huge_pages.hpp"
#include "fabsynth/fem/amg.hpp"

#if defined(FABSYNTH_HAS_CHOLMOD)
// OpenBLAS's thread control, when the BLAS that CHOLMOD loaded is OpenBLAS (weak: absent otherwise).
extern "C" void openblas_set_num_threads(int) __attribute__((weak));
extern "C" int openblas_get_num_threads() __attribute__((weak));
#endif

namespace fabsynth::fem::detail {

/// A factorization broke down at reduced unknown `index` (pivot `pivot`, largest pivot `max_pivot`).
struct singular_unknown {
    long index = 0;
    double pivot = 0, max_pivot = 0;
};

/// What AMG needs beyond the matrix: unknowns grouped by node and the rigid-body modes.
struct unknown_layout {
    std::vector<std::uint32_t> block_start;
    Eigen::MatrixXd near_nullspace;
};

/// Keeps the process's SIGABRT and SIGTERM dispositions across a call that may run METIS (Eigen's
/// MetisOrdering, CHOLMOD's analysis). METIS 5 (GKlib's gk_sigtrap / gk_siguntrap) installs its
/// own handlers with signal() and puts the previous ones back with SysV flags (SA_RESETHAND |
/// SA_NODEFER), so a caller's cleanup handler became one-shot: a second SIGTERM then killed the
/// process in the middle of that cleanup. Restoring the saved sigaction records undoes that. A
/// SIGTERM that arrives while METIS itself runs still meets METIS's handler and is lost (METIS
/// returns an error and LDL^T falls back to the natural order).
class keep_signal_dispositions {
public:
    keep_signal_dispositions() {
        for (int i = 0; i < 2; ++i) ::sigaction(signals[i], nullptr, &saved_[i]);
    }
    keep_signal_dispositions(const keep_signal_dispositions&) = delete;
    keep_signal_dispositions& operator=(const keep_signal_dispositions&) = delete;
    ~keep_signal_dispositions() {
        for (int i = 0; i < 2; ++i) ::sigaction(signals[i], &saved_[i], nullptr);
    }

private:
    static constexpr int signals[2] = {SIGABRT, SIGTERM};  // GKlib's SIGMEM and SIGERR
    struct sigaction saved_[2]{};
};

class linear_backend {
public:
    virtual ~linear_backend() = default;
    /// Symbolic phase (ordering, elimination tree, AMG needs values: done in factorize).
    virtual void analyze(const Eigen::SparseMatrix<double>& A) = 0;
    /// Numeric phase; throws singular_unknown or solver_error.
    virtual void factorize(const Eigen::SparseMatrix<double>& A) = 0;
    /// x = A^-1 b (exact() backends) or one preconditioner application.
    virtual void apply(const std::vector<double>& b, std::vector<double>& x) const = 0;
    [[nodiscard]] virtual bool exact() const = 0;
    /// Stored entries of the factor or preconditioner (memory indicator).
    [[nodiscard]] virtual double stored_entries() const = 0;
    /// Direct methods, after analyze(): the factor's bytes and the factorization's floating-point
    /// operations, predicted from the symbolic factor (0 for the iterative methods).
    [[nodiscard]] virtual double predicted_factor_bytes() const { return 0.0; }
    [[nodiscard]] virtual double predicted_factor_flops() const { return 0.0; }
    /// After the matrix values changed in place: adapt cheaply what can be kept (AMG: the fine
    /// level's diagonal); the result is used as a preconditioner of CG, not as an exact inverse.
    virtual void refresh(const Eigen::SparseMatrix<double>&) {}
};

/// Eigen SimplicialLDLT with METIS nested dissection when built with fabsynth::metis, else AMD;
/// a pivot below pivot_tolerance * max pivot is a mechanism.
class ldlt_backend final : public linear_backend {
public:
#if defined(FABSYNTH_HAS_METIS)
    using ordering = Eigen::MetisOrdering<int>;
#else
    using ordering = Eigen::AMDOrdering<int>;
#endif
    explicit ldlt_backend(double pivot_tolerance) : pivot_tolerance_(pivot_tolerance) {}
    void analyze(const Eigen::SparseMatrix<double>& A) override {
        const keep_signal_dispositions keep;
        s_.analyzePattern(A);
    }
    // The symbolic analysis sizes L: column k holds c_k entries below the diagonal, and the
    // up-looking factorization costs about sum (c_k + 1)^2 operations.
    [[nodiscard]] double predicted_factor_bytes() const override {
        return static_cast<double>(s_.symbolic_factor().nonZeros()) * double(sizeof(double) + sizeof(int));
    }
    [[nodiscard]] double predicted_factor_flops() const override {
        const auto& L = s_.symbolic_factor();
        double flops = 0;
        for (Eigen::Index k = 0; k < L.outerSize(); ++k) {
            const double c = static_cast<double>(L.outerIndexPtr()[k + 1] - L.outerIndexPtr()[k]) + 1.0;
            flops += c * c;
        }
        return flops;
    }
    void factorize(const Eigen::SparseMatrix<double>& A) override {
        s_.factorize(A);
        const Eigen::VectorXd D = s_.vectorD();
        if (D.size() == 0) return;
        const double dmax = D.cwiseAbs().maxCoeff();
        Eigen::Index worst = 0;
        for (Eigen::Index i = 0; i < D.size(); ++i)
            if (D(i) < D(worst)) worst = i;
        if (s_.info() != Eigen::Success || !(D(worst) > pivot_tolerance_ * dmax)) {
            // D is in permuted order: permuted index i holds the original index p with P(p) = i.
            const auto& P = s_.permutationP().indices();
            long orig = static_cast<long>(worst);
            for (Eigen::Index p = 0; p < P.size(); ++p)
                if (P(p) == worst) orig = static_cast<long>(p);
            throw singular_unknown{orig, D(worst), dmax};
        }
    }
    void apply(const std::vector<double>& b, std::vector<double>& x) const override {
        const Eigen::VectorXd y = s_.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), static_cast<Eigen::Index>(b.size())));
        x.assign(y.data(), y.data() + y.size());
    }
    [[nodiscard]] bool exact() const override { return true; }
    [[nodiscard]] double stored_entries() const override { return static_cast<double>(s_.matrixL().nestedExpression().nonZeros()); }

private:
    struct ldlt : Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, ordering> {
        /// L's pattern as sized by analyzePattern (values set by factorize).
        [[nodiscard]] const Eigen::SparseMatrix<double>& symbolic_factor() const { return this->m_matrix; }
    };
    ldlt s_;
    double pivot_tolerance_;
};

#if defined(FABSYNTH_HAS_CHOLMOD)
/// CHOLMOD supernodal LL^T (lower triangle). BLAS runs on one thread during the factorization so
/// that results do not depend on the machine's core count (a multithreaded BLAS may split sums;
/// on the 2-core machine a second BLAS thread gained nothing). SuiteSparse allocates through
/// malloc_huge / calloc_huge (same blocks, freed by free, large ones advised as huge pages: the
/// first touch of an 800 MB factor otherwise costs seconds of page faults on a VM).
class cholmod_backend final : public linear_backend {
public:
    explicit cholmod_backend(double pivot_tolerance) : pivot_tolerance_(pivot_tolerance) {}

private:
    struct llt : Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> {
        /// Original index of the column where the factorization failed, or -1.
        [[nodiscard]] long failed_unknown() const {
            const cholmod_factor* L = this->m_cholmodFactor;
            if (!L || L->minor >= L->n) return -1;
            const int* perm = static_cast<const int*>(L->Perm);
            return perm ? perm[L->minor] : static_cast<long>(L->minor);
        }
        /// CHOLMOD's estimate (min diag L / max diag L)^2, comparable to LDL^T's pivot ratio.
        [[nodiscard]] double reciprocal_condition() { return cholmod_rcond(this->m_cholmodFactor, &this->cholmod()); }
        [[nodiscard]] double factor_entries() const {
            const cholmod_factor* L = this->m_cholmodFactor;
            return L ? static_cast<double>(L->xsize) : 0.0;
        }
        /// CHOLMOD's flop count of the analysed factorization (cholmod_common::fl).
        [[nodiscard]] double analysed_flops() { return this->cholmod().fl; }
    };

public:
    void analyze(const Eigen::SparseMatrix<double>& A) override {
        use_huge_pages();
        {
            const keep_signal_dispositions keep;
            s_.analyzePattern(A);
        }
        if (s_.info() != Eigen::Success) throw solver_error("CHOLMOD symbolic analysis failed (out of memory?)");
        flops_ = s_.analysed_flops();
    }
    void factorize(const Eigen::SparseMatrix<double>& A) override {
        const int threads = openblas_get_num_threads ? openblas_get_num_threads() : 0;
        if (openblas_set_num_threads) openblas_set_num_threads(1);
        use_huge_pages();
        s_.factorize(A);
        if (openblas_set_num_threads && threads > 0) openblas_set_num_threads(threads);
        if (s_.info() != Eigen::Success) {
            const long j = s_.failed_unknown();
            if (j < 0) throw solver_error("CHOLMOD factorization failed (status " + std::to_string(s_.cholmod().status) + ")");
            throw singular_unknown{j, 0.0, 0.0};
        }
        const double rc = s_.reciprocal_condition();
        if (!(rc > pivot_tolerance_))
            throw solver_error("CHOLMOD factorization: pivot ratio (min/max diagonal of L)^2 = " + std::to_string(rc) + " is below " +
                               std::to_string(pivot_tolerance_) +
                               ": the stiffness matrix is singular (a mechanism: missing supports, a loose element or a hinge)");
    }
    void apply(const std::vector<double>& b, std::vector<double>& x) const override {
        const Eigen::VectorXd y = s_.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), static_cast<Eigen::Index>(b.size())));
        x.assign(y.data(), y.data() + y.size());
    }
    [[nodiscard]] bool exact() const override { return true; }
    [[nodiscard]] double stored_entries() const override { return s_.factor_entries(); }
    // The supernodal symbolic factor holds the size of the values (xsize) before factorization.
    [[nodiscard]] double predicted_factor_bytes() const override { return s_.factor_entries() * double(sizeof(double)); }
    [[nodiscard]] double predicted_factor_flops() const override { return flops_; }

private:
    static void use_huge_pages() {
        SuiteSparse_config.malloc_func = &fabsynth::malloc_huge;
        SuiteSparse_config.calloc_func = &fabsynth::calloc_huge;
    }
    llt s_;
    double pivot_tolerance_;
    double flops_ = 0;
};
#endif

/// Incomplete Cholesky (AMD ordering) preconditioner of CG.
class ichol_backend final : public linear_backend {
public:
    void analyze(const Eigen::SparseMatrix<double>& A) override { p_.analyzePattern(A); }
    void factorize(const Eigen::SparseMatrix<double>& A) override {
        p_.factorize(A);
        if (p_.info() != Eigen::Success) throw solver_error("incomplete Cholesky factorization failed: the stiffness matrix is singular or not positive definite");
    }
    void apply(const std::vector<double>& b, std::vector<double>& x) const override {
        const Eigen::VectorXd y = p_.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), static_cast<Eigen::Index>(b.size())));
        x.assign(y.data(), y.data() + y.size());
    }
    [[nodiscard]] bool exact() const override { return false; }
    [[nodiscard]] double stored_entries() const override { return 0.0; }

private:
    Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> p_;
};

/// Diagonal (Jacobi) preconditioner of CG.
class jacobi_backend final : public linear_backend {
public:
    void analyze(const Eigen::SparseMatrix<double>&) override {}
    void factorize(const Eigen::SparseMatrix<double>& A) override {
        inv_.resize(static_cast<std::size_t>(A.rows()));
        for (Eigen::Index i = 0; i < A.rows(); ++i) {
            const double d = A.coeff(i, i);
            if (!(d > 0)) throw singular_unknown{static_cast<long>(i), d, 0.0};
            inv_[static_cast<std::size_t>(i)] = 1.0 / d;
        }
    }
    void apply(const std::vector<double>& b, std::vector<double>& x) const override {
        x.resize(b.size());
        for (std::size_t i = 0; i < b.size(); ++i) x[i] = inv_[i] * b[i];
    }
    [[nodiscard]] bool exact() const override { return false; }
    [[nodiscard]] double stored_entries() const override { return static_cast<double>(inv_.size()); }

private:
    std::vector<double> inv_;
};

/// Smoothed-aggregation AMG V-cycle preconditioner of CG (fem/amg.hpp).
class amg_backend final : public linear_backend {
public:
    amg_backend(unknown_layout layout, const amg_options& opt) : layout_(std::move(layout)), opt_(opt) {}
    void analyze(const Eigen::SparseMatrix<double>&) override {}
    void factorize(const Eigen::SparseMatrix<double>& A) override { amg_ = std::make_unique<sa_amg>(A, layout_.block_start, layout_.near_nullspace, opt_); }
    void apply(const std::vector<double>& b, std::vector<double>& x) const override { amg_->precondition(b, x); }
    void refresh(const Eigen::SparseMatrix<double>&) override {
        if (amg_) amg_->refresh_fine_level();
    }
    [[nodiscard]] bool exact() const override { return false; }
    [[nodiscard]] double stored_entries() const override { return amg_ ? amg_->stored_entries() : 0.0; }

private:
    unknown_layout layout_;
    amg_options opt_;
    std::unique_ptr<sa_amg> amg_;
};

}  // namespace fabsynth::fem::detail
