// SPDX-License-Identifier: MIT
#pragma once
/// @file homogenization.hpp  Periodic homogenization of voxel microstructures and the isotropic
/// fit of procedural-voronoi-foams.md eq. (1).
///
/// homogenize(grid, material): the grid is one period (unit cell) of an infinite periodic
/// material; voxel densities scale the stiffness as in fem/voxel.hpp (voxel_stiffness_law;
/// density 0 = void). For each of the six unit macro-strains eps0_i (Voigt xx, yy, zz, yz, xz, xy,
/// engineering shear) the periodic fluctuation chi_i solves K chi_i = f_i = sum_e K_e u0_i,e,
/// where u0_i is the affine displacement eps0_i x; then
///     C^H_ij = 1/|Y| sum_e (u0_i - chi_i)_e^T K_e (u0_j - chi_j)_e        [MPa]
/// (the energy form, e.g. Andreassen & Andreasen 2014; Dong, Tang & Zhao 2018). Nodes wrap around,
/// so an n^3 cell has n^3 nodes; rigid translations are removed by pinning one node per load-
/// bearing part.
///
/// Floating islands: solid voxels are grouped into face-connected parts (periodic wrap-around).
/// A part that does not connect to its own periodic image carries no load in the infinite
/// material (its fluctuation cancels eps0 exactly, so its energy is zero); such parts are removed
/// before solving, which leaves C^H unchanged and avoids a singular system. Their share is
/// reported as removed_fraction. Voxels touching the rest only along edges or corners form their
/// own parts (an edge is a hinge).
///
/// Solvers are those of fem/voxel.hpp; the default multigrid solver handles ~10^6 DOFs. The
/// periodic multigrid needs even voxel counts for its first coarsening (afterwards odd node
/// counts coarsen too: 60 -> 30 -> 15 -> 8); a cell with an odd voxel count along some axis is
/// solved directly when small (<= max_direct_dofs) and by Jacobi-CG otherwise (much slower).
///
/// Usage:
///   auto h = fabsynth::fem::homogenize(grid, {200.0, 0.3});        // grid: voxel_grid<double>
///   auto fit = fabsynth::fem::fit_isotropic(h.C, 200.0);            // E, nu, relative residual
#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/fem/material.hpp"
#include "fabsynth/fem/voxel.hpp"

namespace fabsynth::fem {

using matrix6 = Eigen::Matrix<double, 6, 6>;

struct homogenization_options {
    voxel_solver_options solver{};   ///< solver and tolerance for each of the six load cases
    voxel_stiffness_law law{};       ///< density -> stiffness factor
};

struct homogenization_result {
    matrix6 C = matrix6::Zero();     ///< effective elasticity [MPa], Voigt (xx,yy,zz,yz,xz,xy), engineering shear, symmetric
    double volume_fraction = 0;      ///< mean voxel density over the cell (solid fraction for 0/1 grids)
    double removed_fraction = 0;     ///< fraction of voxels removed as floating islands
    std::array<voxel_solve_stats, 6> stats{};  ///< per load case
};

/// Isotropic elasticity tensor C^I(E, nu) in the same Voigt convention [MPa].
[[nodiscard]] inline matrix6 isotropic_tensor(double E, double nu) { return isotropic_material{E, nu}.elasticity(); }

/// Result of fit_isotropic.
struct isotropic_fit {
    double E = 0;                  ///< Young's modulus [MPa]
    double nu = 0;                 ///< Poisson's ratio
    double residual = 0;           ///< xi(C^H) of eq. (1): min ||C^I(E, nu) - C^H||_F^2 [MPa^2]
    double relative_residual = 0;  ///< sqrt(residual) / ||C^H||_F (dimensionless; 0 = exactly isotropic)
};

/// Fits an isotropic tensor to C (procedural-voronoi-foams.md eq. (1)): minimises the Frobenius
/// norm of C^I(E, nu) - C over -1 <= nu <= 0.5 and 0 <= E <= E_max, with the norm taken on the 6x6
/// Voigt matrices (engineering shear; the paper does not say which form, and its "relative
/// distance" is not defined, so relative_residual is our normalisation). C^I is linear in the
/// Lame parameters, so the unconstrained minimum is a 2x2 least-squares solve; if it violates the
/// bounds the constrained minimum is found by a scan over nu with the optimal clamped E.
/// @throws invalid_input if C is not finite or E_max <= 0.
[[nodiscard]] inline isotropic_fit fit_isotropic(const matrix6& C, double E_max = std::numeric_limits<double>::infinity()) {
    if (!C.allFinite()) throw invalid_input("fit_isotropic: the tensor has non-finite entries");
    if (!(E_max > 0)) throw invalid_input("fit_isotropic: E_max must be > 0");
    matrix6 A = matrix6::Zero(), B = matrix6::Zero();
    A.topLeftCorner<3, 3>().setOnes();
    for (int i = 0; i < 6; ++i) B(i, i) = i < 3 ? 2.0 : 1.0;
    auto ip = [](const matrix6& X, const matrix6& Y) { return (X.array() * Y.array()).sum(); };
    const double norm2 = ip(C, C);
    auto finish = [&](double E, double nu) {
        isotropic_fit f;
        f.E = E, f.nu = nu;
        f.residual = (isotropic_tensor(E, nu) - C).squaredNorm();
        f.relative_residual = norm2 > 0 ? std::sqrt(f.residual / norm2) : 0.0;
        return f;
    };
    if (norm2 == 0) return finish(0.0, 0.0);
    Eigen::Matrix2d M;
    M << ip(A, A), ip(A, B), ip(A, B), ip(B, B);
    const Eigen::Vector2d lm = M.inverse() * Eigen::Vector2d(ip(A, C), ip(B, C));
    const double lambda = lm(0), mu = lm(1);
    if (mu > 0 && 3 * lambda + 2 * mu > 0) {
        const double E = mu * (3 * lambda + 2 * mu) / (lambda + mu), nu = lambda / (2 * (lambda + mu));
        if (E <= E_max) return finish(E, nu);
    }
    // Constrained case: for fixed nu the objective is quadratic in E (C^I = E S(nu)).
    auto best_E = [&](double nu, double& obj) {
        const matrix6 S = isotropic_tensor(1.0, nu);
        const double E = std::clamp(ip(S, C) / ip(S, S), 0.0, E_max);
        obj = (E * S - C).squaredNorm();
        return E;
    };
    const double nu_hi = 0.5 - 1e-9;  // C^I is unbounded at nu = 1/2 for E > 0
    double best_nu = -1, best = std::numeric_limits<double>::infinity();
    constexpr int scan = 3000;
    for (int s = 0; s <= scan; ++s) {
        const double nu = -1.0 + (nu_hi + 1.0) * s / scan;
        double obj;
        best_E(nu, obj);
        if (obj < best) best = obj, best_nu = nu;
    }
    // Golden-section refinement in the bracketing scan interval.
    double a = std::max(-1.0, best_nu - (nu_hi + 1.0) / scan), b = std::min(nu_hi, best_nu + (nu_hi + 1.0) / scan);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 60; ++it) {
        const double c = b - g * (b - a), d = a + g * (b - a);
        double fc, fd;
        best_E(c, fc), best_E(d, fd);
        if (fc < fd) b = d;
        else a = c;
    }
    double obj;
    const double nu = 0.5 * (a + b);
    const double E = best_E(nu, obj);
    return finish(E, nu);
}

/// Periodic homogenization of a voxel cell (see the file comment).
/// @param grid one period of the microstructure: densities in [0, 1], voxel size grid.spacing() [mm]
///             (only ratios matter: C^H does not depend on the cell's scale)
/// @param material base material (E [MPa], nu)
/// @param progress called as (fraction, "homogenization") over the six load cases
/// @throws invalid_input for bad densities, no_solution if no solid part spans the cell,
///         solver_error if a solve fails
template <voxel_density_grid G, progress_callback P = no_progress>
homogenization_result homogenize(const G& grid, const isotropic_material& material, const homogenization_options& opt = {}, P&& progress = {}) {
    detail::validate_voxel_grid(grid, "homogenize");
    material.validate();
    opt.solver.validate();
    opt.law.validate();
    const ivec3 cells = grid.dims();
    const vec3 h = grid.spacing();
    std::vector<double> scale = detail::voxel_factors(grid, opt.law, cells);
    homogenization_result res;
    const std::size_t nvox = scale.size();
    {
        double sum = 0;
        for (int k = 0; k < cells.z; ++k)
            for (int j = 0; j < cells.y; ++j)
                for (int i = 0; i < cells.x; ++i) sum += static_cast<double>(grid.get(ivec3(i, j, k)));
        res.volume_fraction = sum / static_cast<double>(nvox);
    }

    // Remove floating islands; pin one node per remaining part.
    ivec3 unused;
    const int levels = opt.solver.solver == voxel_solver::multigrid ? detail::choose_levels(cells, true, opt.solver.coarsest_dofs, unused) : 1;
    const int stride = 1 << (levels - 1);  // pinned nodes on coarse-grid points keep the Galerkin hierarchy exact
    const detail::voxel_components comp = detail::label_voxel_components(cells, true, scale);
    std::size_t removed = 0;
    const detail::node_grid vox{cells, true};
    std::vector<std::int64_t> pin(comp.size.size(), -1), pin_any(comp.size.size(), -1);
    for (std::size_t e = 0; e < nvox; ++e) {
        const auto lab = comp.label[e];
        if (lab < 0) continue;
        const auto c = static_cast<std::size_t>(lab);
        if (!comp.wraps[c]) {
            scale[e] = 0.0;
            ++removed;
            continue;
        }
        if (pin[c] >= 0) continue;
        const ivec3 p = vox.coords(e);
        for (int a = 0; a < 8 && pin[c] < 0; ++a) {
            const ivec3 q = p + ivec3(detail::voxel_corner[a][0], detail::voxel_corner[a][1], detail::voxel_corner[a][2]);
            const std::int64_t n = vox.at(q);
            if (pin_any[c] < 0) pin_any[c] = n;
            if (q.x % stride == 0 && q.y % stride == 0 && q.z % stride == 0) pin[c] = n;
        }
    }
    res.removed_fraction = static_cast<double>(removed) / static_cast<double>(nvox);
    std::vector<std::uint8_t> state(3 * vox.count(), detail::dof_free);
    bool any = false;
    for (std::size_t c = 0; c < comp.size.size(); ++c) {
        if (!comp.wraps[c]) continue;
        any = true;
        const std::int64_t n = pin[c] >= 0 ? pin[c] : pin_any[c];
        for (int d = 0; d < 3; ++d) state[3 * static_cast<std::size_t>(n) + static_cast<std::size_t>(d)] = detail::dof_fixed;
    }
    if (!any)
        throw no_solution("homogenize: no solid part connects to its periodic images (the cell is void or made of floating islands), "
                          "so the effective stiffness is zero");

    report_progress(progress, 0.0, "homogenization setup");
    const detail::voxel_element el(h, material);
    detail::voxel_engine eng(cells, true, scale, el, state, levels, opt.solver);
    scale = {}, state = {};
    const detail::voxel_operator& op = eng.op();

    // Element loads of the unit strains, per local node: f_i,a = K[rows a] u0_i.
    std::array<std::array<Eigen::Vector3d, 8>, 6> fe{};
    for (int i = 0; i < 6; ++i)
        for (int a = 0; a < 8; ++a) fe[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)] = el.rows[static_cast<std::size_t>(a)] * el.strain_field[static_cast<std::size_t>(i)];
    std::array<std::vector<double>, 6> chi;
    const double tol_log = std::log(opt.solver.tolerance);
    for (int i = 0; i < 6; ++i) {
        std::vector<double> f(3 * op.active.count(), 0.0);
        parallel_for(0, op.active.count(), [&](std::size_t n) {
            Eigen::Vector3d acc = Eigen::Vector3d::Zero();
            op.for_each_voxel_at_node(n, [&](int a, std::size_t v) { acc += op.scale[v] * fe[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)]; });
            for (int d = 0; d < 3; ++d) f[3 * n + static_cast<std::size_t>(d)] = acc(d);
        }, {.grain = 1024});
        res.stats[static_cast<std::size_t>(i)] = eng.solve(std::move(f), chi[static_cast<std::size_t>(i)], [&](int, double rel) {
            const double part = std::clamp(std::log(std::max(rel, 1e-300)) / tol_log, 0.0, 1.0);
            report_progress(progress, (i + part) / 6.0, "homogenization");
        });
    }

    // Energy form, reduced over the solid voxels in fixed blocks (deterministic).
    const matrix6 sum = parallel_reduce(
        0, op.scale.size(), matrix6(matrix6::Zero()),
        [&](std::size_t v) -> matrix6 {
            const auto& vn = op.corners[v];
            Eigen::Matrix<double, 24, 6> W;
            for (int i = 0; i < 6; ++i)
                for (int b = 0; b < 8; ++b)
                    for (int d = 0; d < 3; ++d)
                        W(3 * b + d, i) = el.strain_field[static_cast<std::size_t>(i)](3 * b + d) -
                                          chi[static_cast<std::size_t>(i)][3 * static_cast<std::size_t>(vn[static_cast<std::size_t>(b)]) + static_cast<std::size_t>(d)];
            return op.scale[v] * (W.transpose() * el.K * W);
        },
        [](matrix6 x, const matrix6& y) { return matrix6(x + y); }, {.grain = 2048});
    const double volume = cells.x * h.x * cells.y * h.y * cells.z * h.z;
    res.C = 0.5 * (sum + sum.transpose()) / volume;
    if (!res.C.allFinite()) throw solver_error("homogenize: the effective tensor is not finite");
    report_progress(progress, 1.0, "homogenization");
    return res;
}

}  // namespace fabsynth::fem
