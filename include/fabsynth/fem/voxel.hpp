// SPDX-License-Identifier: MIT
#pragma once
/// @file voxel.hpp  Linear elasticity on voxel grids: every solid voxel is a hex8 element with
/// shared nodes, solved matrix-free by multigrid-preconditioned CG (scales to millions of DOFs).
///
/// Grid and nodes: a grid of (nx, ny, nz) voxels of size spacing (mm) has (nx+1)(ny+1)(nz+1)
/// nodes; node (i, j, k) is at origin + spacing * (i, j, k) and has index i + (nx+1)(j + (ny+1)k)
/// (voxel_node_index). Voxel (i, j, k) has hex8 corners (i..i+1, j..j+1, k..k+1) in VTK order.
///
/// Densities: voxel density rho in [0, 1]; rho == 0 is void (no element), rho > 0 is an element
/// with Young's modulus E * voxel_stiffness_law::factor(rho) = E * max(rho, min_density)^penalty
/// (penalty 1 = linear, 3 = the usual SIMP value; min_density is a stiffness floor for soft voxels).
/// Poisson's ratio is the same for every voxel.
///
/// Solvers (voxel_solver_options::solver):
///  - multigrid (default): CG preconditioned by a geometric multigrid V-cycle. The fine operator
///    is never assembled: the 24x24 voxel matrix is computed once (fem::hex8) and applied node by
///    node. Level 1 is the exact Galerkin operator (built from 8 precomputed child matrices),
///    deeper levels Galerkin products of 27-point stencils; Chebyshev-Jacobi smoothing; sparse
///    LDL^T on the coarsest grid. Non-periodic grids are padded with void voxels (invisible to the
///    caller) so that they coarsen by 2 several times. Memory: about 0.7 KB per node in total
///    (vectors, plus 1.9 KB stencils per level-1 node, i.e. per 8 fine nodes); measured peaks are
///    in benchmarks/README.md.
///  - jacobi: matrix-free CG with diagonal preconditioning (small problems, or as a baseline).
///  - direct: assembled sparse LDL^T (Eigen); refused above max_direct_dofs.
///
/// Determinism: all loops run through core/parallel.hpp with node-wise gathers and fixed-block
/// reductions, so results are bit-identical for any thread count.
///
/// Singular systems: solid voxels are grouped into face-connected parts; a part that contains no
/// fixed node is unsupported and makes solve_voxel_elasticity throw solver_error naming a voxel
/// of it (voxels attached only along an edge or a corner count as separate parts: they would
/// hinge). Failure to converge within max_iterations throws solver_error too.
///
/// Usage (a cantilever clamped at x = 0, pulled down at x = L):
///   fabsynth::voxel_grid<double> g({64, 16, 16}, {0, 0, 0}, 1.0, 1.0);    // all solid, 1 mm voxels
///   fabsynth::fem::voxel_boundary_conditions bc(g.dims());
///   for (int k = 0; k <= 16; ++k) for (int j = 0; j <= 16; ++j) { bc.fix(0, j, k); bc.add_force(64, j, k, {0, 0, -1}); }
///   auto sol = fabsynth::fem::solve_voxel_elasticity(g, fabsynth::fem::isotropic_material::pla(), bc);
///   sol.displacement[fabsynth::fem::voxel_node_index(g.dims(), 64, 8, 8)];   // mm
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/detail/voxel_element.hpp"
#include "fabsynth/fem/detail/voxel_islands.hpp"
#include "fabsynth/fem/detail/voxel_multigrid.hpp"
#include "fabsynth/fem/detail/voxel_operators.hpp"
#include "fabsynth/fem/material.hpp"

namespace fabsynth::fem {

/// A grid of voxel densities: dims() voxel counts, spacing() voxel size [mm] per axis and
/// get(ivec3) the density in [0, 1] (fabsynth::voxel_grid<double> / <float> qualify). O(1) get.
template <class G>
concept voxel_density_grid = requires(const G& g, ivec3 p) {
    { g.dims() } -> std::convertible_to<ivec3>;
    { g.spacing() } -> std::convertible_to<vec3>;
    { g.get(p) } -> std::convertible_to<double>;
};

/// Non-owning voxel_density_grid over x-fastest densities (e.g. a VTK field):
/// values[i + dims.x * (j + dims.y * k)] is voxel (i, j, k); spacing is the voxel size [mm].
struct density_view {
    ivec3 size{0};
    vec3 voxel_size{1.0};
    std::span<const double> values;

    density_view(const ivec3& dims, const vec3& spacing, std::span<const double> v) : size(dims), voxel_size(spacing), values(v) {
        if (dims.x < 1 || dims.y < 1 || dims.z < 1 ||
            static_cast<double>(dims.x) * dims.y * dims.z != static_cast<double>(v.size()))
            throw invalid_input("density_view: " + std::to_string(v.size()) + " values do not fill a " + std::to_string(dims.x) + "x" +
                                std::to_string(dims.y) + "x" + std::to_string(dims.z) + " grid");
    }
    [[nodiscard]] ivec3 dims() const noexcept { return size; }
    [[nodiscard]] vec3 spacing() const noexcept { return voxel_size; }
    [[nodiscard]] double get(const ivec3& p) const noexcept {
        return values[static_cast<std::size_t>(p.x) +
                      static_cast<std::size_t>(size.x) * (static_cast<std::size_t>(p.y) + static_cast<std::size_t>(size.y) * static_cast<std::size_t>(p.z))];
    }
};

static_assert(voxel_density_grid<density_view>);

/// Voxel stiffness as a function of density (see the file comment).
struct voxel_stiffness_law {
    double penalty = 1.0;      ///< exponent p in E * rho^p (>= 1 recommended; > 0 required)
    double min_density = 0.0;  ///< stiffness floor for solid voxels, in [0, 1]

    void validate() const {
        if (!(std::isfinite(penalty) && penalty > 0))
            throw invalid_input("voxel_stiffness_law: penalty must be finite and > 0, got " + std::to_string(penalty));
        if (!(min_density >= 0 && min_density <= 1))
            throw invalid_input("voxel_stiffness_law: min_density must lie in [0, 1], got " + std::to_string(min_density));
    }
    /// Stiffness factor of a voxel of density rho (0 for void).
    [[nodiscard]] double factor(double rho) const {
        if (rho == 0.0) return 0.0;
        const double r = std::max(rho, min_density);
        return penalty == 1.0 ? r : std::pow(r, penalty);
    }
};

enum class voxel_solver { multigrid, jacobi, direct };

/// Parses "multigrid" / "jacobi" / "direct" (invalid_input otherwise).
inline voxel_solver parse_voxel_solver(const std::string& s) {
    if (s == "multigrid" || s == "mg") return voxel_solver::multigrid;
    if (s == "jacobi" || s == "cg") return voxel_solver::jacobi;
    if (s == "direct") return voxel_solver::direct;
    throw invalid_input("voxel solver '" + s + "' is unknown (use multigrid, jacobi or direct)");
}

struct voxel_solver_options {
    voxel_solver solver = voxel_solver::multigrid;
    double tolerance = 1e-8;               ///< stop at ||f - K u|| <= tolerance * ||f||
    int max_iterations = 5000;             ///< CG iterations before solver_error
    int smoothing_degree = 2;              ///< multigrid: Chebyshev degree of pre/post smoothing (1..8)
    std::size_t coarsest_dofs = 6000;      ///< multigrid: coarsen until at most this many DOFs (or no longer possible)
    std::size_t max_direct_dofs = 200000;  ///< direct: refuse larger systems (memory)

    void validate() const {
        if (!(tolerance > 0 && tolerance < 1)) throw invalid_input("voxel_solver_options: tolerance must lie in (0, 1)");
        if (max_iterations < 1) throw invalid_input("voxel_solver_options: max_iterations must be >= 1");
        if (smoothing_degree < 1 || smoothing_degree > 8) throw invalid_input("voxel_solver_options: smoothing_degree must lie in [1, 8]");
    }
};

/// What a solve did.
struct voxel_solve_stats {
    int iterations = 0;             ///< CG iterations
    double relative_residual = 0;   ///< ||f - K u|| / ||f|| reached
    int levels = 1;                 ///< multigrid levels (1 for jacobi/direct)
    std::size_t dofs = 0;           ///< free DOFs
    double setup_seconds = 0, solve_seconds = 0;
};

/// Node index of node (i, j, k) in a grid of `cells` voxels (non-periodic numbering).
[[nodiscard]] inline std::size_t voxel_node_index(const ivec3& cells, int i, int j, int k) {
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(cells.x + 1) *
                                             (static_cast<std::size_t>(j) + static_cast<std::size_t>(cells.y + 1) * static_cast<std::size_t>(k));
}

/// Nodal forces and fixed displacement components on the node grid of a voxel grid.
struct voxel_boundary_conditions {
    ivec3 cells{0};
    std::vector<vec3> force;           ///< per node [N]
    std::vector<std::uint8_t> fixed;   ///< per node: bit 0/1/2 = x/y/z displacement fixed to 0

    voxel_boundary_conditions() = default;
    explicit voxel_boundary_conditions(const ivec3& voxel_dims) : cells(voxel_dims) {
        if (voxel_dims.x < 1 || voxel_dims.y < 1 || voxel_dims.z < 1)
            throw invalid_input("voxel_boundary_conditions: voxel dims must be >= 1");
        const std::size_t n = voxel_node_index(cells, cells.x, cells.y, cells.z) + 1;
        force.assign(n, vec3(0.0));
        fixed.assign(n, 0);
    }
    /// Fixes the components in `mask` (default all three) of node (i, j, k).
    void fix(int i, int j, int k, std::uint8_t mask = 7) { fixed.at(voxel_node_index(cells, i, j, k)) |= mask; }
    void add_force(int i, int j, int k, const vec3& f) { force.at(voxel_node_index(cells, i, j, k)) += f; }
};

/// Result of solve_voxel_elasticity.
struct voxel_solution {
    std::vector<vec3> displacement;  ///< per node [mm] (0 at nodes without solid voxels)
    double compliance = 0;           ///< f . u [N mm]
    voxel_solve_stats stats;
};

namespace detail {

/// Copies densities into stiffness factors, validating each value.
template <voxel_density_grid G>
std::vector<double> voxel_factors(const G& grid, const voxel_stiffness_law& law, const ivec3& padded) {
    const ivec3 d = grid.dims();
    std::vector<double> s(static_cast<std::size_t>(padded.x) * static_cast<std::size_t>(padded.y) * static_cast<std::size_t>(padded.z), 0.0);
    for (int k = 0; k < d.z; ++k)
        for (int j = 0; j < d.y; ++j)
            for (int i = 0; i < d.x; ++i) {
                const double rho = static_cast<double>(grid.get(ivec3(i, j, k)));
                if (!(rho >= 0.0 && rho <= 1.0))
                    throw invalid_input("voxel densities: voxel (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                                        ") has density " + std::to_string(rho) + ", expected a value in [0, 1]");
                s[static_cast<std::size_t>(i) + static_cast<std::size_t>(padded.x) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(padded.y) * static_cast<std::size_t>(k))] =
                    law.factor(rho);
            }
    return s;
}

template <voxel_density_grid G>
void validate_voxel_grid(const G& grid, const char* what) {
    const ivec3 d = grid.dims();
    const vec3 h = grid.spacing();
    for (int a = 0; a < 3; ++a) {
        if (d[a] < 1 || d[a] > (1 << 14))
            throw invalid_input(std::string(what) + ": voxel dims must lie in [1, 16384], got " + std::to_string(d[a]));
        if (!(std::isfinite(h[a]) && h[a] > 0)) throw invalid_input(std::string(what) + ": voxel spacing must be finite and > 0");
    }
    // 2^31 nodes: beyond that int-based coordinates overflow (and memory is long exhausted).
    if (static_cast<double>(d.x + 1) * (d.y + 1) * (d.z + 1) > 2.0e9) throw invalid_input(std::string(what) + ": grid too large");
}

/// Number of multigrid levels and the padded voxel dims for a grid. Non-periodic grids are padded
/// with void voxels to a multiple of 2^(levels-1) (at most +50% voxels). Periodic grids cannot be
/// padded: they need even voxel counts for the first coarsening (else a single level), after
/// which odd node counts coarsen too (see axis_transfer).
inline int choose_levels(const ivec3& cells, bool periodic, std::size_t coarsest_dofs, ivec3& padded) {
    padded = cells;
    if (periodic) {
        if (cells.x % 2 || cells.y % 2 || cells.z % 2) return 1;
        ivec3 n = cells;
        int L = 1;
        while (3.0 * n.x * n.y * n.z > static_cast<double>(coarsest_dofs) && L < 12 && (n.x > 2 || n.y > 2 || n.z > 2)) {
            for (int a = 0; a < 3; ++a) n[a] = (n[a] + 1) / 2;
            ++L;
        }
        return L;
    }
    auto dofs_at = [&](const ivec3& c) { return 3.0 * double(c.x + 1) * (c.y + 1) * (c.z + 1); };
    int L = 0;
    const double vol = double(cells.x) * cells.y * cells.z;
    for (;;) {
        const int f = 1 << L;
        if (dofs_at(padded / f) <= static_cast<double>(coarsest_dofs) || L >= 11) break;
        const int g = f * 2;
        ivec3 cand;
        bool ok = true;
        for (int a = 0; a < 3; ++a) {
            cand[a] = (cells[a] + g - 1) / g * g;
            if (cand[a] / g < 1) ok = false;
        }
        if (!ok || double(cand.x) * cand.y * cand.z > 1.5 * vol) break;
        padded = cand;
        ++L;
    }
    return L + 1;
}

/// Ready-to-solve voxel stiffness system (fine operator + preconditioner).
class voxel_engine {
public:
    /// cells: voxel counts; scale: per box voxel (0 = void); state: per box DOF (3 per node of the
    /// box: cells + 1 per axis, or cells when periodic), free or fixed.
    voxel_engine(const ivec3& cells, bool periodic, const std::vector<double>& scale, const voxel_element& el,
                 const std::vector<std::uint8_t>& state, int levels, const voxel_solver_options& opt)
        : opt_(opt), op_(make_voxel_operator(cells, periodic, scale, el, state)) {
        dofs_ = static_cast<std::size_t>(std::count(op_.state.begin(), op_.state.end(), dof_free));
        // A grid that cannot coarsen (periodic with odd voxel counts) is solved directly when
        // small, else by Jacobi-CG.
        const bool mg = opt.solver == voxel_solver::multigrid && (levels > 1 || dofs_ <= opt.max_direct_dofs);
        if (mg) {
            mg_ = std::make_unique<voxel_multigrid>(op_, levels, multigrid_settings{.smoothing_degree = opt.smoothing_degree,
                                                                                    .coarsest_dofs = opt.coarsest_dofs});
        } else if (opt.solver == voxel_solver::direct) {
            if (dofs_ > opt.max_direct_dofs)
                throw invalid_input("voxel FEM: the direct solver is limited to " + std::to_string(opt.max_direct_dofs) + " DOFs, this problem has " +
                                    std::to_string(dofs_) + "; use the multigrid solver");
            mg_ = std::make_unique<voxel_multigrid>(op_, 1, multigrid_settings{});
        } else {
            const std::vector<double> diag = op_.diagonal();
            inv_diag_.resize(diag.size());
            for (std::size_t i = 0; i < diag.size(); ++i) inv_diag_[i] = op_.state[i] == dof_free && diag[i] > 0 ? 1.0 / diag[i] : 1.0;
        }
        setup_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    }

    /// The fine operator: its active nodes (op().active) number the vectors of solve().
    [[nodiscard]] const voxel_operator& op() const noexcept { return op_; }
    [[nodiscard]] std::size_t free_dofs() const noexcept { return dofs_; }

    /// Solves K x = b on the active nodes (3 per op().active node; b is zeroed on non-free DOFs
    /// first; x starts at 0). on_it(iteration, rel).
    template <class OnIt>
    voxel_solve_stats solve(std::vector<double> b, std::vector<double>& x, OnIt&& on_it) {
        const auto t0 = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i < b.size(); ++i)
            if (op_.state[i] != dof_free) b[i] = 0.0;
        x.assign(b.size(), 0.0);
        auto apply = [&](const std::vector<double>& v, std::vector<double>& y) { op_.apply(v, y); };
        pcg_report rep;
        if (mg_) {
            rep = pcg("voxel FEM", apply, [&](const std::vector<double>& r, std::vector<double>& z) { mg_->precondition(r, z); }, b, x, opt_.tolerance,
                      opt_.max_iterations, on_it);
        } else {
            rep = pcg("voxel FEM", apply,
                      [&](const std::vector<double>& r, std::vector<double>& z) {
                          parallel_for(0, r.size(), [&](std::size_t i) { z[i] = inv_diag_[i] * r[i]; }, {.grain = 8192});
                      },
                      b, x, opt_.tolerance, opt_.max_iterations, on_it);
        }
        for (double v : x)
            if (!std::isfinite(v)) throw solver_error("voxel FEM: the solution is not finite (singular stiffness matrix?)");
        if (!rep.converged)
            throw solver_error("voxel FEM: CG did not converge in " + std::to_string(opt_.max_iterations) + " iterations (relative residual " +
                               std::to_string(rep.relative_residual) + ", tolerance " + std::to_string(opt_.tolerance) + ")");
        voxel_solve_stats s;
        s.iterations = rep.iterations;
        s.relative_residual = rep.relative_residual;
        s.levels = mg_ ? mg_->num_levels() : 1;
        s.dofs = dofs_;
        s.setup_seconds = setup_seconds_;
        s.solve_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return s;
    }

private:
    std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();  // first member: setup time includes op_
    voxel_solver_options opt_;
    voxel_operator op_;
    std::unique_ptr<voxel_multigrid> mg_;
    std::vector<double> inv_diag_;
    std::size_t dofs_ = 0;
    double setup_seconds_ = 0;
};

}  // namespace detail

/// Solves K u = f on the voxel grid with the given supports and loads.
/// @param grid densities in [0,1] (voxel_density_grid), voxel size from grid.spacing() [mm]
/// @param material base material (E [MPa], nu); density scales E through `law`
/// @param bc forces [N] and fixed components on the (nx+1)(ny+1)(nz+1) node grid
/// @param progress called as (fraction, "voxel FEM") during CG (fraction from the residual)
/// @throws invalid_input for bad densities/options, solver_error for unsupported parts or no convergence
template <voxel_density_grid G, progress_callback P = no_progress>
voxel_solution solve_voxel_elasticity(const G& grid, const isotropic_material& material, const voxel_boundary_conditions& bc,
                                      const voxel_solver_options& opt = {}, const voxel_stiffness_law& law = {}, P&& progress = {}) {
    detail::validate_voxel_grid(grid, "solve_voxel_elasticity");
    material.validate();
    opt.validate();
    law.validate();
    const ivec3 cells = grid.dims();
    if (bc.cells != cells || bc.force.size() != voxel_node_index(cells, cells.x, cells.y, cells.z) + 1 || bc.fixed.size() != bc.force.size())
        throw invalid_input("solve_voxel_elasticity: boundary conditions were made for a different grid");
    for (std::size_t n = 0; n < bc.force.size(); ++n)
        if (!all_finite(bc.force[n])) throw invalid_input("solve_voxel_elasticity: force at node " + std::to_string(n) + " is not finite");

    ivec3 padded = cells;
    const int levels = opt.solver == voxel_solver::multigrid ? detail::choose_levels(cells, false, opt.coarsest_dofs, padded) : 1;
    std::vector<double> scale = detail::voxel_factors(grid, law, padded);
    const detail::node_grid nodes{padded + 1, false};
    auto padded_node = [&](std::size_t n) {
        const int nx = cells.x + 1, ny = cells.y + 1;
        const int i = static_cast<int>(n % static_cast<std::size_t>(nx)), j = static_cast<int>((n / static_cast<std::size_t>(nx)) % static_cast<std::size_t>(ny)),
                  k = static_cast<int>(n / (static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny)));
        return nodes.index(i, j, k);
    };

    // Every face-connected solid part needs a fixed node.
    const detail::voxel_components comp = detail::label_voxel_components(padded, false, scale);
    std::vector<std::uint8_t> supported(comp.size.size(), 0);
    std::vector<std::uint8_t> state(3 * nodes.count(), detail::dof_free);
    for (std::size_t n = 0; n < bc.fixed.size(); ++n) {
        if (!bc.fixed[n]) continue;
        const std::size_t pn = padded_node(n);
        for (int d = 0; d < 3; ++d)
            if (bc.fixed[n] & (1u << d)) state[3 * pn + static_cast<std::size_t>(d)] = detail::dof_fixed;
        const ivec3 p = nodes.coords(pn);
        for (int a = 0; a < 8; ++a) {
            const ivec3 c = p - ivec3(detail::voxel_corner[a][0], detail::voxel_corner[a][1], detail::voxel_corner[a][2]);
            if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= padded.x || c.y >= padded.y || c.z >= padded.z) continue;
            const auto lab = comp.label[static_cast<std::size_t>(c.x) + static_cast<std::size_t>(padded.x) * (static_cast<std::size_t>(c.y) + static_cast<std::size_t>(padded.y) * static_cast<std::size_t>(c.z))];
            if (lab >= 0) supported[static_cast<std::size_t>(lab)] = 1;
        }
    }
    for (std::size_t c = 0; c < supported.size(); ++c)
        if (!supported[c]) {
            const ivec3 v = detail::node_grid{padded, false}.coords(comp.first[c]);
            throw solver_error("solve_voxel_elasticity: the solid part of " + std::to_string(comp.size[c]) + " voxels containing voxel (" +
                               std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) +
                               ") touches no fixed node (voxels joined only by an edge or corner count as separate parts)");
        }

    const detail::voxel_element el(grid.spacing(), material);
    report_progress(progress, 0.0, "voxel FEM setup");
    detail::voxel_engine eng(padded, false, scale, el, state, levels, opt);
    scale = {}, state = {};
    const detail::node_set& active = eng.op().active;
    std::vector<double> f(3 * active.count(), 0.0), u;
    for (std::size_t n = 0; n < bc.force.size(); ++n) {
        if (bc.force[n] == vec3(0.0)) continue;
        const std::int32_t a = active.index[padded_node(n)];
        if (a < 0)
            throw invalid_input("solve_voxel_elasticity: a force acts on node " + std::to_string(n) + ", which touches no solid voxel");
        for (int d = 0; d < 3; ++d) f[3 * static_cast<std::size_t>(a) + static_cast<std::size_t>(d)] = bc.force[n][d];
    }
    const double tol_log = std::log(opt.tolerance);
    voxel_solution sol;
    sol.stats = eng.solve(f, u, [&](int, double rel) {
        report_progress(progress, std::clamp(std::log(std::max(rel, 1e-300)) / tol_log, 0.0, 1.0), "voxel FEM");
    });
    sol.displacement.assign(bc.force.size(), vec3(0.0));
    for (std::size_t n = 0; n < bc.force.size(); ++n) {
        const std::int32_t a = active.index[padded_node(n)];
        if (a < 0) continue;
        const auto i = 3 * static_cast<std::size_t>(a);
        sol.displacement[n] = vec3(u[i], u[i + 1], u[i + 2]);
        sol.compliance += glm::dot(sol.displacement[n], bc.force[n]);
    }
    report_progress(progress, 1.0, "voxel FEM");
    return sol;
}

}  // namespace fabsynth::fem
