// SPDX-License-Identifier: MIT
#pragma once
/// @file structure.hpp  Structural optimization of a filigree on a base surface
/// (filigree-synthesis.md §5 on the baked mesh M_b, §6.1: M_b "serves as both the input of stress
/// analysis and the base mesh for generating a printable mesh").
///
/// Model: M_b's triangles become S3 shells (fem/shell3.hpp, CST membrane + DKT bending) of the
/// current thickness, normals those of the base faces. Load case (§5: gravity and "pressure forces
/// from the outside, applied on all shell elements"): self weight along -up (density x 9.81 m/s^2),
/// a uniform pressure on every element (default 1 kPa, pushing against the element normal, i.e.
/// from outside on a closed base). Supports: every node within support_fraction (5%) of the
/// extent of M_b along `up` above its lowest point, all six DOFs clamped: the piece stands on its
/// lowest 5%. Nodal von Mises, weak nodes, histogram: as structure.hpp. The analysis mesh is M_b
/// cleaned by fem_mesh_of (vertices within a tenth of the narrowest strip width merged).
///
/// Reinforcement (§5): phase 1 inserts an element (the class of largest weight) at the surface
/// point nearest each weak region's centre and re-synthesizes (a few rounds of placement and
/// boosting through surface_space) while more than 0.5% of the nodes are weak (at most 3 rounds,
/// a round that does not lower the weak fraction is undone); phase 2 raises the thickness by 10%
/// per analysis until no node is weak. Before every analysis M_b is reduced to its largest
/// connected piece (as the 2D path keeps its largest piece): a piece that touches no other cannot
/// be held by the supports.
///
/// Usage:
///   auto rep = fabsynth::filigree::analyse_surface_structure(mb, 1.0, {0, 0, 1}, opt);
///   auto rr  = fabsynth::filigree::reinforce_on_surface(classes, weights, region, field, so, syn, ropt);
///
/// Errors: as structure.hpp's analyse_structure (invalid_input for an empty mesh or bad options,
/// solver_error when the solve fails), invalid_input for an up vector that is not finite and non-zero.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/fem/mesh.hpp"
#include "fabsynth/filigree/reinforcement.hpp"
#include "fabsynth/filigree/structure.hpp"
#include "fabsynth/filigree/surface/reconstruct.hpp"
#include "fabsynth/filigree/surface/synthesis.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"

namespace fabsynth::filigree {

/// The piece of m with the most faces, vertices compacted: faces joined across shared edges (two
/// parts that meet only at a vertex would hinge there, a mechanism for the shell analysis). Ties:
/// the piece of the lowest face. `dropped`: the number of other pieces.
[[nodiscard]] inline triangle_mesh largest_piece(const triangle_mesh& m, std::size_t* dropped = nullptr) {
    if (m.faces.empty()) return {};
    union_find pieces(m.faces.size());
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> first_face;  // undirected edge -> a face using it
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const auto e = std::minmax(m.faces[f][static_cast<std::size_t>(k)], m.faces[f][static_cast<std::size_t>((k + 1) % 3)]);
            const auto [it, fresh] = first_face.try_emplace({e.first, e.second}, f);
            if (!fresh) pieces.unite(f, it->second);
        }
    std::vector<std::uint32_t> comp(m.faces.size());
    std::vector<std::size_t> size(m.faces.size(), 0);
    std::size_t count = 0;
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
        comp[f] = pieces.find(f);
        count += size[comp[f]]++ == 0;
    }
    const auto keep = static_cast<std::uint32_t>(std::max_element(size.begin(), size.end()) - size.begin());
    if (dropped) *dropped = count - 1;
    std::vector<std::uint8_t> in_piece(m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) in_piece[f] = comp[f] == keep;
    return faces_subset(m, in_piece);
}

/// The shell analysis mesh of a baked pattern: vertices closer than `merge` [mm] clustered
/// (geometry/mesh.hpp; the per-face booleans leave edges down to the weld tolerance, whose
/// elements make the stiffness singular in practice), triangles with a height below 1e-3 of their
/// longest edge dropped (no stiffness worth a pivot), then the largest edge-connected piece.
[[nodiscard]] inline triangle_mesh fem_mesh_of(const triangle_mesh& mb, double merge) {
    triangle_mesh m = cluster_vertices(mb, merge);
    std::vector<std::array<std::uint32_t, 3>> kept;
    for (const auto& f : m.faces) {
        const vec3 a = m.vertices[f[0]], b = m.vertices[f[1]], c = m.vertices[f[2]];
        const double l2 = std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a), glm::dot(c - b, c - b)});
        if (glm::length(glm::cross(b - a, c - a)) > 1e-3 * l2) kept.push_back(f);
    }
    m.faces = std::move(kept);
    return largest_piece(m);
}

/// S3 shells of `thickness` [mm] over the triangles of mb, one section of `material`.
[[nodiscard]] inline fem::mesh shell_model(const triangle_mesh& mb, double thickness, const structure_material& material) {
    if (mb.faces.empty()) throw invalid_input("structure: the baked mesh is empty (no triangles)");
    require_positive(thickness, "structure: thickness (mm)");
    fem::mesh m;
    m.nodes = mb.vertices;
    m.sections.push_back({material.elastic, thickness});
    m.elements.reserve(mb.faces.size());
    for (const auto& t : mb.faces) m.elements.push_back(fem::make_element<fem::shell3>(t));
    return m;
}

/// Nodes of mb's triangles within `fraction` of the extent along `up` above the lowest (ascending).
[[nodiscard]] inline std::vector<std::uint32_t> support_nodes_along(const triangle_mesh& mb, vec3 up, double fraction) {
    std::vector<char> used(mb.vertices.size(), 0);
    for (const auto& t : mb.faces)
        for (const std::uint32_t v : t) used[v] = 1;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < used.size(); ++i)
        if (used[i]) lo = std::min(lo, glm::dot(mb.vertices[i], up)), hi = std::max(hi, glm::dot(mb.vertices[i], up));
    const double limit = lo + fraction * (hi - lo) + 1e-9 * (hi - lo);
    std::vector<std::uint32_t> out;
    for (std::uint32_t i = 0; i < used.size(); ++i)
        if (used[i] && glm::dot(mb.vertices[i], up) <= limit) out.push_back(i);
    if (out.empty()) throw invalid_input("structure: no node lies in the support region (nothing holds the piece)");
    return out;
}

/// Shell analysis of mb at `thickness` [mm] under the load case of the file comment.
/// report.node_positions stays empty; report.node_deflection is the displacement along up [mm].
[[nodiscard]] inline structural_report analyse_surface_structure(const triangle_mesh& mb, double thickness, vec3 up, const structure_options& opt = {}) {
    opt.validate();
    if (!all_finite(up) || !(glm::length(up) > 0)) throw invalid_input("structure: the up vector must be finite and non-zero");
    up = glm::normalize(up);
    const fem::mesh m = shell_model(mb, thickness, opt.material);
    std::vector<std::uint32_t> supports = support_nodes_along(mb, up, opt.support_fraction);
    const fem::load_case lc = structural_load_case(m, supports, opt, -up);
    const fem::static_result r = detail::structure::solve_checked(m, lc, opt.solver);
    structural_report rep = detail::structure::summarize({}, m, r, thickness, std::move(supports), opt);
    rep.max_deflection = 0;
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
        rep.node_deflection[i] = glm::dot(r.displacement(i), up);
        rep.max_deflection = std::max(rep.max_deflection, std::abs(rep.node_deflection[i]));
    }
    return rep;
}

/// Options of reinforce_on_surface (as reinforcement_options, plus the up vector).
struct surface_reinforcement_options {
    reinforcement_options base;  ///< enabled, material, thickness, pressure, weak_limit, rounds
    vec3 up{0, 0, 1};
};

/// What reinforce_on_surface produced: the final layout, M_b (its largest piece) and the §5 record
/// (structural_record, shared with the planar form).
struct surface_reinforcement_result : structural_record {
    std::vector<surface_instance> instances;
    std::vector<surface_skeleton> skeletons;
    triangle_mesh baked;                   ///< M_b, largest piece
    triangle_mesh fem;                     ///< the analysed mesh (M_b, close vertices merged; empty without analysis)
    structural_report final_report;        ///< the last analysis (stresses per fem vertex; empty without analysis)
};

namespace detail::surface {

// M_b of a layout, reduced to its largest piece.
[[nodiscard]] inline triangle_mesh baked_piece(std::span<const element> classes, std::span<const surface_instance> instances,
                                               std::span<const surface_skeleton> skeletons, const surface_control& field, const surface_region& region,
                                               std::size_t& dropped, double& dropped_fraction) {
    const surface_space s(classes, {instances.begin(), instances.end()}, field, region);
    const triangle_mesh all = bake_pattern(s, skeletons);
    if (all.faces.empty()) throw solver_error("filigree: the synthesized pattern is empty");
    triangle_mesh piece = largest_piece(all, &dropped);
    const double total = surface_area(all);
    dropped_fraction = total > 0 ? 1.0 - surface_area(piece) / total : 0.0;
    return piece;
}

}  // namespace detail::surface

/// The two phases of §5 on the pattern `syn` (from synthesize_on_surface with the same classes,
/// region, field and options); see the file comment. With opt.base.enabled false: M_b only.
[[nodiscard]] inline surface_reinforcement_result reinforce_on_surface(std::span<const element> classes, std::span<const double> weights,
                                                                       const surface_region& region, const surface_control& field,
                                                                       const synthesis_options& so, const surface_synthesis_result& syn,
                                                                       const surface_reinforcement_options& opt = {}, const progress_span& progress = {}) {
    namespace ds = detail::surface;
    detail::reinforce::check_thickness(opt.base);
    if (!detail::reinforce::default_support(opt.base.support))
        throw invalid_input("reinforce_on_surface: `support` is the planar form's; on a base surface the supports are the lowest 5% along `up`");
    const auto t0 = std::chrono::steady_clock::now();
    surface_reinforcement_result r;
    r.instances = syn.instances, r.skeletons = syn.skeletons, r.thickness = opt.base.thickness;
    r.baked = ds::baked_piece(classes, r.instances, r.skeletons, field, region, r.pieces_dropped, r.dropped_area_fraction);
    if (opt.base.enabled) {
        structure_options sopt;
        sopt.material = preset_material(opt.base.material);
        sopt.pressure_pa = opt.base.pressure_pa;
        r.yield_mpa = sopt.material.yield_mpa, r.histogram_bin_mpa = sopt.histogram_bin_mpa;
        double narrowest = std::numeric_limits<double>::infinity();
        for (const element& e : classes)
            for (const double w : e.widths) narrowest = std::min(narrowest, w);
        const double merge = 0.1 * narrowest;
        struct layout {
            std::vector<surface_instance> instances;
            std::vector<surface_skeleton> skeletons;
            triangle_mesh baked;
            std::size_t dropped = 0;
            double dropped_fraction = 0;
            triangle_mesh fem;
        };
        layout best{r.instances, r.skeletons, r.baked, r.pieces_dropped, r.dropped_area_fraction, fem_mesh_of(r.baked, merge)};
        const std::uint32_t cls = reinforcement_class(weights);
        reinforcement_loop(
            best, r, opt.base, [&](const layout& l, double t) { return analyse_surface_structure(l.fem, t, opt.up, sopt); },
            [&](const layout& l, const structural_report& rep, int round, std::size_t& added, const progress_span& grow_progress) -> std::optional<layout> {
                std::vector<surface_instance> in = l.instances;
                for (const vec3& c : cluster_centres<vec3>(l.fem.vertices, rep.weak_nodes, 0.5 * classes[cls].size)) {
                    const surface_point at = ds::nearest_region_point(region, c);
                    const std::uint32_t here = region.class_allowed ? reinforcement_class(weights, [&](std::uint32_t k) { return region.class_allowed(k, at.face); }) : cls;
                    if (here != UINT32_MAX) in.push_back({instance{here, {0, 0}, 0, field(at).scale, classes[here].vertices}, at}), ++added;
                }
                if (added == 0) return std::nullopt;
                surface_space s(classes, std::move(in), field, region, so.gamma_boundary);
                synthesis_options again = so;
                again.max_rounds = opt.base.resynthesis_rounds;
                again.seed = so.seed + 1000 * static_cast<std::uint64_t>(round + 1);
                surface_synthesis_result res;
                optimize_layout(s, again, res, grow_progress);
                surface_cut_report cut;
                layout next;
                next.skeletons = surface_skeletons(s, so.topology_cut ? &cut : nullptr);
                next.baked = ds::baked_piece(classes, s.instances(), next.skeletons, field, region, next.dropped, next.dropped_fraction);
                next.fem = fem_mesh_of(next.baked, merge);
                next.instances = s.instances();
                return next;
            },
            [&](const layout& l, double t, const progress_span& thicken_progress) {
                thickening_result th = thicken_with([&](double tt) { return analyse_surface_structure(l.fem, tt, opt.up, sopt); }, t,
                                                    thickening_options{.max_thickness = opt.base.max_thickness}, thicken_progress);
                r.fem = l.fem;
                r.final_report = th.report;
                return th;
            },
            progress);
        r.instances = std::move(best.instances), r.skeletons = std::move(best.skeletons), r.baked = std::move(best.baked);
        r.pieces_dropped = best.dropped, r.dropped_area_fraction = best.dropped_fraction;
        r.fem_nodes = best.fem.vertices.size();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace fabsynth::filigree
