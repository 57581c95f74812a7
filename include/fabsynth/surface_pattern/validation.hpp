// SPDX-License-Identifier: MIT
#pragma once
/// @file validation.hpp  Full-resolution finite element validation of a thickened pattern
/// (structurally-sound-patterns.md §6.3, Table 3): every voxel of the thickened pattern becomes a
/// hexahedral element, the object is fixed to the ground and loaded by its own weight, and the
/// statistics of |s1| + |s2| + |s3| over the elements are reported in Pa.
///
/// Model (validate_stress_field / validate_stress):
///  - Elements: one hex8 per voxel of the set (fem/voxel.hpp: matrix-free, multigrid-preconditioned
///    CG; no other solver). The FEM grid is the bounding box of the analysed voxels; the solver is
///    sparse (~25 bytes per node of that box, ~1.6 KB per solid voxel: the full bunny shell at
///    256^3 takes 1.3 GB and 26 s per load case, benchmarks/README.md).
///  - Supports: with d = gravity / |gravity| ("down") and the extent [a, b] of the voxel boxes
///    projected onto d, a voxel whose centre c has b - c.d <= support_fraction * (b - a) lies in the
///    bottom support_fraction of the extent; all 8 nodes of such a voxel are fixed (all three
///    components). These supported voxels carry no strain (score 0) and are left out of the
///    statistics; they are the "ground" (counted in fixed_elements).
///  - Load: the weight rho g V of each voxel along options.load_direction (default: gravity) as
///    consistent nodal loads of the trilinear hex8: rho g V / 8 on each of its 8 nodes (the integral
///    of each shape function over a box is V / 8). The supports always come from `gravity`, also
///    when the weight is turned: the paper's "unexpected" profile keeps the object fixed to the
///    ground and only changes the direction of the weight (§6.3, second half of Table 3); use
///    unexpected(options) for that case.
///  - Score: the stress at the element centre (natural coordinates 0, fem::hex8), its principal
///    stresses and |s1| + |s2| + |s3| (fem/stress.hpp principal_stress_score), in Pa.
///  - Statistics over the free (not supported) analysed elements: average, median (mean of the two
///    middle values for an even count), 99th percentile (linear interpolation between order
///    statistics at rank 0.99 (n - 1), i.e. the default "type 7" definition of R and NumPy) and max.
///
/// Units: the voxel grid is in mm and fem/ uses consistent mm-N-s-tonne units (material.hpp):
/// rho [kg/m^3] * g [m/s^2] = rho g [N/m^3] = 1e-9 rho g [N/mm^3]; forces are in N, stresses out of
/// the solver in MPa = N/mm^2 = 1e6 Pa. The material's own density field is not used: the weight
/// comes from validation_options::density_kg_m3 (so the load can be scaled without touching E).
///
/// Unsupported pieces: the stiffness of a piece without a fixed voxel is singular ("disconnected
/// structures lead to an under-determined system", §6.3). Pieces are the face-connected (6-connected)
/// components of the set, as in fem/voxel.hpp: voxels meeting only along an edge or at a corner
/// would hinge. A piece is supported iff it contains a supported voxel (a piece touching a fixed
/// node only along an edge or at a corner is not: it could rotate about it). Choice: by default the
/// unsupported pieces are left out and reported (unsupported_pieces, unsupported_voxels; their
/// scores are NaN); with validation_options::require_supported they make the call throw
/// no_solution naming how many pieces and voxels are unsupported.
///
/// Determinism: the solve and the stress recovery are bit-identical for any thread count
/// (fem/voxel.hpp, core/parallel.hpp); statistics are summed in voxel order.
///
/// Usage:
///   auto thick = fabsynth::surface_pattern::thicken_inward(l0.geometry, l0.voxels, l0.normals, solid, 1.2);
///   fabsynth::surface_pattern::validation_options o;                       // ABS, weight along -z
///   auto expected = fabsynth::surface_pattern::validate_stress(thick, o);   // Pa
///   auto unexpected = fabsynth::surface_pattern::validate_stress(thick, fabsynth::surface_pattern::unexpected(o));
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/hex8.hpp"
#include "fabsynth/fem/material.hpp"
#include "fabsynth/fem/stress.hpp"
#include "fabsynth/fem/voxel.hpp"
#include "fabsynth/surface_pattern/fabricate.hpp"
#include "fabsynth/voxel/neighbourhood.hpp"

namespace fabsynth::surface_pattern {

/// An upper estimate of the peak memory (bytes) of validating a solid on a grid of `resolution`
/// voxels along its longest side. The sparse voxel FEM (fem/voxel.hpp) costs ~25 bytes per node of
/// the box (at most (resolution + 1)^3) plus ~1.6 KB per solid voxel; the solid of a surface
/// pattern is a shell, estimated here as 12 resolution^2 voxels (the bunny's full 1.2 mm shell at
/// 256 is 644 k = 9.8 x 256^2 voxels): 60 B per box node and 20 KB x resolution^2 in all, with
/// room for the surface pipeline's own grids (2.3 GB at 256, 13 GB at 512). Measured peaks:
/// benchmarks/README.md.
[[nodiscard]] inline double validation_bytes(int resolution) {
    const double r = static_cast<double>(resolution);
    return 60.0 * std::pow(r + 1, 3) + 20000.0 * r * r;
}

struct validation_options {
    /// Elastic material (E [MPa], nu). Default ABS (fem/material.hpp: Stratasys ABSplus-P430, E =
    /// 2200 MPa, nu = 0.35), the material of §6.3. Its density field is ignored (density_kg_m3).
    fem::isotropic_material material = fem::isotropic_material::abs();
    /// Mass density [kg/m^3]. 1040: specific gravity 1.04 of the Stratasys ABSplus-P430 data sheet
    /// (the same source as material.hpp's ABS preset; generic ABS is 1040-1060, PLA about 1240).
    double density_kg_m3 = 1040;
    vec3 gravity{0, 0, -1};        ///< "down": defines the supports, and the weight unless load_direction is set
    vec3 load_direction{0, 0, 0};  ///< direction of the weight; (0, 0, 0) = gravity (see unexpected())
    double g = 9.81;               ///< gravitational acceleration [m/s^2]
    double support_fraction = 0.10;  ///< voxels in the first 10% of the extent along gravity are fixed, in (0, 1]
    double tolerance = 1e-6;       ///< CG: stop at ||f - K u|| <= tolerance ||f|| (fem/voxel.hpp)
    int max_iterations = 5000;     ///< CG iterations before solver_error (fem/voxel.hpp's default)
    bool require_supported = false;  ///< throw no_solution for unsupported pieces instead of leaving them out
    /// Optional supports: the voxels whose centre [mm] makes this true are fixed, instead of the
    /// support_fraction rule (e.g. structure_options::fixed, plane_support). The load stays the weight.
    std::function<bool(const vec3&)> fixed{};

    /// Throws invalid_input for non-finite or out-of-range values (zero gravity included).
    void validate() const {
        material.validate();
        if (!(std::isfinite(density_kg_m3) && density_kg_m3 > 0))
            throw invalid_input("validation: density must be finite and > 0 kg/m^3, got " + detail::num(density_kg_m3));
        if (!all_finite(gravity) || glm::length(gravity) == 0.0 || !std::isfinite(glm::length(gravity)))
            throw invalid_input("validation: gravity must be a finite non-zero direction");
        if (!all_finite(load_direction) || !std::isfinite(glm::length(load_direction)))
            throw invalid_input("validation: load_direction must be finite ((0, 0, 0) = gravity)");
        if (!(std::isfinite(g) && g > 0)) throw invalid_input("validation: g must be finite and > 0 m/s^2, got " + detail::num(g));
        if (!(support_fraction > 0 && support_fraction <= 1))
            throw invalid_input("validation: support_fraction must lie in (0, 1], got " + detail::num(support_fraction));
        if (!(tolerance > 0 && tolerance < 1)) throw invalid_input("validation: tolerance must lie in (0, 1)");
        if (max_iterations < 1) throw invalid_input("validation: max_iterations must be >= 1");
    }
};

/// Statistics of |s1| + |s2| + |s3| [Pa] over the free analysed elements (see the file comment).
struct stress_statistics {
    double average = 0, median = 0, p99 = 0, max = 0;  ///< Pa
    std::size_t elements = 0;            ///< elements in the statistics (free analysed voxels)
    std::size_t fixed_elements = 0;      ///< analysed voxels in the support zone (score 0, not in the statistics)
    std::size_t unsupported_voxels = 0;  ///< voxels of unsupported pieces, left out
    int unsupported_pieces = 0;          ///< face-connected pieces without a supported voxel
    std::size_t dofs = 0;                ///< free DOFs of the solve
    int iterations = 0;                  ///< CG iterations
    double seconds = 0;                  ///< wall time of the whole call
};

/// Per-voxel scores and their statistics.
struct stress_field {
    std::vector<double> score;  ///< per voxel of the set (same order) [Pa]: 0 in the support zone, NaN if left out
    stress_statistics stats;
};

/// The "unexpected" direction of §6.3, orthogonal to gravity: the coordinate axis e least aligned
/// with d = gravity / |gravity| (smallest |d_i|, ties to x, then y), made orthogonal to d and
/// normalized: (e - (e.d) d) / |...|. For gravity (0, 0, -1) this is (1, 0, 0), the paper's choice.
/// Throws invalid_input for a zero or non-finite gravity.
[[nodiscard]] inline vec3 unexpected_direction(const vec3& gravity) {
    const double len = glm::length(gravity);
    if (!all_finite(gravity) || !(std::isfinite(len) && len > 0)) throw invalid_input("unexpected_direction: gravity must be finite and non-zero");
    const vec3 d = gravity / len;
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (std::abs(d[a]) < std::abs(d[axis])) axis = a;
    vec3 e(0.0);
    e[axis] = 1.0;
    const vec3 u = e - glm::dot(e, d) * d;
    return u / glm::length(u);
}

/// Options for the unexpected load case: the same supports (from o.gravity), the weight along
/// unexpected_direction(o.gravity).
[[nodiscard]] inline validation_options unexpected(validation_options o) {
    o.load_direction = unexpected_direction(o.gravity);
    return o;
}

namespace detail {

/// Dense 0/1 densities over a box of the synthesis grid (a fem::voxel_density_grid).
struct box_densities {
    ivec3 size{0};
    vec3 voxel_size{1.0};
    std::vector<std::uint8_t> solid;
    [[nodiscard]] ivec3 dims() const noexcept { return size; }
    [[nodiscard]] vec3 spacing() const noexcept { return voxel_size; }
    [[nodiscard]] std::size_t index(const ivec3& p) const noexcept {
        return static_cast<std::size_t>(p.x) +
               static_cast<std::size_t>(size.x) * (static_cast<std::size_t>(p.y) + static_cast<std::size_t>(size.y) * static_cast<std::size_t>(p.z));
    }
    [[nodiscard]] double get(const ivec3& p) const noexcept { return solid[index(p)]; }
};
static_assert(fem::voxel_density_grid<box_densities>);

/// Value at rank q (n - 1) of sorted values, linearly interpolated (type 7).
[[nodiscard]] inline double sorted_quantile(const std::vector<double>& v, double q) {
    const double r = q * static_cast<double>(v.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(r));
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (r - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

}  // namespace detail

/// Full-resolution FEA of the thickened pattern `solid` (see the file comment): per-voxel
/// |s1| + |s2| + |s3| at the element centres [Pa] and their statistics.
/// @throws invalid_input for an invalid or empty set or bad options; no_solution if no voxel is
///         supported, or for unsupported pieces with require_supported; solver_error if CG fails
template <progress_callback P = no_progress>
[[nodiscard]] stress_field validate_stress_field(const voxel_set& solid, const validation_options& opt, P&& progress = {}) {
    const auto t0 = std::chrono::steady_clock::now();
    validate(solid, "validate_stress");
    opt.validate();
    if (solid.empty()) throw invalid_input("validate_stress: the voxel set is empty");
    const grid_geometry& geo = solid.geometry;
    const vec3 h = geo.spacing;
    const std::size_t n = solid.size();

    // Supports: the bottom support_fraction of the extent along d (voxel boxes projected on d).
    const vec3 d = glm::normalize(opt.gravity);
    const double half = 0.5 * (std::abs(d.x) * h.x + std::abs(d.y) * h.y + std::abs(d.z) * h.z);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    std::vector<double> depth(n);
    for (std::size_t i = 0; i < n; ++i) {
        depth[i] = glm::dot(geo.center(solid.voxels[i]), d);
        lo = std::min(lo, depth[i] - half), hi = std::max(hi, depth[i] + half);
    }
    const double cut = opt.support_fraction * (hi - lo);
    std::vector<std::uint8_t> fixed(n);
    for (std::size_t i = 0; i < n; ++i) fixed[i] = (opt.fixed ? opt.fixed(geo.center(solid.voxels[i])) : hi - depth[i] <= cut) ? 1 : 0;

    // Face-connected pieces; keep those with a supported voxel.
    const voxel_set_components cc = set_components(solid, connectivity::c6{});
    std::vector<std::uint8_t> piece_ok(static_cast<std::size_t>(cc.count), 0);
    for (std::size_t i = 0; i < n; ++i)
        if (fixed[i]) piece_ok[static_cast<std::size_t>(cc.labels[i])] = 1;
    stress_field out;
    stress_statistics& st = out.stats;
    for (int c = 0; c < cc.count; ++c)
        if (!piece_ok[static_cast<std::size_t>(c)]) ++st.unsupported_pieces, st.unsupported_voxels += static_cast<std::size_t>(cc.sizes[static_cast<std::size_t>(c)]);
    if (st.unsupported_voxels == n)
        throw no_solution("validate_stress: no voxel lies in the support zone of a piece (" + std::to_string(cc.count) + " pieces)");
    if (opt.require_supported && st.unsupported_pieces > 0)
        throw no_solution("validate_stress: " + std::to_string(st.unsupported_pieces) + " of " + std::to_string(cc.count) + " pieces (" +
                          std::to_string(st.unsupported_voxels) + " of " + std::to_string(n) +
                          " voxels) have no voxel in the support zone; disconnected structures cannot be simulated");
    auto analysed = [&](std::size_t i) { return piece_ok[static_cast<std::size_t>(cc.labels[i])] != 0; };

    // The FEM grid: the bounding box of the analysed voxels.
    ivec3 bmin(std::numeric_limits<int>::max()), bmax(std::numeric_limits<int>::min());
    for (std::size_t i = 0; i < n; ++i)
        if (analysed(i)) bmin = glm::min(bmin, solid.voxels[i]), bmax = glm::max(bmax, solid.voxels[i]);
    detail::box_densities grid;
    grid.size = bmax - bmin + 1;
    grid.voxel_size = h;
    grid.solid.assign(static_cast<std::size_t>(grid.size.x) * static_cast<std::size_t>(grid.size.y) * static_cast<std::size_t>(grid.size.z), 0);
    fem::voxel_boundary_conditions bc(grid.size);
    // Weight per voxel [N]: rho g [N/m^3] * 1e-9 [m^3/mm^3] * V [mm^3]; an eighth of it on each node.
    const vec3 load = glm::length(opt.load_direction) > 0 ? glm::normalize(opt.load_direction) : d;
    const vec3 nodal = load * (opt.density_kg_m3 * opt.g * 1e-9 * h.x * h.y * h.z / 8.0);
    for (std::size_t i = 0; i < n; ++i) {
        if (!analysed(i)) continue;
        const ivec3 p = solid.voxels[i] - bmin;
        grid.solid[grid.index(p)] = 1;
        for (const auto& c : fem::detail::voxel_corner) {
            if (fixed[i]) bc.fix(p.x + c[0], p.y + c[1], p.z + c[2]);
            bc.add_force(p.x + c[0], p.y + c[1], p.z + c[2], nodal);
        }
    }
    // Everything analysed is supported (no free voxel): zero displacement, nothing to solve.
    const bool any_free = [&] {
        for (std::size_t i = 0; i < n; ++i)
            if (analysed(i) && !fixed[i]) return true;
        return false;
    }();
    fem::voxel_solution sol;
    if (any_free) {
        const fem::voxel_solver_options so{.tolerance = opt.tolerance, .max_iterations = opt.max_iterations};
        sol = fem::solve_voxel_elasticity(grid, opt.material, bc, so, {}, progress);
    } else {
        sol.cells = grid.size;  // no node: every displacement is 0
    }
    st.dofs = sol.stats.dofs;
    st.iterations = sol.stats.iterations;

    // Centre stress = S0 u_e with S0 (6 x 24) the hex8 centre stress of unit nodal displacements.
    fem::hex8::nodes_t X{};
    for (int a = 0; a < 8; ++a)
        X[static_cast<std::size_t>(a)] = vec3(fem::detail::voxel_corner[a][0], fem::detail::voxel_corner[a][1], fem::detail::voxel_corner[a][2]) * h;
    Eigen::Matrix<double, 6, 24> S0;
    for (int j = 0; j < 24; ++j) {
        fem::hex8::vector_t e = fem::hex8::vector_t::Zero();
        e(j) = 1.0;
        S0.col(j) = fem::hex8::stress(X, opt.material, e, fem::hex8::centroid());
    }
    out.score.assign(n, std::numeric_limits<double>::quiet_NaN());
    parallel_for(0, n, [&](std::size_t i) {
        if (!analysed(i)) return;
        if (fixed[i]) { out.score[i] = 0.0; return; }
        const ivec3 p = solid.voxels[i] - bmin;
        fem::hex8::vector_t ue;
        for (int a = 0; a < 8; ++a) {
            const auto& c = fem::detail::voxel_corner[a];
            const vec3 u = sol.displacement(p.x + c[0], p.y + c[1], p.z + c[2]);
            for (int k = 0; k < 3; ++k) ue(3 * a + k) = u[k];
        }
        out.score[i] = 1e6 * fem::principal_stress_score(S0 * ue);  // MPa -> Pa
    }, {.grain = 1024});

    std::vector<double> free_scores;
    for (std::size_t i = 0; i < n; ++i) {
        if (!analysed(i)) continue;
        if (fixed[i]) ++st.fixed_elements;
        else free_scores.push_back(out.score[i]);
    }
    st.elements = free_scores.size();
    if (!free_scores.empty()) {
        double sum = 0;
        for (double v : free_scores) sum += v;  // voxel order: deterministic
        st.average = sum / static_cast<double>(free_scores.size());
        std::sort(free_scores.begin(), free_scores.end());
        st.median = detail::sorted_quantile(free_scores, 0.5);
        st.p99 = detail::sorted_quantile(free_scores, 0.99);
        st.max = free_scores.back();
    }
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

/// Statistics of validate_stress_field (the numbers of Table 3).
template <progress_callback P = no_progress>
[[nodiscard]] stress_statistics validate_stress(const voxel_set& solid, const validation_options& opt, P&& progress = {}) {
    return validate_stress_field(solid, opt, std::forward<P>(progress)).stats;
}

}  // namespace fabsynth::surface_pattern
