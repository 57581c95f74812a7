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
/// per analysis until no node is weak. Before every analysis M_b is made one piece as the 2D path
/// does (a piece that touches no other cannot be held by the supports): every other piece is joined
/// to the largest by a bridge strip along the surface when one of at most max_bridge_mm reaches it
/// (default surface_bridge_widths x the narrowest strip width), else trimmed or dropped, counted.
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
#include <unordered_map>
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

/// Default longest bridge on a surface, in narrowest strip widths (surface_reinforcement_options'
/// base.max_bridge_mm = 0). The planar path bridges pieces the domain's clipping cuts off, a few
/// widths away (4 widths there). On a surface the pieces come from where the local
/// parameterizations stop (a thin ear, a neck: the map folds before it reaches the other side), so
/// the instances on either side never become neighbours and their strips end further apart:
/// measured on the main job's bunny (C-scrolls at 16 mm, 0.8 mm strips), the pattern on one ear,
/// 5.2% of the area, ended 5.4 mm (6.7 widths) from the rest, so the default is 8 widths.
inline constexpr double surface_bridge_widths = 8.0;

namespace detail::surface {

// Per face of m its piece (faces joined across shared edges; numbered from 0 in order of each
// piece's first face) and, in `faces`, the face count of each piece.
[[nodiscard]] inline std::vector<std::uint32_t> edge_pieces(const triangle_mesh& m, std::vector<std::size_t>& faces) {
    union_find pieces(m.faces.size());
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> first_face;  // undirected edge -> a face using it
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const auto e = std::minmax(m.faces[f][static_cast<std::size_t>(k)], m.faces[f][static_cast<std::size_t>((k + 1) % 3)]);
            const auto [it, fresh] = first_face.try_emplace({e.first, e.second}, f);
            if (!fresh) pieces.unite(f, it->second);
        }
    std::vector<std::uint32_t> label(m.faces.size(), UINT32_MAX), out(m.faces.size());
    faces.clear();
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
        const std::uint32_t r = pieces.find(f);
        if (label[r] == UINT32_MAX) label[r] = static_cast<std::uint32_t>(faces.size()), faces.push_back(0);
        out[f] = label[r];
        ++faces[out[f]];
    }
    return out;
}

}  // namespace detail::surface

/// The piece of m with the most faces, vertices compacted: faces joined across shared edges (two
/// parts that meet only at a vertex would hinge there, a mechanism for the shell analysis). Ties:
/// the piece of the lowest face. `dropped`: the number of other pieces.
[[nodiscard]] inline triangle_mesh largest_piece(const triangle_mesh& m, std::size_t* dropped = nullptr) {
    if (m.faces.empty()) return {};
    std::vector<std::size_t> size;
    const std::vector<std::uint32_t> piece = detail::surface::edge_pieces(m, size);
    const auto keep = static_cast<std::uint32_t>(std::max_element(size.begin(), size.end()) - size.begin());
    if (dropped) *dropped = size.size() - 1;
    std::vector<std::uint8_t> in_piece(m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) in_piece[f] = piece[f] == keep;
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

// Key of the grid cell of side `cell` (mm) holding p, shifted by (dx, dy, dz) cells.
[[nodiscard]] inline std::uint64_t cell_key(vec3 p, double cell, std::int64_t dx = 0, std::int64_t dy = 0, std::int64_t dz = 0) {
    auto k = [&](double x, std::int64_t d) { return static_cast<std::uint64_t>((static_cast<std::int64_t>(std::floor(x / cell)) + d) & 0x1fffff); };
    return (k(p.x, dx) << 42) | (k(p.y, dy) << 21) | k(p.z, dz);
}

// Per piece of m (`piece` per face, `count` pieces) other than `main`: its vertex nearest a vertex
// of `main` (3D) and that vertex, when they are at most `reach` mm apart (else UINT32_MAX).
[[nodiscard]] inline std::vector<std::pair<std::uint32_t, std::uint32_t>> nearest_to_main(const triangle_mesh& m, const std::vector<std::uint32_t>& piece,
                                                                                       std::size_t count, std::uint32_t main, double reach) {
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;  // cells of side reach: a pair within reach is in neighbouring cells
    std::vector<std::uint8_t> seen(m.vertices.size(), 0);
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        if (piece[f] == main)
            for (const std::uint32_t v : m.faces[f])
                if (!seen[v]) seen[v] = 1, grid[cell_key(m.vertices[v], reach)].push_back(v);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> best(count, {UINT32_MAX, UINT32_MAX});
    std::vector<double> best_d(count, reach);
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
        const std::uint32_t q = piece[f];
        if (q == main) continue;
        for (const std::uint32_t v : m.faces[f])
            for (std::int64_t dx = -1; dx <= 1; ++dx)
                for (std::int64_t dy = -1; dy <= 1; ++dy)
                    for (std::int64_t dz = -1; dz <= 1; ++dz) {
                        const auto it = grid.find(cell_key(m.vertices[v], reach, dx, dy, dz));
                        if (it == grid.end()) continue;
                        for (const std::uint32_t u : it->second) {
                            const double d = glm::distance(m.vertices[v], m.vertices[u]);
                            if (d < best_d[q] || (d == best_d[q] && best[q].first == UINT32_MAX)) best_d[q] = d, best[q] = {v, u};
                        }
                    }
    }
    return best;
}

// M_b of a layout reduced to one piece, as the planar path's one_piece: every piece other than the
// largest (by faces) is joined to it by a bridge strip of the narrowest width along the surface
// from its vertex nearest the largest piece, when that geodesic is at most `max_bridge` mm long and
// the map reaches it (up to 4 passes, so a piece may join through another); what is left is
// trimmed (less area than a square of twice the width) or dropped, and counted in `book`.
[[nodiscard]] inline triangle_mesh baked_piece(std::span<const element> classes, std::span<const surface_instance> instances,
                                               std::span<const surface_skeleton> skeletons, const surface_control& field, const surface_region& region,
                                               double max_bridge, detail::reinforce::piece_bookkeeping& book) {
    const surface_space s(classes, {instances.begin(), instances.end()}, field, region);
    std::vector<std::vector<face_contours>> parts(s.size());
    parallel_for(0, s.size(), [&](std::size_t i) { parts[i] = instance_contours(s, i, skeletons[i]); });
    std::vector<face_contours> contours;
    for (auto& p : parts) contours.insert(contours.end(), std::make_move_iterator(p.begin()), std::make_move_iterator(p.end()));
    const triangle_mesh& base = s.patcher().mesh();
    triangle_mesh all = bake_per_face(base, contours);
    if (all.faces.empty()) throw solver_error("filigree: the synthesized pattern is empty");
    const double w = detail::reinforce::narrowest_width(classes);
    std::vector<std::size_t> size;
    std::vector<std::uint32_t> piece = edge_pieces(all, size);
    const std::size_t pieces_before = size.size();
    for (int pass = 0; pass < 4 && size.size() > 1 && max_bridge > 0 && w > 0; ++pass) {
        const auto main = static_cast<std::uint32_t>(std::max_element(size.begin(), size.end()) - size.begin());
        std::vector<std::pair<vec3, vec3>> pairs;  // a piece's nearest vertex to the largest one, and that one's
        for (const auto& [a, b] : nearest_to_main(all, piece, size.size(), main, max_bridge))
            if (a != UINT32_MAX) pairs.emplace_back(all.vertices[a], all.vertices[b]);
        std::vector<std::vector<face_contours>> bridges(pairs.size());
        parallel_for(0, pairs.size(), [&](std::size_t k) {
            bridges[k] = bridge_contours(s.patcher(), region, nearest_region_point(region, pairs[k].first), nearest_region_point(region, pairs[k].second),
                                         w, max_bridge);
        });
        bool any = false;
        for (auto& b : bridges) any = any || !b.empty(), contours.insert(contours.end(), std::make_move_iterator(b.begin()), std::make_move_iterator(b.end()));
        if (!any) break;
        triangle_mesh joined = bake_per_face(base, contours);
        std::vector<std::size_t> joined_size;
        std::vector<std::uint32_t> joined_piece = edge_pieces(joined, joined_size);
        const bool progress = joined_size.size() < size.size();
        all = std::move(joined), piece = std::move(joined_piece), size = std::move(joined_size);
        if (!progress) break;
    }
    const auto main = static_cast<std::uint32_t>(std::max_element(size.begin(), size.end()) - size.begin());
    std::vector<double> piece_area(size.size(), 0.0);
    for (std::uint32_t f = 0; f < all.faces.size(); ++f) {
        const auto& t = all.faces[f];
        piece_area[piece[f]] += 0.5 * glm::length(glm::cross(all.vertices[t[1]] - all.vertices[t[0]], all.vertices[t[2]] - all.vertices[t[0]]));
    }
    double total = 0, removed = 0;
    book = {};
    for (std::uint32_t q = 0; q < size.size(); ++q) {
        total += piece_area[q];
        if (q == main) continue;
        removed += piece_area[q];
        (piece_area[q] < 4 * w * w ? book.trimmed : book.dropped) += 1;
    }
    book.bridged = pieces_before > size.size() ? pieces_before - size.size() : 0;
    book.dropped_fraction = total > 0 ? removed / total : 0.0;
    std::vector<std::uint8_t> keep(all.faces.size());
    for (std::size_t f = 0; f < all.faces.size(); ++f) keep[f] = piece[f] == main;
    return faces_subset(all, keep);
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
    const double max_bridge = opt.base.max_bridge_mm < 0 ? 0.0
                              : opt.base.max_bridge_mm > 0 ? opt.base.max_bridge_mm
                                                           : surface_bridge_widths * detail::reinforce::narrowest_width(classes);
    detail::reinforce::piece_bookkeeping book;
    r.baked = ds::baked_piece(classes, r.instances, r.skeletons, field, region, max_bridge, book);
    auto keep_book = [&](const detail::reinforce::piece_bookkeeping& b) {
        r.pieces_dropped = b.dropped, r.pieces_bridged = b.bridged, r.pieces_trimmed = b.trimmed, r.dropped_area_fraction = b.dropped_fraction;
    };
    keep_book(book);
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
            detail::reinforce::piece_bookkeeping book;
            triangle_mesh fem;
        };
        layout best{r.instances, r.skeletons, r.baked, book, fem_mesh_of(r.baked, merge)};
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
                next.baked = ds::baked_piece(classes, s.instances(), next.skeletons, field, region, max_bridge, next.book);
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
        keep_book(best.book);
        r.fem_nodes = best.fem.vertices.size();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace fabsynth::filigree
