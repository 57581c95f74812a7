// SPDX-License-Identifier: MIT
#pragma once
/// @file solvers.hpp  Sparse solver policies, solver methods and options, and the constrained
/// linear static solve K u = f with a compile-time solver policy.
///
/// Most callers want solve_context.hpp (runtime method choice, reuse, several load cases) and its
/// solve_linear_static(mesh, loads, options). This header keeps the compile-time route for any
/// Eigen-shaped solver (concept sparse_solver: default constructible, analyzePattern(A),
/// factorize(A), compute(A), info(), solve(b)). Ready-made policies:
///   ldlt_solver        Eigen::SimplicialLDLT (exact, checks pivots for mechanisms)
///   cg_ichol_solver    Eigen::ConjugateGradient + IncompleteCholesky (low memory, iterative)
///   cg_jacobi_solver   Eigen::ConjugateGradient + diagonal (Jacobi) preconditioner
///   cholmod_solver     Eigen::CholmodSupernodalLLT (only when FABSYNTH_HAS_CHOLMOD is defined,
///                      i.e. when linking fabsynth::cholmod)
/// All give the same displacements to ~1e-10 relative on well-posed problems (tested to 1e-8).
///
/// Failure is never silent: a structure part without supports, too few supports, a zero or
/// negative pivot, a failed factorization, CG non-convergence, non-finite results or a residual
/// check failure all throw solver_error naming the cause.
///
/// Usage:
///   auto r = fabsynth::fem::solve_linear_static<fabsynth::fem::cg_ichol_solver>(mesh, loads);
///   vec3 u = r.displacement(node);
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#if defined(FABSYNTH_HAS_CHOLMOD)
#include <Eigen/CholmodSupport>
#endif

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <numeric>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/fem/amg.hpp"
#include "fabsynth/fem/assembly.hpp"
#include "fabsynth/fem/boundary.hpp"
#include "fabsynth/fem/mesh.hpp"

namespace fabsynth::fem {

using sparse_matrix = Eigen::SparseMatrix<double>;

/// An Eigen-shaped sparse solver for symmetric positive definite matrices (one factorization,
/// many solves). Cost is the policy's: e.g. SimplicialLDLT O(fill-in) memory and time.
template <class S>
concept sparse_solver = std::default_initializable<S> && requires(S s, const sparse_matrix& A, const Eigen::VectorXd& b) {
    s.analyzePattern(A);
    s.factorize(A);
    s.compute(A);
    { s.info() } -> std::convertible_to<Eigen::ComputationInfo>;
    { s.solve(b) };
};

using ldlt_solver = Eigen::SimplicialLDLT<sparse_matrix>;
using cg_ichol_solver =
    Eigen::ConjugateGradient<sparse_matrix, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>>>;
using cg_jacobi_solver = Eigen::ConjugateGradient<sparse_matrix, Eigen::Lower | Eigen::Upper, Eigen::DiagonalPreconditioner<double>>;
#if defined(FABSYNTH_HAS_CHOLMOD)
using cholmod_solver = Eigen::CholmodSupernodalLLT<sparse_matrix>;
#endif

static_assert(sparse_solver<ldlt_solver> && sparse_solver<cg_ichol_solver> && sparse_solver<cg_jacobi_solver>);

/// Linear solver methods of solve_context (solve_context.hpp documents the automatic choice).
enum class solver_method { automatic, ldlt, cholmod, cg, cg_jacobi, amg };

/// Command-line name of a method: auto, ldlt, cholmod, cg, cg-jacobi, amg.
[[nodiscard]] inline const char* method_name(solver_method m) {
    switch (m) {
        case solver_method::ldlt: return "ldlt";
        case solver_method::cholmod: return "cholmod";
        case solver_method::cg: return "cg";
        case solver_method::cg_jacobi: return "cg-jacobi";
        case solver_method::amg: return "amg";
        default: return "auto";
    }
}
/// Method of a command-line name; throws invalid_input listing the names.
[[nodiscard]] inline solver_method parse_solver_method(std::string_view name) {
    for (solver_method m : {solver_method::automatic, solver_method::ldlt, solver_method::cholmod, solver_method::cg, solver_method::cg_jacobi,
                            solver_method::amg})
        if (name == method_name(m)) return m;
    throw invalid_input("unknown solver '" + std::string(name) + "' (auto, ldlt, cholmod, cg, cg-jacobi, amg)");
}
/// Whether this build has the method (cholmod needs fabsynth::cholmod).
[[nodiscard]] inline bool method_available(solver_method m) {
#if defined(FABSYNTH_HAS_CHOLMOD)
    (void)m;
    return true;
#else
    return m != solver_method::cholmod;
#endif
}

struct solve_options {
    solver_method method = solver_method::automatic;  ///< solve_context / solve_linear_static without a policy
    std::size_t direct_limit = 20000;  ///< automatic: direct LDL^T up to this many free DOFs
    bool reuse_preconditioner = true;  ///< after stiffness-scale changes, first try CG on the previous factorization
    long reuse_iterations = 40;        ///< ... and refactorize if it needs more iterations (AMG: 2x its last count + 10)
    amg_options amg;                   ///< method amg
    double tolerance = 1e-12;          ///< relative residual target of iterative solvers
    long max_iterations = 0;           ///< iterative solvers; 0 = 4 * number of unknowns (AMG: 2000)
    double pivot_tolerance = 1e-13;    ///< LDLT pivots below this * max pivot mean a mechanism
    double residual_tolerance = 1e-6;  ///< accepted |K u - f| / |f| of the final check
    bool check_supports = true;        ///< check every connected part has >= 6 fixed DOFs
};

/// Solution of a linear static problem.
struct static_result {
    dof_map dofs;
    Eigen::VectorXd u;          ///< all DOFs [mm, rad] (dofs.total)
    Eigen::VectorXd reactions;  ///< K u - f [N, N mm]: support reactions at fixed DOFs, ~0 elsewhere
    double relative_residual = 0;
    long iterations = 0;        ///< iterative solvers only
    std::string solver;         ///< method that produced u (solve_context: auto resolved to its choice)

    /// Translation [mm] of node i (0 for nodes without DOFs).
    [[nodiscard]] vec3 displacement(std::size_t i) const {
        if (dofs.count[i] < 3) return vec3(0.0);
        const auto o = static_cast<Eigen::Index>(dofs.offset[i]);
        return vec3(u(o), u(o + 1), u(o + 2));
    }
    /// Rotation vector [rad] of a shell node (0 for solid-only nodes).
    [[nodiscard]] vec3 rotation(std::size_t i) const {
        if (dofs.count[i] < 6) return vec3(0.0);
        const auto o = static_cast<Eigen::Index>(dofs.offset[i]);
        return vec3(u(o + 3), u(o + 4), u(o + 5));
    }
    /// Element DOF vector of element e of type E (gathered from u).
    template <finite_element E>
    [[nodiscard]] Eigen::Matrix<double, element_dofs<E>, 1> element_dofs_of(const mesh& m, std::size_t e) const {
        Eigen::Matrix<double, element_dofs<E>, 1> ue;
        for (int a = 0; a < E::num_nodes; ++a)
            for (int i = 0; i < E::dofs_per_node; ++i)
                ue(E::dofs_per_node * a + i) = u(static_cast<Eigen::Index>(dofs.offset[m.elements[e].nodes[a]] + static_cast<std::size_t>(i)));
        return ue;
    }
};

namespace detail {
inline const char* dof_name(int k) {
    static const char* names[6] = {"ux", "uy", "uz", "rx", "ry", "rz"};
    return k >= 0 && k < 6 ? names[k] : "?";
}
inline std::string dof_label(const mesh& m, const dof_map& dofs, std::size_t g) {
    const auto it = std::upper_bound(dofs.offset.begin(), dofs.offset.end(), g);
    const std::size_t node = static_cast<std::size_t>(it - dofs.offset.begin()) - 1;
    return "node " + std::to_string(m.node_label(node)) + " " + dof_name(static_cast<int>(g - dofs.offset[node]));
}
}  // namespace detail

/// Throws solver_error if some connected part of the mesh (elements linked through shared nodes)
/// can move as a rigid body: fewer than 6 fixed DOFs, or supports that leave a rigid translation
/// or rotation free (e.g. all pins on one line). Names the part by its elements. Internal
/// mechanisms (hinges) are caught later by the pivot and residual checks.
inline void check_supports(const mesh& m, const dof_map& dofs, const load_case& lc) {
    const std::size_t nn = m.nodes.size();
    union_find parts_of_nodes(nn);
    auto find = [&](std::uint32_t x) { return parts_of_nodes.find(x); };
    for (const element& e : m.elements)
        for (int a = 1; a < num_nodes(e.kind); ++a) parts_of_nodes.unite(e.nodes[0], e.nodes[a]);
    std::vector<std::pair<std::uint32_t, int>> fixed;
    for (const auto& f : lc.fixed) fixed.emplace_back(f.node, f.dof);
    std::sort(fixed.begin(), fixed.end());
    fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
    // Parts in order of their first element.
    std::vector<std::int64_t> part_of_root(nn, -1);
    std::vector<std::vector<std::size_t>> parts;
    for (std::size_t e = 0; e < m.elements.size(); ++e) {
        const std::uint32_t r = find(m.elements[e].nodes[0]);
        if (part_of_root[r] < 0) part_of_root[r] = static_cast<std::int64_t>(parts.size()), parts.emplace_back();
        parts[static_cast<std::size_t>(part_of_root[r])].push_back(e);
    }
    (void)dofs;
    // Fixed DOFs grouped by part.
    std::vector<std::vector<std::pair<std::uint32_t, int>>> part_fixed(parts.size());
    for (const auto& [node, dof] : fixed) {
        const std::int64_t p = part_of_root[find(node)];
        if (p >= 0) part_fixed[static_cast<std::size_t>(p)].emplace_back(node, dof);
    }
    for (std::size_t p = 0; p < parts.size(); ++p) {
        const std::size_t k = part_fixed[p].size();
        std::string list;
        for (std::size_t i = 0; i < parts[p].size() && i < 8; ++i) list += (i ? ", " : "") + std::to_string(m.element_label(parts[p][i]));
        if (parts[p].size() > 8) list += ", ... " + std::to_string(parts[p].size()) + " elements in all";
        const std::string name = "part " + std::to_string(p + 1) + " of " + std::to_string(parts.size()) + " (elements " + list + ")";
        if (k < 6)
            throw solver_error(name + (k == 0 ? std::string(" has no support") : " has only " + std::to_string(k) + " fixed DOFs (at least 6 are needed)") +
                               ": it can move as a rigid body; fix more DOFs on it");
        // The supports must stop all 6 rigid-body modes: G = sum r r^T over fixed DOFs, where r holds
        // the 6 rigid modes (3 translations, 3 rotations about the part's centroid, scaled by its size)
        // evaluated at that DOF, must be non-singular. Catches e.g. collinear pins.
        vec3 c(0.0);
        std::size_t cnt = 0;
        double L = 0;
        for (std::size_t e : parts[p])
            for (int a = 0; a < num_nodes(m.elements[e].kind); ++a) c += m.nodes[m.elements[e].nodes[a]], ++cnt;
        c /= static_cast<double>(cnt);
        for (std::size_t e : parts[p])
            for (int a = 0; a < num_nodes(m.elements[e].kind); ++a) L = std::max(L, glm::length(m.nodes[m.elements[e].nodes[a]] - c));
        if (!(L > 0)) L = 1;
        Eigen::Matrix<double, 6, 6> G = Eigen::Matrix<double, 6, 6>::Zero();
        for (const auto& [node, dof] : part_fixed[p]) {
            Eigen::Matrix<double, 6, 1> r = Eigen::Matrix<double, 6, 1>::Zero();
            const vec3 d = (m.nodes[node] - c) / L;
            if (dof < 3) {
                r(dof) = 1;
                for (int j = 0; j < 3; ++j) {
                    vec3 axis(0.0);
                    axis[j] = 1;
                    r(3 + j) = glm::cross(axis, d)[dof];
                }
            } else {
                r(dof) = 1;  // rotation dof of a shell node: rigid rotation about axis dof-3
            }
            G += r * r.transpose();
        }
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(G);
        if (!(es.eigenvalues()(0) > 1e-10 * es.eigenvalues()(5))) {
            const Eigen::Matrix<double, 6, 1> v = es.eigenvectors().col(0);
            const bool rot = v.tail<3>().norm() > v.head<3>().norm();
            const Eigen::Vector3d dir = rot ? Eigen::Vector3d(v.tail<3>().normalized()) : Eigen::Vector3d(v.head<3>().normalized());
            throw solver_error(name + " is not held against rigid-body " + (rot ? "rotation about an axis along (" : "translation along (") +
                               std::to_string(dir(0)) + ", " + std::to_string(dir(1)) + ", " + std::to_string(dir(2)) +
                               "): its supports are collinear or too few; fix more DOFs on it");
        }
    }
}

/// Solves K u = f with u(fixed[i].first) = fixed[i].second by eliminating the fixed DOFs.
/// K: n x n symmetric (both triangles), f: n. `label(g)` names global DOF g in messages.
/// Returns u (n) and fills residual/iterations. Throws solver_error on any numerical failure.
/// The solver keeps referring to the reduced matrix, which dies on return: do not reuse it for solve().
template <sparse_solver Solver, class Label>
Eigen::VectorXd solve_constrained(const sparse_matrix& K, const Eigen::VectorXd& f,
                                  const std::vector<std::pair<std::size_t, double>>& fixed, Solver& solver,
                                  const solve_options& opt, Label&& label, double* residual = nullptr,
                                  long* iterations = nullptr) {
    const Eigen::Index n = K.rows();
    if (K.cols() != n || f.size() != n) throw invalid_input("solve_constrained: K and f sizes differ");
    std::vector<std::int64_t> map(static_cast<std::size_t>(n), 0);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
    for (const auto& [g, v] : fixed) {
        if (g >= static_cast<std::size_t>(n)) throw invalid_input("solve_constrained: fixed dof index out of range");
        map[g] = -1;
        u(static_cast<Eigen::Index>(g)) = v;
    }
    std::vector<Eigen::Index> free;
    for (Eigen::Index i = 0; i < n; ++i)
        if (map[static_cast<std::size_t>(i)] == 0) map[static_cast<std::size_t>(i)] = static_cast<std::int64_t>(free.size()), free.push_back(i);
        else map[static_cast<std::size_t>(i)] = -1;
    const Eigen::Index nf = static_cast<Eigen::Index>(free.size());
    if (nf == 0) return u;
    // Reduced system: Kff uf = f_f - Kfc uc.
    Eigen::VectorXd b(nf);
    for (Eigen::Index i = 0; i < nf; ++i) b(i) = f(free[static_cast<std::size_t>(i)]);
    sparse_matrix Kff(nf, nf);
    {
        std::vector<sparse_matrix::StorageIndex> outer(static_cast<std::size_t>(nf) + 1, 0), inner;
        std::vector<double> val;
        inner.reserve(static_cast<std::size_t>(K.nonZeros()));
        val.reserve(static_cast<std::size_t>(K.nonZeros()));
        for (Eigen::Index j = 0; j < n; ++j) {
            const std::int64_t jf = map[static_cast<std::size_t>(j)];
            for (sparse_matrix::InnerIterator it(K, j); it; ++it) {
                const std::int64_t i_f = map[static_cast<std::size_t>(it.row())];
                if (jf >= 0 && i_f >= 0) inner.push_back(static_cast<sparse_matrix::StorageIndex>(i_f)), val.push_back(it.value());
                else if (jf < 0 && i_f >= 0 && u(j) != 0.0) b(i_f) -= it.value() * u(j);
            }
            if (jf >= 0) outer[static_cast<std::size_t>(jf) + 1] = static_cast<sparse_matrix::StorageIndex>(inner.size());
        }
        Kff.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
        std::copy(outer.begin(), outer.end(), Kff.outerIndexPtr());
        std::copy(inner.begin(), inner.end(), Kff.innerIndexPtr());
        std::copy(val.begin(), val.end(), Kff.valuePtr());
    }
    auto name_free = [&](Eigen::Index i) { return label(static_cast<std::size_t>(free[static_cast<std::size_t>(i)])); };
    if constexpr (requires { solver.setTolerance(1.0); solver.setMaxIterations(Eigen::Index(1)); }) {
        solver.setTolerance(opt.tolerance);
        solver.setMaxIterations(opt.max_iterations > 0 ? opt.max_iterations : 4 * nf);
    }
    solver.compute(Kff);
    if (solver.info() != Eigen::Success)
        throw solver_error("factorization of the stiffness matrix (" + std::to_string(nf) +
                           " free dofs) failed: the matrix is singular or not positive definite (a mechanism: "
                           "missing supports, a loose element or a hinge)");
    if constexpr (requires { solver.vectorD(); solver.permutationP(); }) {
        const Eigen::VectorXd D = solver.vectorD();
        const double dmax = D.cwiseAbs().maxCoeff();
        Eigen::Index worst = 0;
        for (Eigen::Index i = 0; i < D.size(); ++i)
            if (D(i) < D(worst)) worst = i;
        if (!(D(worst) > opt.pivot_tolerance * dmax)) {
            // D is in permuted order: permuted index i holds original index p with P(p) = i.
            const auto& P = solver.permutationP().indices();
            Eigen::Index orig = worst;
            for (Eigen::Index p = 0; p < P.size(); ++p)
                if (P(p) == worst) orig = p;
            throw solver_error(std::string(D(worst) < 0 && std::abs(D(worst)) > opt.pivot_tolerance * dmax ? "negative" : "zero") +
                               " pivot " + std::to_string(D(worst)) + " (max " + std::to_string(dmax) + ") at " + name_free(orig) +
                               ": the stiffness matrix is singular (a mechanism: missing supports, a loose element or a hinge)");
        }
    }
    const Eigen::VectorXd uf = solver.solve(b);
    if constexpr (requires { solver.iterations(); }) {
        if (iterations) *iterations = static_cast<long>(solver.iterations());
    }
    if (solver.info() != Eigen::Success) {
        if constexpr (requires { solver.iterations(); solver.error(); })
            throw solver_error("conjugate gradient did not converge in " + std::to_string(solver.iterations()) +
                               " iterations (relative residual " + std::to_string(solver.error()) + ", target " +
                               std::to_string(opt.tolerance) + ")");
        else
            throw solver_error("sparse solve failed (solver info " + std::to_string(static_cast<int>(solver.info())) + ")");
    }
    if (!uf.allFinite()) throw solver_error("the solution contains NaN or infinity (singular or badly scaled stiffness matrix)");
    const double bn = b.norm();
    const double res = bn > 0 ? (Kff * uf - b).norm() / bn : uf.norm();
    if (residual) *residual = res;
    if (!(res <= opt.residual_tolerance))
        throw solver_error("residual check failed: |K u - f| / |f| = " + std::to_string(res) +
                           " (limit " + std::to_string(opt.residual_tolerance) + "); the system is (nearly) singular");
    for (Eigen::Index i = 0; i < nf; ++i) u(free[static_cast<std::size_t>(i)]) = uf(i);
    return u;
}

/// Assembles and solves the linear static problem of mesh m under load case lc with a
/// user-configured solver object. Throws invalid_input for bad input, solver_error on failure.
template <sparse_solver Solver>
[[nodiscard]] static_result solve_linear_static(const mesh& m, const load_case& lc, const solve_options& opt, Solver& solver) {
    static_result r;
    r.dofs = dof_map(m);
    const sparse_matrix K = assemble_stiffness(m, r.dofs);
    const Eigen::VectorXd f = assemble_loads(m, r.dofs, lc);
    if (opt.check_supports) check_supports(m, r.dofs, lc);
    std::vector<std::pair<std::size_t, double>> fixed;
    for (const auto& fx : lc.fixed) fixed.emplace_back(r.dofs.index(fx.node, fx.dof), fx.value);
    std::sort(fixed.begin(), fixed.end());
    for (std::size_t i = 1; i < fixed.size(); ++i)
        if (fixed[i].first == fixed[i - 1].first && fixed[i].second != fixed[i - 1].second)
            throw invalid_input("conflicting prescribed values for " + detail::dof_label(m, r.dofs, fixed[i].first));
    fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
    r.u = solve_constrained(K, f, fixed, solver, opt, [&](std::size_t g) { return detail::dof_label(m, r.dofs, g); },
                            &r.relative_residual, &r.iterations);
    r.reactions = K * r.u - f;
    return r;
}

/// Same with a default-constructed Solver. Without a Solver, solve_context.hpp's overload chooses
/// the method (automatic by default).
template <sparse_solver Solver>
[[nodiscard]] static_result solve_linear_static(const mesh& m, const load_case& lc, const solve_options& opt = {}) {
    Solver solver;
    return solve_linear_static(m, lc, opt, solver);
}

}  // namespace fabsynth::fem
