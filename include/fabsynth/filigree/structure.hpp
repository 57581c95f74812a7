// SPDX-License-Identifier: MIT
#pragma once
/// @file structure.hpp  Shell FEM of a flat filigree piece and the two phases of the structural
/// optimization of filigree-synthesis.md §5: weak nodes (von Mises stress above the yield
/// stress), the centres of weak regions where phase 1 inserts new elements, and phase 2's
/// thickening by 10% per iteration "until no weak nodes are detected".
///
/// Model (§5 "Finite Element Simulation": shell elements on the surface mesh with a preset
/// thickness): the fem_triangulation (reconstruct.hpp) becomes S3 shells (fem/shell3.hpp: CST
/// membrane + DKT bending) of thickness t in the plane z = 0, normals +z.
///
/// Load case chosen for a flat piece (the paper applies "pressure forces from the outside, applied
/// on all shell elements" plus gravity, §5, and leaves the scenario open): the piece lies
/// horizontally and is clamped (all six DOFs) along a support region, by default every node within
/// support_fraction (5%) of the bounding-box height above the lowest y, i.e. the piece is held at
/// its lowest 5% like a horizontal cantilever plate; it carries its self weight (density x
/// 9.81 m/s^2 per volume, -z) and a uniform pressure p on every element (-z, default 1 kPa: a hand
/// pressing on the piece). Both act out of plane, so the piece works in plate bending. Other ways
/// to hold it: structure_options::support (any set of nodes: an edge, a box, a hanging point) and
/// gravity_down (e.g. (0, 1, 0): the piece hangs upright in its plane and its weight pulls toward
/// the drawing's bottom, a membrane load; the pressure stays out of plane). Units: the
/// fem module's mm, N, MPa, t/mm^3; p [Pa] enters as p * 1e-6 MPa, g [m/s^2] as g * 1e3 mm/s^2.
///
/// Nodal stress: fem::nodal_von_mises (fem/stress.hpp), eq. (5) of §5 at each node: the MEAN over
/// the node's elements of that element's von Mises stress evaluated at the node, on the more
/// stressed face (zeta = +-1, where bending stress peaks). A node is weak iff its stress exceeds the
/// yield stress (strictly). The histogram is that of §8.3.1 / Fig. 21: bins of 5 MPa from 0 to 2 x
/// yield, then one open bin.
///
/// Usage:
///   auto tri = fabsynth::filigree::make_fem_triangulation(outline, 0.5);
///   fabsynth::filigree::structure_options opt;                        // ABS, 1 kPa, gravity, lowest 5%
///   auto rep = fabsynth::filigree::analyse_structure(tri, 1.2, opt);  // t = 1.2 mm
///   auto sites = fabsynth::filigree::weak_region_centres(rep, 5.0);   // phase 1: where to add elements
///   auto thick = fabsynth::filigree::thicken_until_strong(tri, 1.2, opt);  // phase 2
///
/// Errors: invalid_input for an empty triangulation, a thickness that is not finite and > 0, bad
/// options or no node in the support region; solver_error when a part of the piece is not
/// connected to any support (fem's check), the stiffness is singular, or the solution fails the
/// accuracy check of detail::structure::solve_checked. Deterministic for any thread count (the fem
/// assembly and stress recovery are).
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/fem/assembly.hpp"
#include "fabsynth/fem/boundary.hpp"
#include "fabsynth/fem/material.hpp"
#include "fabsynth/fem/mesh.hpp"
#include "fabsynth/fem/solve_context.hpp"
#include "fabsynth/fem/stress.hpp"
#include "fabsynth/filigree/reconstruct.hpp"

namespace fabsynth::filigree {

/// The printed materials: the plastics of §5 ("commonly used printing materials, typically ABS or
/// PLA"), and more for lamps and jewellery (PETG, laser-sintered PA12, laser-melted 316L steel and
/// Ti-6Al-4V). Names: material_name / parse_material.
enum class material_preset { abs, pla, petg, pa12, steel_316l, ti64 };

/// Elastic constants and yield stress of the printed material.
struct structure_material {
    fem::isotropic_material elastic;  ///< E [MPa], nu, density [t/mm^3]
    double yield_mpa = 0;             ///< yield stress [MPa]: nodes above it are weak (§5)
};

/// The presets. Elastic constants are the fem module's (fem/material.hpp states their data-sheet
/// sources), so that one ABS exists in the library. Yield stresses, data-sheet values, not
/// measurements:
///   ABS   40 MPa: the paper's value (§8.3.1: "The yield stress of the plastic material used in our
///         models is 40MPa"), inside the 35-45 MPa of typical ABS data sheets;
///   PLA   50 MPa: a typical data-sheet tensile yield of PLA (about 50-60 MPa; printed parts are
///         weaker across layers);
///   PETG  50 MPa: typical PETG filament data sheets (tensile yield 45-53 MPa);
///   PA12  48 MPa: EOS PA 2200's tensile strength (the sheet gives no separate yield stress, and
///         PA12 yields close to it);
///   316L 170 MPa: ASTM A240's minimum 0.2% proof stress of annealed 316L (laser-melted parts are
///         stronger, so this is on the safe side);
///   Ti-6Al-4V 880 MPa: ASM's typical yield of annealed Ti-6Al-4V.
[[nodiscard]] inline structure_material preset_material(material_preset p) {
    switch (p) {
        case material_preset::pla: return {fem::isotropic_material::pla(), 50.0};
        case material_preset::petg: return {fem::isotropic_material::petg(), 50.0};
        case material_preset::pa12: return {fem::isotropic_material::pa12(), 48.0};
        case material_preset::steel_316l: return {fem::isotropic_material::steel_316l(), 170.0};
        case material_preset::ti64: return {fem::isotropic_material::ti64(), 880.0};
        case material_preset::abs: break;
    }
    return {fem::isotropic_material::abs(), 40.0};
}

namespace detail::structure {
inline constexpr std::pair<material_preset, const char*> material_names[] = {
    {material_preset::abs, "abs"},   {material_preset::pla, "pla"},         {material_preset::petg, "petg"},
    {material_preset::pa12, "pa12"}, {material_preset::steel_316l, "316l"}, {material_preset::ti64, "ti64"}};
}  // namespace detail::structure

/// The preset's name: "abs", "pla", "petg", "pa12", "316l", "ti64".
[[nodiscard]] inline std::string material_name(material_preset p) {
    for (const auto& [m, name] : detail::structure::material_names)
        if (m == p) return name;
    return "abs";
}

/// The preset of a name of material_name (case-sensitive); throws invalid_input listing the names.
[[nodiscard]] inline material_preset parse_material(std::string_view name) {
    std::string known;
    for (const auto& [m, n] : detail::structure::material_names) {
        if (name == n) return m;
        known += known.empty() ? n : std::string(", ") + n;
    }
    throw invalid_input("material must be one of " + known + ", got '" + std::string(name) + "'");
}

/// A side of the flat piece's bounding box, as drawn (domain frame, y down: top = smallest y).
enum class support_side { top, bottom, left, right };

/// Load case, material and solver of the analysis (see the file comment).
struct structure_options {
    structure_material material = preset_material(material_preset::abs);
    double pressure_pa = 1000.0;    ///< uniform pressure on every element [Pa], pushing -z; finite (0 = none)
    double gravity_m_s2 = 9.81;     ///< self-weight acceleration [m/s^2]; finite (0 = none)
    /// Direction gravity acts in (unit length after normalization): -z, the piece lies flat; (0, 1, 0),
    /// the piece stands or hangs upright in its plane, gravity toward the drawing's bottom (y down).
    vec3 gravity_down{0.0, 0.0, -1.0};
    /// Clamp the nodes within support_fraction of the bounding box's extent from this side (top:
    /// y <= y_min + fraction * (y_max - y_min); bottom, left, right alike), fraction in [0, 1].
    support_side side = support_side::top;
    double support_fraction = 0.05;
    /// If set, replaces support_fraction: the nodes whose position [mm] it accepts are clamped.
    std::function<bool(const vec2&)> support{};
    std::string support_description{};  ///< names the support region in the error when no node lies in it
    double histogram_bin_mpa = 5.0; ///< bin width of the stress histogram [MPa], > 0
    fem::solve_options solver{};    ///< fem's default: automatic method choice

    /// Throws invalid_input naming the first bad option.
    void validate() const {
        material.elastic.validate();
        if (!(std::isfinite(material.yield_mpa) && material.yield_mpa > 0))
            throw invalid_input("structure: yield stress must be finite and > 0 MPa, got " + std::to_string(material.yield_mpa));
        if (!std::isfinite(pressure_pa)) throw invalid_input("structure: pressure must be finite (Pa)");
        if (!std::isfinite(gravity_m_s2)) throw invalid_input("structure: gravity must be finite (m/s^2)");
        if (!(std::isfinite(glm::length(gravity_down)) && glm::length(gravity_down) > 0))
            throw invalid_input("structure: the gravity direction must be finite and not zero");
        if (!(support_fraction >= 0.0 && support_fraction <= 1.0))
            throw invalid_input("structure: support fraction must lie in [0, 1], got " + std::to_string(support_fraction));
        if (!(std::isfinite(histogram_bin_mpa) && histogram_bin_mpa > 0))
            throw invalid_input("structure: histogram bin must be finite and > 0 MPa");
    }
};

/// Result of one analysis. Per-node vectors have one entry per vertex of the triangulation.
struct structural_report {
    std::vector<double> node_von_mises;     ///< [MPa] mean over adjacent elements, more stressed face (file comment)
    double max_von_mises = 0;               ///< [MPa]
    double weak_fraction = 0;               ///< weak nodes / nodes
    std::vector<std::uint32_t> weak_nodes;  ///< nodes with von Mises > yield, ascending
    std::vector<vec2> node_positions;       ///< [mm]
    /// Node counts per stress bin: [k b, (k+1) b) for k < ceil(2 yield / b), then [that, inf); b = 5 MPa.
    std::vector<std::size_t> histogram;
    double thickness = 0;                   ///< [mm]
    double yield = 0;                       ///< [MPa] the criterion used
    std::vector<double> node_deflection;    ///< uz [mm] (negative = down)
    double max_deflection = 0;              ///< max |uz| [mm]
    std::vector<std::uint32_t> support_nodes;  ///< clamped nodes, ascending
    vec3 support_reaction{0.0};             ///< total force the supports exert on the piece [N]
    std::string solver;                     ///< fem method used
};

/// Phase 1 of §5 as a model: S3 shells of thickness [mm] over the triangulation (z = 0, normals +z),
/// one section of `material`.
[[nodiscard]] inline fem::mesh shell_model(const fem_triangulation& tri, double thickness, const structure_material& material) {
    if (tri.mesh.triangles.empty()) throw invalid_input("structure: the triangulation is empty (no triangles)");
    require_positive(thickness, "structure: thickness (mm)");
    fem::mesh m;
    m.nodes.reserve(tri.mesh.vertices.size());
    for (const vec2& p : tri.mesh.vertices) m.nodes.emplace_back(p.x, p.y, 0.0);
    m.sections.push_back({material.elastic, thickness});
    m.elements.reserve(tri.mesh.triangles.size());
    for (const auto& t : tri.mesh.triangles) m.elements.push_back(fem::make_element<fem::shell3>(t));
    return m;
}

/// The clamped nodes (ascending): opt.support if set, else the band of support_fraction of the
/// bounding box along opt.side (nodes of some triangle only). Throws invalid_input if there is none.
[[nodiscard]] inline std::vector<std::uint32_t> support_nodes(const fem_triangulation& tri, const structure_options& opt) {
    std::vector<char> used(tri.mesh.vertices.size(), 0);
    for (const auto& t : tri.mesh.triangles)
        for (std::uint32_t v : t) used[v] = 1;
    box2 b;
    for (std::size_t i = 0; i < used.size(); ++i)
        if (used[i]) b.extend(tri.mesh.vertices[i]);
    const bool vertical = opt.side == support_side::top || opt.side == support_side::bottom;
    const int axis = vertical ? 1 : 0;
    const double extent = b.size()[axis];
    const double band = opt.support_fraction * extent + 1e-9 * extent;  // fraction 0: the extreme edge
    const bool low = opt.side == support_side::top || opt.side == support_side::left;
    std::vector<std::uint32_t> out;
    for (std::uint32_t i = 0; i < used.size(); ++i) {
        if (!used[i]) continue;
        const vec2 p = tri.mesh.vertices[i];
        const bool in_band = low ? p[axis] <= b.lo[axis] + band : p[axis] >= b.hi[axis] - band;
        if (opt.support ? opt.support(p) : in_band) out.push_back(i);
    }
    if (out.empty())
        throw invalid_input("structure: no node lies in the support region" +
                            (opt.support_description.empty() ? std::string() : " (" + opt.support_description + ")") + " (nothing holds the piece)");
    return out;
}

/// The load case of the file comment on model m: all six DOFs of `supports` fixed, gravity and
/// pressure on every element.
/// `down`: the unit direction gravity acts in (opt.gravity_down for the flat piece; -up on a base surface).
[[nodiscard]] inline fem::load_case structural_load_case(const fem::mesh& m, std::span<const std::uint32_t> supports,
                                                         const structure_options& opt, vec3 down = {0, 0, -1}) {
    fem::load_case lc;
    for (std::uint32_t n : supports)
        for (int d = 0; d < 6; ++d) lc.fixed.push_back({n, d});
    for (std::uint32_t e = 0; e < m.elements.size(); ++e) {
        if (opt.gravity_m_s2 != 0.0) lc.gravity.push_back({e, down * (opt.gravity_m_s2 * 1e3)});  // m/s^2 -> mm/s^2
        if (opt.pressure_pa != 0.0) lc.pressures.push_back({e, opt.pressure_pa * 1e-6});                    // Pa -> MPa, +p pushes -z
    }
    return lc;
}

namespace detail::structure {

/// fem's solve (solve_context with opt's method: automatic by default) with a residual check that
/// suits thin flexible pieces. fem checks the relative residual |f - K u| / |f| <= 1e-6; for a
/// long thin piece (deflections of many thicknesses under small loads, small elements where strips
/// meet) that number cannot be computed below ~ eps |K| |u| / |f|, above 1e-6 with an exact solve.
/// So fem's own check runs at max(opt.residual_tolerance, 1e-2) (a coarse guard; singular systems
/// are caught by its pivot and support checks), and the solution is accepted if the relative
/// residual meets opt.residual_tolerance or the componentwise backward error
/// max_i |f - K u|_i / (|K| |u| + |f|)_i (Oettli-Prager) is <= 1e-10, i.e. u solves a system within
/// 1e-10 relative of the assembled one. Otherwise up to two steps of iterative refinement
/// (u += K^-1 (f - K u) with the same factorization) are tried before solver_error. Reactions
/// K u - f as in fem::static_result.
inline fem::static_result solve_checked(const fem::mesh& m, const fem::load_case& lc, const fem::solve_options& opt) {
    constexpr double backward_tolerance = 1e-10;
    fem::solve_options guard = opt;
    guard.residual_tolerance = std::max(opt.residual_tolerance, 1e-2);
    fem::solve_context ctx(m, lc, guard);
    fem::static_result r = ctx.solve(lc);
    const fem::dof_map& dofs = ctx.dofs();
    const Eigen::SparseMatrix<double> K = fem::assemble_stiffness(m, dofs);
    const Eigen::VectorXd f = fem::assemble_loads(m, dofs, lc);
    std::vector<char> fixed(dofs.total, 0);
    for (const fem::fixed_dof& x : lc.fixed) fixed[dofs.index(x.node, x.dof)] = 1;
    double f_norm = 0.0;
    for (std::size_t g = 0; g < dofs.total; ++g)
        if (!fixed[g]) f_norm += f(static_cast<Eigen::Index>(g)) * f(static_cast<Eigen::Index>(g));
    f_norm = std::sqrt(f_norm);
    Eigen::VectorXd res;
    double backward = 0.0;
    auto measure = [&] {  // residual on the free DOFs and its componentwise backward error
        res = f - K * r.u;
        const Eigen::VectorXd scale = K.cwiseAbs() * r.u.cwiseAbs() + f.cwiseAbs();
        backward = 0.0;
        for (std::size_t g = 0; g < dofs.total; ++g) {
            const auto i = static_cast<Eigen::Index>(g);
            if (fixed[g]) res(i) = 0.0;
            else if (scale(i) > 0.0) backward = std::max(backward, std::abs(res(i)) / scale(i));
        }
        r.relative_residual = f_norm > 0.0 ? res.norm() / f_norm : 0.0;
    };
    auto accepted = [&] { return r.relative_residual <= opt.residual_tolerance || backward <= backward_tolerance; };
    measure();
    for (int step = 0; step < 2 && !accepted(); ++step) {
        fem::load_case correction;  // supports keep their prescribed values (0)
        for (std::uint32_t n = 0; n < m.nodes.size(); ++n)
            for (int k = 0; k < dofs.count[n]; ++k) {
                const double v = res(static_cast<Eigen::Index>(dofs.offset[n] + static_cast<std::size_t>(k)));
                if (v != 0.0) correction.forces.push_back({n, k, v});
            }
        r.u += ctx.solve(correction).u;
        measure();
    }
    if (!accepted())
        throw solver_error("structure: the shell solve left a relative residual of " + std::to_string(r.relative_residual) +
                           " and a backward error of " + std::to_string(backward) + " (limits " + std::to_string(opt.residual_tolerance) +
                           ", 1e-10); the piece is (nearly) a mechanism");
    r.reactions = K * r.u - f;
    return r;
}

/// Node statistics of a solved model (weak nodes, histogram, maxima, reactions).
inline structural_report summarize(std::vector<vec2> positions, const fem::mesh& m, const fem::static_result& r, double thickness,
                                   std::vector<std::uint32_t> supports, const structure_options& opt) {
    structural_report rep;
    rep.thickness = thickness;
    rep.yield = opt.material.yield_mpa;
    rep.solver = r.solver;
    rep.node_positions = std::move(positions);
    rep.node_von_mises = fem::nodal_von_mises(m, r);
    const double bin = opt.histogram_bin_mpa;
    const auto closed_bins = static_cast<std::size_t>(std::ceil(2.0 * rep.yield / bin));
    rep.histogram.assign(closed_bins + 1, 0);
    for (std::uint32_t i = 0; i < rep.node_von_mises.size(); ++i) {
        const double s = rep.node_von_mises[i];
        rep.max_von_mises = std::max(rep.max_von_mises, s);
        if (s > rep.yield) rep.weak_nodes.push_back(i);
        const double k = std::floor(s / bin);
        ++rep.histogram[k >= static_cast<double>(closed_bins) ? closed_bins : static_cast<std::size_t>(std::max(0.0, k))];
    }
    rep.weak_fraction = rep.node_von_mises.empty() ? 0.0 : static_cast<double>(rep.weak_nodes.size()) / static_cast<double>(rep.node_von_mises.size());
    rep.node_deflection.resize(m.nodes.size());
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
        rep.node_deflection[i] = r.displacement(i).z;
        rep.max_deflection = std::max(rep.max_deflection, std::abs(rep.node_deflection[i]));
    }
    for (std::uint32_t n : supports)
        for (int d = 0; d < 3; ++d) rep.support_reaction[d] += r.reactions(static_cast<Eigen::Index>(r.dofs.index(n, d)));
    rep.support_nodes = std::move(supports);
    return rep;
}

}  // namespace detail::structure

/// Shell analysis of the piece at `thickness` [mm] under the load case of `opt` (file comment),
/// solved by fem::solve_context with opt.solver (default: fem's automatic method choice), its
/// accuracy checked by detail::structure::solve_checked.
/// Throws invalid_input for an empty triangulation, a bad thickness or options, no support node;
/// solver_error if a part is not held or the solve fails.
[[nodiscard]] inline structural_report analyse_structure(const fem_triangulation& tri, double thickness, const structure_options& opt = {}) {
    opt.validate();
    const fem::mesh m = shell_model(tri, thickness, opt.material);
    std::vector<std::uint32_t> supports = support_nodes(tri, opt);
    const fem::load_case lc = structural_load_case(m, supports, opt, glm::normalize(opt.gravity_down));
    const fem::static_result r = detail::structure::solve_checked(m, lc, opt.solver);
    return detail::structure::summarize(tri.mesh.vertices, m, r, thickness, std::move(supports), opt);
}

/// The centroids of the groups of points[ids] linked by single linkage at `radius` [mm] (groups in
/// order of their first id; 2D or 3D points). Throws invalid_input unless the radius is finite and > 0.
template <class P>
[[nodiscard]] std::vector<P> cluster_centres(std::span<const P> points, std::span<const std::uint32_t> ids, double radius) {
    require_positive(radius, "weak_region_centres: cluster radius (mm)");
    const std::size_t n = ids.size();
    std::vector<P> p(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = points[ids[i]];
    union_find groups(n);
    std::map<std::array<std::int64_t, 3>, std::vector<std::uint32_t>> cells;
    auto cell_of = [&](const P& q) {
        std::array<std::int64_t, 3> c{0, 0, 0};
        for (int d = 0; d < P::length(); ++d) c[static_cast<std::size_t>(d)] = static_cast<std::int64_t>(std::floor(q[d] / radius));
        return c;
    };
    for (std::uint32_t i = 0; i < n; ++i) {
        const auto c = cell_of(p[i]);
        for (std::int64_t dz = (P::length() == 3 ? -1 : 0); dz <= (P::length() == 3 ? 1 : 0); ++dz)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dx = -1; dx <= 1; ++dx) {
                    const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == cells.end()) continue;
                    for (std::uint32_t j : it->second)
                        if (glm::length(p[i] - p[j]) <= radius) groups.unite(i, j);
                }
        cells[c].push_back(i);
    }
    std::vector<std::uint32_t> slot(n, 0xffffffffu);
    std::vector<P> sum;
    std::vector<double> count;
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t root = groups.find(i);  // the smallest index of its group (union_find.hpp)
        if (slot[root] == 0xffffffffu) slot[root] = static_cast<std::uint32_t>(sum.size()), sum.emplace_back(0.0), count.push_back(0.0);
        sum[slot[root]] += p[i];
        count[slot[root]] += 1.0;
    }
    for (std::size_t g = 0; g < sum.size(); ++g) sum[g] /= count[g];
    return sum;
}

/// Phase 1 of §5: the weak nodes grouped by single linkage (two weak nodes within cluster_radius
/// [mm] are in one group), and each group's centroid [mm], where the caller inserts new pattern
/// elements. Groups are ordered by their smallest node index. Throws invalid_input unless the
/// radius is finite and > 0. O(W) expected for W weak nodes (uniform grid of cell cluster_radius).
[[nodiscard]] inline std::vector<vec2> weak_region_centres(const structural_report& rep, double cluster_radius) {
    for (const std::uint32_t w : rep.weak_nodes)
        if (w >= rep.node_positions.size()) throw invalid_input("weak_region_centres: a weak node has no position");
    return cluster_centres<vec2>(rep.node_positions, rep.weak_nodes, cluster_radius);
}

/// Parameters of phase 2.
struct thickening_options {
    double growth = 1.1;      ///< thickness factor per iteration (the paper's 10%), > 1
    int max_iterations = 30;  ///< bound on the number of increases, >= 0
    /// Largest thickness analysed [mm]; 0: no bound but max_iterations. Phase 2 stops at the last
    /// t0 * growth^k <= max_thickness (t0 itself must not exceed it).
    double max_thickness = 0;
};

/// Outcome of phase 2. history[k] is the analysis at thickness t0 * growth^k.
struct thickening_result {
    double thickness = 0;     ///< final thickness [mm] = t0 * growth^iterations
    int iterations = 0;       ///< increases applied (k)
    bool converged = false;   ///< weak_fraction reached 0 within max_iterations
    std::vector<double> thickness_history;      ///< [mm], iterations + 1 entries
    std::vector<double> weak_fraction_history;  ///< per analysis
    std::vector<double> max_von_mises_history;  ///< [MPa] per analysis
    structural_report report;                   ///< the last analysis
};

/// Phase 2 with any analysis: analyse(t) -> structural_report at thickness t [mm].
template <class Analyse>
[[nodiscard]] thickening_result thicken_with(Analyse&& analyse, double thickness, const thickening_options& topt, const progress_span& progress = {}) {
    require_positive(thickness, "thicken_until_strong: thickness (mm)");
    if (!(std::isfinite(topt.growth) && topt.growth > 1.0)) throw invalid_input("thicken_until_strong: growth must be finite and > 1");
    if (topt.max_iterations < 0) throw invalid_input("thicken_until_strong: max_iterations must be >= 0");
    if (!(std::isfinite(topt.max_thickness) && topt.max_thickness >= 0))
        throw invalid_input("thicken_until_strong: max_thickness must be finite and >= 0 mm (0: none)");
    if (topt.max_thickness > 0 && thickness > topt.max_thickness)
        throw invalid_input("thicken_until_strong: the thickness " + std::to_string(thickness) + " mm exceeds the maximum thickness " +
                            std::to_string(topt.max_thickness) + " mm");
    thickening_result out;
    for (int k = 0;; ++k) {
        const double t = thickness * std::pow(topt.growth, k);
        if (k > 0 && topt.max_thickness > 0 && t > topt.max_thickness * (1 + 1e-12)) return out;  // the bound: stop, weak nodes remain
        progress(static_cast<double>(k) / (topt.max_iterations + 1), "thickening");
        out.report = analyse(t);
        out.thickness = t;
        out.iterations = k;
        out.thickness_history.push_back(t);
        out.weak_fraction_history.push_back(out.report.weak_fraction);
        out.max_von_mises_history.push_back(out.report.max_von_mises);
        if (out.report.weak_fraction == 0.0) {
            out.converged = true;
            return out;
        }
        if (k == topt.max_iterations) return out;
    }
}

/// Phase 2 of §5: analyses at t0, and while weak nodes remain multiplies the thickness by
/// opt.growth (t_k = t0 * growth^k, computed by a power, so no drift) and analyses again, at most
/// opt.max_iterations times and never above topt.max_thickness (when set). Throws what
/// analyse_structure throws, and invalid_input for bad options.
[[nodiscard]] inline thickening_result thicken_until_strong(const fem_triangulation& tri, double thickness, const structure_options& opt = {},
                                                            const thickening_options& topt = {}, const progress_span& progress = {}) {
    return thicken_with([&](double t) { return analyse_structure(tri, t, opt); }, thickness, topt, progress);
}

}  // namespace fabsynth::filigree
