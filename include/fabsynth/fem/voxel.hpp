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
///    is never assembled: the 24x24 voxel matrix is computed once (fem::hex8) and applied voxel by
///    voxel. Level 1 is the exact Galerkin operator (built from 8 precomputed child matrices),
///    deeper levels Galerkin products of 27-point stencils; Chebyshev-Jacobi smoothing; sparse
///    LDL^T on the coarsest grid. Non-periodic grids are padded with void voxels (invisible to the
///    caller) so that they coarsen by 2 several times, and stop coarsening before a level whose
///    coarse nodes would tie separate pieces of material together (voxel_solver_options::
///    max_split_fraction: thin strips of a carved pattern closer than the coarse spacing).
///    Sparse storage: every level keeps only its active nodes (those touching material), the fine
///    level only its solid voxels; the bounding box costs ~25 bytes per box node (densities,
///    component labels, fixed-DOF states, two int32 lookup tables), the solid about 1.6 KB per solid
///    voxel (vectors, level-1 stencils at 1.9 KB per active coarse node, coarse factor). A thin
///    shell of 556 k voxels in a 256^3 box: 1.5 GB peak, 24 s; peaks in benchmarks/README.md.
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
///   sol.displacement(64, 8, 8);   // mm
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
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
    /// multigrid on non-periodic grids: stop coarsening before a level where more than this
    /// fraction of the coarse nodes would tie separate pieces of material together (the solid
    /// voxels under a coarse node's support are not face-connected: strips of a carved pattern
    /// closer than the coarse spacing), as long as the level reached has at most
    /// max_split_coarse_dofs DOFs (its direct factorization stays cheap). 1 = never stop early.
    double max_split_fraction = 0.05;
    std::size_t max_split_coarse_dofs = 120000;  ///< multigrid: see max_split_fraction (DOFs of the level reached)
    std::size_t max_direct_dofs = 200000;  ///< direct: refuse larger systems (memory)

    void validate() const {
        if (!(tolerance > 0 && tolerance < 1)) throw invalid_input("voxel_solver_options: tolerance must lie in (0, 1)");
        if (max_iterations < 1) throw invalid_input("voxel_solver_options: max_iterations must be >= 1");
        if (smoothing_degree < 1 || smoothing_degree > 8) throw invalid_input("voxel_solver_options: smoothing_degree must lie in [1, 8]");
        if (!(max_split_fraction >= 0 && max_split_fraction <= 1)) throw invalid_input("voxel_solver_options: max_split_fraction must lie in [0, 1]");
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

/// Nodal forces and fixed displacement components on the node grid of a voxel grid. Sparse: only
/// the nodes given a force or a fixed component are stored (a hash map, ~60 bytes per node), so a
/// thin shell in a large box costs what its nodes cost. Forces on one node add up in call order.
class voxel_boundary_conditions {
public:
    struct node_condition {
        std::size_t node = 0;     ///< voxel_node_index
        vec3 force{0.0};          ///< [N]
        std::uint8_t fixed = 0;   ///< bit 0/1/2 = x/y/z displacement fixed to 0
    };

    ivec3 cells{0};

    voxel_boundary_conditions() = default;
    explicit voxel_boundary_conditions(const ivec3& voxel_dims) : cells(voxel_dims) {
        if (voxel_dims.x < 1 || voxel_dims.y < 1 || voxel_dims.z < 1)
            throw invalid_input("voxel_boundary_conditions: voxel dims must be >= 1");
    }
    /// Fixes the components in `mask` (default all three) of node (i, j, k), 0 <= i <= cells.x etc.
    void fix(int i, int j, int k, std::uint8_t mask = 7) { slot(i, j, k).fixed |= mask; }
    /// Adds the force f [N] to node (i, j, k).
    void add_force(int i, int j, int k, const vec3& f) { slot(i, j, k).force += f; }
    /// The nodes with a condition, in ascending node index.
    [[nodiscard]] std::vector<node_condition> nodes() const {
        std::vector<node_condition> r;
        r.reserve(map_.size());
        for (const auto& [n, c] : map_) r.push_back({n, c.force, c.fixed});
        std::sort(r.begin(), r.end(), [](const node_condition& a, const node_condition& b) { return a.node < b.node; });
        return r;
    }

private:
    struct value {
        vec3 force{0.0};
        std::uint8_t fixed = 0;
    };
    value& slot(int i, int j, int k) {
        if (i < 0 || j < 0 || k < 0 || i > cells.x || j > cells.y || k > cells.z)
            throw invalid_input("voxel_boundary_conditions: node (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                                ") lies outside the " + std::to_string(cells.x + 1) + " x " + std::to_string(cells.y + 1) + " x " +
                                std::to_string(cells.z + 1) + " node grid");
        return map_[voxel_node_index(cells, i, j, k)];
    }
    std::unordered_map<std::size_t, value> map_;
};

/// Result of solve_voxel_elasticity: the displacements of the nodes that touch a solid voxel.
struct voxel_solution {
    ivec3 cells{0};
    std::vector<std::size_t> node;   ///< voxel_node_index of the nodes touching a solid voxel, ascending
    std::vector<vec3> u;             ///< displacement per entry of `node` [mm]
    double compliance = 0;           ///< f . u [N mm]
    voxel_solve_stats stats;

    /// Displacement of node (i, j, k) [mm]: 0 at nodes without a solid voxel. O(log nodes).
    [[nodiscard]] vec3 displacement(int i, int j, int k) const { return displacement(voxel_node_index(cells, i, j, k)); }
    /// The same by voxel_node_index.
    [[nodiscard]] vec3 displacement(std::size_t n) const {
        const auto it = std::lower_bound(node.begin(), node.end(), n);
        return it != node.end() && *it == n ? u[static_cast<std::size_t>(it - node.begin())] : vec3(0.0);
    }
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
inline int choose_levels(const ivec3& cells, bool periodic, std::size_t coarsest_dofs, ivec3& padded, int max_levels = 12) {
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
        if (dofs_at(padded / f) <= static_cast<double>(coarsest_dofs) || L >= 11 || L + 1 >= max_levels) break;
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

/// The number of multigrid levels at which coarsening stops tying separate pieces of material
/// together (voxel_solver_options::max_split_fraction): solid(p) tells whether voxel p of a grid
/// of `cells` voxels is solid; levels are made by 2 x 2 x 2 block unions. A coarse node of level
/// l + 1 spans the 4 x 4 x 4 level-l voxels around it (its trilinear support); when those solid
/// voxels are not face-connected, its shape function moves pieces the solid does not join, and the
/// coarse correction degrades (measured on a carved hooks pattern on the bunny at 256^3: 2 515 CG
/// iterations with 6 levels, 833 with 4, 258 with 3, 123 with 2; its split fractions per level are
/// 4%, 7%, 14%, 37%; a full shell's stay below 0.1%). Returns max_levels when no level splits.
/// The support pattern is a 64-bit mask, its pieces found by bit-parallel dilation.
template <class Solid>
int separation_levels(const ivec3& cells, Solid&& solid, int max_levels, double max_split, std::size_t max_coarse_dofs) {
    if (max_levels <= 1 || max_split >= 1) return max_levels;
    ivec3 n = cells;
    std::vector<std::uint8_t> s(static_cast<std::size_t>(n.x) * static_cast<std::size_t>(n.y) * static_cast<std::size_t>(n.z));
    parallel_for(0, static_cast<std::size_t>(n.z), [&](std::size_t k) {
        for (int j = 0; j < n.y; ++j)
            for (int i = 0; i < n.x; ++i)
                s[static_cast<std::size_t>(i) + static_cast<std::size_t>(n.x) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n.y) * k)] =
                    solid(ivec3(i, j, static_cast<int>(k))) ? 1 : 0;
    });
    // bits of the 4 x 4 x 4 pattern (bit x + 4 y + 16 z) that may move one step along +-x / +-y
    constexpr std::uint64_t x0 = 0x1111111111111111ull, x3 = x0 << 3, y0 = 0x000F000F000F000Full, y3 = y0 << 12;
    const auto pieces_joined = [&](std::uint64_t m) {
        std::uint64_t r = m & (~m + 1);  // lowest solid voxel
        for (;;) {
            const std::uint64_t d = (r | ((r & ~x3) << 1) | ((r & ~x0) >> 1) | ((r & ~y3) << 4) | ((r & ~y0) >> 4) | (r << 16) | (r >> 16)) & m;
            if (d == r) return r == m;
            r = d;
        }
    };
    for (int l = 0; l + 1 < max_levels; ++l) {
        const auto at = [&](int i, int j, int k) -> std::uint64_t {
            if (i < 0 || j < 0 || k < 0 || i >= n.x || j >= n.y || k >= n.z) return 0;
            return s[static_cast<std::size_t>(i) + static_cast<std::size_t>(n.x) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n.y) * static_cast<std::size_t>(k))];
        };
        const ivec3 m = (n + 1) / 2;
        // per z-plane of coarse nodes: level-l nodes touching solid (2 z-planes of fine nodes per
        // coarse plane, the last plane once) and coarse nodes with solid / split supports
        struct tally { std::size_t active = 0, coarse = 0, split = 0; };
        std::vector<tally> per(static_cast<std::size_t>(m.z + 1));
        parallel_for(0, per.size(), [&](std::size_t K) {
            tally t;
            const int k = static_cast<int>(K);
            for (int kk = 2 * k; kk <= std::min(2 * k + 1, n.z); ++kk)
                for (int j = 0; j <= n.y; ++j)
                    for (int i = 0; i <= n.x; ++i) {
                        std::uint64_t any = 0;
                        for (int c = 0; c < 8; ++c) any |= at(i - (c & 1), j - ((c >> 1) & 1), kk - (c >> 2));
                        t.active += any;
                    }
            for (int J = 0; J <= m.y; ++J)
                for (int I = 0; I <= m.x; ++I) {
                    std::uint64_t mask = 0;
                    for (int c = 0; c < 64; ++c) mask |= at(2 * I - 2 + (c & 3), 2 * J - 2 + ((c >> 2) & 3), 2 * k - 2 + (c >> 4)) << c;
                    if (!mask) continue;
                    ++t.coarse;
                    t.split += pieces_joined(mask) ? 0 : 1;
                }
            per[K] = t;
        }, {.grain = 1});
        tally sum;
        for (const tally& t : per) sum.active += t.active, sum.coarse += t.coarse, sum.split += t.split;
        if (static_cast<double>(sum.split) > max_split * static_cast<double>(sum.coarse) && 3 * sum.active <= max_coarse_dofs) return l + 1;
        std::vector<std::uint8_t> t(static_cast<std::size_t>(m.x) * static_cast<std::size_t>(m.y) * static_cast<std::size_t>(m.z));
        parallel_for(0, static_cast<std::size_t>(m.z), [&](std::size_t K) {
            const int k = static_cast<int>(K);
            for (int J = 0; J < m.y; ++J)
                for (int I = 0; I < m.x; ++I) {
                    std::uint64_t any = 0;
                    for (int c = 0; c < 8; ++c) any |= at(2 * I + (c & 1), 2 * J + ((c >> 1) & 1), 2 * k + (c >> 2));
                    t[static_cast<std::size_t>(I) + static_cast<std::size_t>(m.x) * (static_cast<std::size_t>(J) + static_cast<std::size_t>(m.y) * K)] =
                        static_cast<std::uint8_t>(any);
                }
        });
        s.swap(t);
        n = m;
    }
    return max_levels;
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
    if (bc.cells != cells) throw invalid_input("solve_voxel_elasticity: boundary conditions were made for a different grid");
    const std::vector<voxel_boundary_conditions::node_condition> conditions = bc.nodes();
    for (const auto& c : conditions)
        if (!all_finite(c.force)) throw invalid_input("solve_voxel_elasticity: force at node " + std::to_string(c.node) + " is not finite");

    ivec3 padded = cells;
    int levels = 1;
    if (opt.solver == voxel_solver::multigrid) {
        levels = detail::choose_levels(cells, false, opt.coarsest_dofs, padded);
        const int joined = detail::separation_levels(cells, [&](const ivec3& p) { return static_cast<double>(grid.get(p)) != 0.0; }, levels,
                                                     opt.max_split_fraction, opt.max_split_coarse_dofs);
        if (joined < levels) levels = detail::choose_levels(cells, false, opt.coarsest_dofs, padded, joined);
    }
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
    for (const auto& c : conditions) {
        if (!c.fixed) continue;
        const std::size_t pn = padded_node(c.node);
        for (int d = 0; d < 3; ++d)
            if (c.fixed & (1u << d)) state[3 * pn + static_cast<std::size_t>(d)] = detail::dof_fixed;
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
    for (const auto& c : conditions) {
        if (c.force == vec3(0.0)) continue;
        const std::int32_t a = active.index[padded_node(c.node)];
        if (a < 0)
            throw invalid_input("solve_voxel_elasticity: a force acts on node " + std::to_string(c.node) + ", which touches no solid voxel");
        for (int d = 0; d < 3; ++d) f[3 * static_cast<std::size_t>(a) + static_cast<std::size_t>(d)] = c.force[d];
    }
    const double tol_log = std::log(opt.tolerance);
    voxel_solution sol;
    sol.stats = eng.solve(f, u, [&](int, double rel) {
        report_progress(progress, std::clamp(std::log(std::max(rel, 1e-300)) / tol_log, 0.0, 1.0), "voxel FEM");
    });
    // Active nodes in padded box order are in ascending unpadded node order too.
    sol.cells = cells;
    sol.node.reserve(active.count());
    sol.u.reserve(active.count());
    for (std::size_t a = 0; a < active.count(); ++a) {
        const ivec3 p = active.pos[a];
        if (p.x > cells.x || p.y > cells.y || p.z > cells.z) continue;  // padding (no solid voxel: cannot happen)
        sol.node.push_back(voxel_node_index(cells, p.x, p.y, p.z));
        sol.u.emplace_back(u[3 * a], u[3 * a + 1], u[3 * a + 2]);
    }
    for (const auto& c : conditions) sol.compliance += glm::dot(sol.displacement(c.node), c.force);
    report_progress(progress, 1.0, "voxel FEM");
    return sol;
}

}  // namespace fabsynth::fem
