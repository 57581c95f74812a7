// SPDX-License-Identifier: MIT
#pragma once
/// @file solve_context.hpp  Linear static solves that reuse their analysis: fixed mesh and
/// supports, changing element stiffness scales and loads (the structural loops of
/// structurally-sound-patterns.md sec. 5.2 and filigree-synthesis.md sec. 5), several load cases
/// per factorization, and the solver chosen by size and availability.
///
/// The constructor numbers the DOFs, checks the supports, assembles the stiffness once, splits it
/// into the free-free block (both triangles) and the columns of the fixed DOFs, chooses the method
/// and runs its symbolic analysis. set_stiffness_scale() adds (s_new - s_old) K_e into the stored
/// values (no reassembly, no new pattern). The next solve() then either runs CG preconditioned by
/// the previous factorization or AMG hierarchy (solve_options::reuse_preconditioner, the default;
/// exact to the CG tolerance) and refactorizes numerically only if that needs more than
/// reuse_iterations iterations, or refactorizes at once. A symbolic analysis is never repeated.
///
/// Methods (solver_method, fem_solve --solver):
///   automatic  ldlt up to direct_limit free DOFs; above it amg for meshes with solid elements
///              (a direct factor of a 3D mesh costs ~n^2 flops, AMG-CG ~n) and cholmod (else ldlt)
///              for shell-only meshes (2D-like fill); if AMG-CG fails to converge, a direct method
///   ldlt       Eigen SimplicialLDLT, METIS ordering when built with fabsynth::metis, else AMD
///   cholmod    CHOLMOD supernodal Cholesky (fabsynth::cholmod)
///   cg         CG + incomplete Cholesky       cg-jacobi  CG + diagonal       amg  CG + SA-AMG (amg.hpp)
/// All agree to the CG tolerance (tested to 1e-8 relative); singular systems throw solver_error
/// naming the cause (unsupported part, collinear pins, or the DOF where a pivot vanished).
///
/// Usage:
///   fabsynth::fem::solve_context ctx(mesh, supports);            // supports.fixed: the fixed DOFs
///   auto r1 = ctx.solve(gravity_case);
///   ctx.set_stiffness_scale(e, 1e-3);                           // e.g. an "empty" beam
///   auto r2 = ctx.solve(gravity_case);                          // no new analysis
///   std::cout << ctx.statistics().method << ": " << ctx.statistics().reason;
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/huge_pages.hpp"
#include "fabsynth/fem/assembly.hpp"
#include "fabsynth/fem/boundary.hpp"
#include "fabsynth/fem/detail/krylov.hpp"
#include "fabsynth/fem/detail/linear_backends.hpp"
#include "fabsynth/fem/mesh.hpp"
#include "fabsynth/fem/solvers.hpp"

namespace fabsynth::fem {

/// What a context did and why (times in seconds, wall clock).
struct solve_statistics {
    std::string method;   ///< method in use: ldlt, cholmod, cg, cg-jacobi, amg
    std::string reason;   ///< why automatic chose it (or "requested")
    std::size_t free_dofs = 0, fixed_dofs = 0;
    double stored_entries = 0;  ///< entries of the factor / preconditioner
    /// Direct methods: the factor's bytes and floating-point operations predicted by the symbolic
    /// analysis (set by the constructor, before any factorization; 0 for iterative methods), so a
    /// caller can refuse a factorization that would not fit or not finish.
    double predicted_factor_bytes = 0, predicted_factor_flops = 0;
    int analyses = 0, factorizations = 0, solves = 0;
    int reused_solves = 0;     ///< solves answered by CG on a previous factorization
    long last_iterations = 0;  ///< CG iterations of the last solve (0 for a direct solve)
    double assemble_seconds = 0;   ///< constructor: checks, assembly, split
    double analyze_seconds = 0;    ///< symbolic analyses
    double factorize_seconds = 0;  ///< numeric factorizations / AMG set-ups
    double solve_seconds = 0;      ///< inside solve(), including the factorizations it triggered
};

class solve_context {
public:
    /// m: the mesh (copied); supports.fixed: the DOFs held fixed in every solve, with default
    /// values (other members of supports are ignored). Throws invalid_input for a bad mesh or
    /// supports or a method this build lacks, solver_error for a part that is not held.
    solve_context(mesh m, const load_case& supports, const solve_options& opt = {}) : m_(std::move(m)), opt_(opt) {
        const auto t0 = clock::now();
        m_.validate();
        dofs_ = dof_map(m_);
        load_case only_supports;
        only_supports.fixed = supports.fixed;
        validate(only_supports, m_, dofs_);
        if (opt_.check_supports) check_supports(m_, dofs_, only_supports);
        fixed_ = sorted_fixed(supports.fixed);
        number_unknowns();
        split_stiffness(assemble_stiffness(m_, dofs_));
        stats_.assemble_seconds = seconds_since(t0);
        stats_.free_dofs = free_.size();
        stats_.fixed_dofs = fixed_.size();
        choose_method();
        const auto t1 = clock::now();
        if (!free_.empty()) backend_->analyze(Kff());
        ++stats_.analyses;
        stats_.analyze_seconds = seconds_since(t1);
        stats_.predicted_factor_bytes = backend_->predicted_factor_bytes();
        stats_.predicted_factor_flops = backend_->predicted_factor_flops();
    }

    [[nodiscard]] const mesh& model() const noexcept { return m_; }
    [[nodiscard]] const dof_map& dofs() const noexcept { return dofs_; }
    [[nodiscard]] const solve_statistics& statistics() const noexcept { return stats_; }

    /// Sets the stiffness scale (finite, > 0) of element e; the stored matrix is updated at once.
    void set_stiffness_scale(std::size_t e, double scale) { set_stiffness_scales(std::span<const std::size_t>(&e, 1), std::span<const double>(&scale, 1)); }

    /// Sets the stiffness scales of elements[i] to scales[i] (same lengths).
    void set_stiffness_scales(std::span<const std::size_t> elements, std::span<const double> scales) {
        if (elements.size() != scales.size()) throw invalid_input("set_stiffness_scales: element and scale lists differ in length");
        for (std::size_t i = 0; i < elements.size(); ++i) {
            if (elements[i] >= m_.elements.size())
                throw invalid_input("set_stiffness_scales: element index " + std::to_string(elements[i]) + " is out of range (" +
                                    std::to_string(m_.elements.size()) + " elements)");
            if (!(std::isfinite(scales[i]) && scales[i] > 0))
                throw invalid_input("set_stiffness_scales: scale of element " + std::to_string(m_.element_label(elements[i])) +
                                    " must be finite and > 0, got " + std::to_string(scales[i]));
        }
        constexpr std::size_t chunk = 1024;
        for (std::size_t c0 = 0; c0 < elements.size(); c0 += chunk) {
            const std::size_t c1 = std::min(elements.size(), c0 + chunk);
            std::vector<Eigen::MatrixXd> Ke(c1 - c0);
            parallel_for(c0, c1, [&](std::size_t k) {
                const std::size_t e = elements[k];
                const double delta = scales[k] - m_.elements[e].stiffness_scale;
                visit_kind(m_.elements[e].kind, [&]<class E>(std::type_identity<E>) {
                    Ke[k - c0] = detail::scaled_element_stiffness<E>(m_, e, delta);
                });
            }, {.grain = 16});
            for (std::size_t k = c0; k < c1; ++k) {  // serial, in list order: deterministic sums
                add_element_matrix(elements[k], Ke[k - c0]);
                m_.elements[elements[k]].stiffness_scale = scales[k];
            }
        }
        if (!elements.empty()) values_changed_ = true;
    }

    /// Solves for one load case. lc.fixed is either empty (the supports' values) or prescribes
    /// values on exactly the supports' DOFs. Throws invalid_input for bad loads, solver_error on
    /// numerical failure.
    [[nodiscard]] static_result solve(const load_case& lc) {
        const auto t0 = clock::now();
        static_result r;
        r.dofs = dofs_;
        const Eigen::VectorXd f = assemble_loads(m_, dofs_, lc);
        const std::vector<std::pair<std::size_t, double>> fixed = lc.fixed.empty() ? fixed_ : prescribed_values(lc);
        const std::size_t n = dofs_.total, nf = free_.size();
        r.u = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
        for (const auto& [g, v] : fixed) r.u(static_cast<Eigen::Index>(g)) = v;
        // Right-hand side of the free DOFs: f_f - K_fc u_c.
        std::vector<double> b(nf), x(nf, 0.0);
        for (std::size_t i = 0; i < nf; ++i) b[i] = f(static_cast<Eigen::Index>(free_[i]));
        for (std::size_t c = 0; c < fixed.size(); ++c) {
            const double uc = fixed[c].second;
            if (uc == 0.0) continue;
            for (sparse_matrix::InnerIterator it(Kc_, static_cast<Eigen::Index>(c)); it; ++it) {
                const std::int64_t i = reduced_[static_cast<std::size_t>(it.row())];
                if (i >= 0) b[static_cast<std::size_t>(i)] -= it.value() * uc;
            }
        }
        if (nf > 0) solve_free(b, x, r);
        for (std::size_t i = 0; i < nf; ++i) r.u(static_cast<Eigen::Index>(free_[i])) = x[i];
        // Reactions K u - f: residual on the free DOFs, support reactions on the fixed ones.
        r.reactions = -f;
        std::vector<double> Kx(nf);
        if (nf > 0) detail::transposed_product(Kff(), x.data(), Kx.data());
        for (std::size_t i = 0; i < nf; ++i) r.reactions(static_cast<Eigen::Index>(free_[i])) = Kx[i] - b[i];  // K_ff x + K_fc u_c - f_f
        for (std::size_t c = 0; c < fixed.size(); ++c) {
            double s = 0;
            for (sparse_matrix::InnerIterator it(Kc_, static_cast<Eigen::Index>(c)); it; ++it) s += it.value() * r.u(it.row());
            r.reactions(static_cast<Eigen::Index>(fixed[c].first)) += s;
        }
        r.solver = stats_.method;
        ++stats_.solves;
        stats_.solve_seconds += seconds_since(t0);
        return r;
    }

    /// Solves several load cases with one factorization (in order).
    [[nodiscard]] std::vector<static_result> solve(std::span<const load_case> cases) {
        std::vector<static_result> out;
        out.reserve(cases.size());
        for (const load_case& lc : cases) out.push_back(solve(lc));
        return out;
    }

private:
    using clock = std::chrono::steady_clock;
    [[nodiscard]] sparse_matrix& Kff() { return *Kff_; }
    [[nodiscard]] const sparse_matrix& Kff() const { return *Kff_; }
    static double seconds_since(clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); }

    std::vector<std::pair<std::size_t, double>> sorted_fixed(const std::vector<fixed_dof>& list) const {
        std::vector<std::pair<std::size_t, double>> fixed;
        for (const auto& fx : list) fixed.emplace_back(dofs_.index(fx.node, fx.dof), fx.value);
        std::sort(fixed.begin(), fixed.end());
        for (std::size_t i = 1; i < fixed.size(); ++i)
            if (fixed[i].first == fixed[i - 1].first && fixed[i].second != fixed[i - 1].second)
                throw invalid_input("conflicting prescribed values for " + detail::dof_label(m_, dofs_, fixed[i].first));
        fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
        return fixed;
    }

    std::vector<std::pair<std::size_t, double>> prescribed_values(const load_case& lc) const {
        auto fixed = sorted_fixed(lc.fixed);
        bool same = fixed.size() == fixed_.size();
        for (std::size_t i = 0; same && i < fixed.size(); ++i) same = fixed[i].first == fixed_[i].first;
        if (!same)
            throw invalid_input("solve_context: the load case fixes " + std::to_string(fixed.size()) +
                                " DOFs that differ from the context's " + std::to_string(fixed_.size()) +
                                " supports (a context keeps its supports; give values for exactly those DOFs, or none)");
        return fixed;
    }

    /// reduced_[g] = index among the free DOFs, or -1 - (index among the fixed DOFs).
    void number_unknowns() {
        constexpr std::int64_t unset = std::numeric_limits<std::int64_t>::max();
        reduced_.assign(dofs_.total, unset);
        for (std::size_t c = 0; c < fixed_.size(); ++c) reduced_[fixed_[c].first] = -1 - static_cast<std::int64_t>(c);
        for (std::size_t g = 0; g < dofs_.total; ++g)
            if (reduced_[g] == unset) reduced_[g] = static_cast<std::int64_t>(free_.size()), free_.push_back(g);
    }

    /// K -> K_ff (free x free, both triangles) and K_c (all rows x fixed columns).
    void split_stiffness(const sparse_matrix& K) {
        using Index = sparse_matrix::StorageIndex;
        const std::size_t nf = free_.size();
        std::vector<Index> outer(nf + 1, 0), inner;
        std::vector<double> val;
        inner.reserve(static_cast<std::size_t>(K.nonZeros()));
        val.reserve(static_cast<std::size_t>(K.nonZeros()));
        advise_huge_pages(inner.data(), inner.capacity() * sizeof(Index));
        advise_huge_pages(val.data(), val.capacity() * sizeof(double));
        std::vector<Index> c_outer(fixed_.size() + 1, 0), c_inner;
        std::vector<double> c_val;
        for (Eigen::Index j = 0; j < K.outerSize(); ++j) {
            const std::int64_t rj = reduced_[static_cast<std::size_t>(j)];
            for (sparse_matrix::InnerIterator it(K, j); it; ++it) {
                const std::int64_t ri = reduced_[static_cast<std::size_t>(it.row())];
                if (rj >= 0 && ri >= 0) inner.push_back(static_cast<Index>(ri)), val.push_back(it.value());
                else if (rj < 0) c_inner.push_back(static_cast<Index>(it.row())), c_val.push_back(it.value());
            }
            if (rj >= 0) outer[static_cast<std::size_t>(rj) + 1] = static_cast<Index>(inner.size());
            else c_outer[static_cast<std::size_t>(-1 - rj) + 1] = static_cast<Index>(c_inner.size());
        }
        auto fill = [](sparse_matrix& M, Eigen::Index rows, Eigen::Index cols, const std::vector<Index>& o, const std::vector<Index>& in,
                       const std::vector<double>& v) {
            M = sparse_matrix(rows, cols);
            M.resizeNonZeros(static_cast<Eigen::Index>(in.size()));
            advise_huge_pages(M.innerIndexPtr(), in.size() * sizeof(Index));
            advise_huge_pages(M.valuePtr(), v.size() * sizeof(double));
            std::copy(o.begin(), o.end(), M.outerIndexPtr());
            std::copy(in.begin(), in.end(), M.innerIndexPtr());
            std::copy(v.begin(), v.end(), M.valuePtr());
        };
        fill(Kff(), static_cast<Eigen::Index>(nf), static_cast<Eigen::Index>(nf), outer, inner, val);
        fill(Kc_, K.rows(), static_cast<Eigen::Index>(fixed_.size()), c_outer, c_inner, c_val);
    }

    /// Adds an element matrix (element DOF order) into K_ff and K_c.
    void add_element_matrix(std::size_t e, const Eigen::MatrixXd& Ke) {
        const element& el = m_.elements[e];
        const int nn = num_nodes(el.kind);
        const int d = static_cast<int>(Ke.rows()) / nn;
        auto global = [&](int local) { return dofs_.offset[el.nodes[local / d]] + static_cast<std::size_t>(local % d); };
        auto add = [](sparse_matrix& M, Eigen::Index row, Eigen::Index col, double v) {
            const auto* begin = M.innerIndexPtr() + M.outerIndexPtr()[col];
            const auto* end = M.innerIndexPtr() + M.outerIndexPtr()[col + 1];
            const auto* it = std::lower_bound(begin, end, static_cast<sparse_matrix::StorageIndex>(row));
            M.valuePtr()[it - M.innerIndexPtr()] += v;
        };
        for (int b = 0; b < Ke.cols(); ++b) {
            const std::int64_t rb = reduced_[global(b)];
            for (int a = 0; a < Ke.rows(); ++a) {
                const std::int64_t ra = reduced_[global(a)];
                if (rb >= 0 && ra >= 0) add(Kff(), ra, rb, Ke(a, b));
                else if (rb < 0) add(Kc_, static_cast<Eigen::Index>(global(a)), -1 - rb, Ke(a, b));
            }
        }
    }

    [[nodiscard]] bool has_solid_elements() const {
        return std::any_of(m_.elements.begin(), m_.elements.end(), [](const element& e) { return e.kind != element_kind::shell3; });
    }

    void choose_method() {
        solver_method method = opt_.method;
        if (method == solver_method::automatic) {
            const std::string n = std::to_string(free_.size()) + " free DOFs";
            if (free_.size() <= opt_.direct_limit) {
                method = solver_method::ldlt;
                stats_.reason = n + " <= " + std::to_string(opt_.direct_limit) + ": direct LDL^T";
            } else if (has_solid_elements()) {
                method = solver_method::amg;
                stats_.reason = n + " of a mesh with solid elements: AMG-preconditioned CG (a direct factor of a 3D mesh grows as n^2)";
            } else {
                method = method_available(solver_method::cholmod) ? solver_method::cholmod : solver_method::ldlt;
                stats_.reason = n + " of a shell mesh: direct " + std::string(method_name(method)) + " (2D-like fill)";
            }
        } else {
            stats_.reason = "requested";
        }
        make_backend(method);
    }

    void make_backend(solver_method method) {
        if (!method_available(method))
            throw invalid_input(std::string("solver ") + method_name(method) + " is not available in this build (SuiteSparse CHOLMOD not found)");
        method_ = method;
        stats_.method = method_name(method);
        switch (method) {
            case solver_method::cholmod:
#if defined(FABSYNTH_HAS_CHOLMOD)
                backend_ = std::make_unique<detail::cholmod_backend>(opt_.pivot_tolerance);
#endif
                break;
            case solver_method::cg: backend_ = std::make_unique<detail::ichol_backend>(); break;
            case solver_method::cg_jacobi: backend_ = std::make_unique<detail::jacobi_backend>(); break;
            case solver_method::amg: backend_ = std::make_unique<detail::amg_backend>(unknown_layout(), opt_.amg); break;
            default: backend_ = std::make_unique<detail::ldlt_backend>(opt_.pivot_tolerance); break;
        }
    }

    /// Free DOFs grouped by node, and the six rigid-body modes on them (centred and scaled by the
    /// mesh size so that all columns are O(1)).
    [[nodiscard]] detail::unknown_layout unknown_layout() const {
        detail::unknown_layout L;
        const std::size_t nf = free_.size();
        L.block_start.push_back(0);
        L.near_nullspace = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(nf), 6);
        vec3 lo(INFINITY), hi(-INFINITY);
        for (const vec3& p : m_.nodes) lo = glm::min(lo, p), hi = glm::max(hi, p);
        const vec3 c = 0.5 * (lo + hi);
        const double size = std::max(1e-300, 0.5 * glm::length(hi - lo));
        for (std::size_t node = 0; node < m_.nodes.size(); ++node) {
            std::uint32_t count = 0;
            const vec3 x = (m_.nodes[node] - c) / size;
            for (int k = 0; k < dofs_.count[node]; ++k) {
                const std::int64_t i = reduced_[dofs_.offset[node] + static_cast<std::size_t>(k)];
                if (i < 0) continue;
                ++count;
                for (int a = 0; a < 3; ++a) {
                    vec3 axis(0.0);
                    axis[a] = 1;
                    if (k < 3) {
                        L.near_nullspace(i, k) = 1.0;
                        L.near_nullspace(i, 3 + a) = glm::cross(axis, x)[k];
                    } else if (k - 3 == a) {
                        L.near_nullspace(i, 3 + a) = 1.0 / size;
                    }
                }
            }
            if (count) L.block_start.push_back(L.block_start.back() + count);
        }
        return L;
    }

    void factorize() {
        const auto t = clock::now();
        try {
            backend_->factorize(Kff());
        } catch (const detail::singular_unknown& s) {
            const std::string where = detail::dof_label(m_, dofs_, free_[static_cast<std::size_t>(s.index)]);
            if (s.max_pivot > 0)
                throw solver_error(std::string(s.pivot < 0 && std::abs(s.pivot) > opt_.pivot_tolerance * s.max_pivot ? "negative" : "zero") +
                                   " pivot " + std::to_string(s.pivot) + " (max " + std::to_string(s.max_pivot) + ") at " + where +
                                   ": the stiffness matrix is singular (a mechanism: missing supports, a loose element or a hinge)");
            throw solver_error(std::string(stats_.method) + " factorization of " + std::to_string(free_.size()) +
                               " free DOFs broke down at " + where +
                               ": the stiffness matrix is singular or not positive definite (a mechanism: missing supports, a "
                               "loose element or a hinge)");
        }
        stats_.stored_entries = backend_->stored_entries();
        ++stats_.factorizations;
        stats_.factorize_seconds += seconds_since(t);
        factored_ = true;
        values_changed_ = false;
        stale_ = false;
    }

    /// Solves K_ff x = b, filling r.relative_residual / r.iterations.
    void solve_free(const std::vector<double>& b, std::vector<double>& x, static_result& r) {
        if (!factored_) {
            factorize();
        } else if (values_changed_) {
            values_changed_ = false;
            // Worth trying only when the old operator is strong (a factorization or an AMG hierarchy);
            // a Jacobi or incomplete-Cholesky preconditioner costs less to recompute than to test.
            if (opt_.reuse_preconditioner && (backend_->exact() || method_ == solver_method::amg)) backend_->refresh(Kff()), stale_ = true;
            else factorize();
        }
        const double bn = std::sqrt(detail::dot(b, b));
        if (!std::isfinite(bn)) throw solver_error("the load vector is not finite");
        if (backend_->exact() && !stale_) {
            backend_->apply(b, x);
            r.iterations = 0;
        } else {
            const long cap = stale_ ? reuse_cap() : iteration_cap();
            const bool converged = run_cg(b, x, cap, r);
            if (!converged && stale_) {
                factorize();  // the previous factorization no longer preconditions well enough
                solve_free(b, x, r);
                return;
            }
            if (!converged) {
                if (opt_.method == solver_method::automatic && method_ == solver_method::amg) {
                    stats_.reason += "; AMG-CG did not converge in " + std::to_string(cap) + " iterations, fell back to a direct method";
                    make_backend(method_available(solver_method::cholmod) ? solver_method::cholmod : solver_method::ldlt);
                    const auto t = clock::now();
                    backend_->analyze(Kff());
                    ++stats_.analyses;
                    stats_.analyze_seconds += seconds_since(t);
                    factored_ = false;
                    solve_free(b, x, r);
                    return;
                }
                throw solver_error(stats_.method + " conjugate gradients did not converge in " + std::to_string(cap) +
                                   " iterations (relative residual " + std::to_string(r.relative_residual) + ", target " +
                                   std::to_string(opt_.tolerance) + "): the system is (nearly) singular or badly conditioned");
            }
            if (stale_) ++stats_.reused_solves;
            else if (method_ == solver_method::amg) fresh_iterations_ = r.iterations;
        }
        stats_.last_iterations = r.iterations;
        for (double v : x)
            if (!std::isfinite(v)) throw solver_error("the solution contains NaN or infinity (singular or badly scaled stiffness matrix)");
        std::vector<double> Kx(x.size());
        detail::transposed_product(Kff(), x.data(), Kx.data());
        double rr = 0;
        for (std::size_t i = 0; i < x.size(); ++i) rr += (Kx[i] - b[i]) * (Kx[i] - b[i]);
        r.relative_residual = bn > 0 ? std::sqrt(rr) / bn : std::sqrt(detail::dot(x, x));
        if (!(r.relative_residual <= opt_.residual_tolerance))
            throw solver_error("residual check failed: |K u - f| / |f| = " + std::to_string(r.relative_residual) + " (limit " +
                               std::to_string(opt_.residual_tolerance) + "); the system is (nearly) singular");
    }

    [[nodiscard]] long iteration_cap() const {
        if (opt_.max_iterations > 0) return opt_.max_iterations;
        return method_ == solver_method::amg ? 2000 : 4 * static_cast<long>(free_.size());
    }
    [[nodiscard]] long reuse_cap() const {
        return method_ == solver_method::amg ? 2 * fresh_iterations_ + 10 : opt_.reuse_iterations;
    }

    bool run_cg(const std::vector<double>& b, std::vector<double>& x, long cap, static_result& r) const {
        x.assign(b.size(), 0.0);
        auto apply = [&](const std::vector<double>& v, std::vector<double>& y) {
            y.resize(v.size());
            detail::transposed_product(Kff(), v.data(), y.data());
        };
        auto prec = [&](const std::vector<double>& v, std::vector<double>& z) { backend_->apply(v, z); };
        const detail::pcg_report rep =
            detail::pcg(method_name(method_), apply, prec, b, x, opt_.tolerance, static_cast<int>(std::min<long>(cap, 1L << 30)), [](int, double) {});
        r.iterations = rep.iterations;
        r.relative_residual = rep.relative_residual;
        return rep.converged;
    }

    mesh m_;
    solve_options opt_;
    dof_map dofs_;
    std::vector<std::pair<std::size_t, double>> fixed_;
    std::vector<std::int64_t> reduced_;
    std::vector<std::size_t> free_;
    std::unique_ptr<sparse_matrix> Kff_ = std::make_unique<sparse_matrix>();  ///< on the heap: AMG keeps its address
    sparse_matrix Kc_;
    solver_method method_ = solver_method::ldlt;
    std::unique_ptr<detail::linear_backend> backend_;
    bool factored_ = false, values_changed_ = false, stale_ = false;
    long fresh_iterations_ = 0;
    solve_statistics stats_;
};

/// Assembles and solves the linear static problem of mesh m under load case lc with the method
/// of opt.method (default: automatic). Throws invalid_input for bad input, solver_error on failure.
[[nodiscard]] inline static_result solve_linear_static(const mesh& m, const load_case& lc, const solve_options& opt = {}) {
    solve_context ctx(m, lc, opt);
    return ctx.solve(lc);
}

}  // namespace fabsynth::fem
