// SPDX-License-Identifier: MIT
#pragma once
/// @file reinforcement.hpp  From synthesized skeletons to one strong printable piece
/// (filigree-synthesis.md §5, §6): strips (reconstruct.hpp) clipped to the domain, the connected
/// piece kept, then the structural optimization of §5 by shell FEM (structure.hpp):
///   phase 1: while more than `weak_limit` (the paper's 0.5%) of the nodes are weak, new elements
///            are inserted at the centres of the weak regions and the pattern is re-synthesized
///            (placement, boosting, topology cut), at most `max_insertion_rounds` times;
///   phase 2: the thickness grows by 10% per iteration until no node is weak.
///
/// Usage:
///   auto syn = fabsynth::filigree::synthesize_pattern(classes, weights, domain, field, so);
///   auto r = fabsynth::filigree::reinforce(classes, weights, domain, field, so, syn, {.thickness = 1.0});
///   r.outline;  r.thickness;  r.histogram_before;  r.histogram_after;   // Fig. 21
///
/// One piece: the strips are united and opened (shrunk, then grown, by a tenth of the narrowest
/// strip width), so that parts touching at a single point, which would print as a hinge, count as
/// separate; when clipping to the domain leaves more than one connected piece (element ends cut off
/// by the boundary; the topology cut never disconnects), each other piece within `max_bridge_mm`
/// of the largest is joined to it by a straight strip of the narrowest width along their nearest
/// contact (`pieces_bridged`); the rest are removed, as `pieces_trimmed` when smaller than a square
/// of twice the strip width (no printable strip) and `pieces_dropped` otherwise, their share of
/// the strip area in `dropped_area_fraction`.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/filigree/matching.hpp"
#include "fabsynth/filigree/reconstruct.hpp"
#include "fabsynth/filigree/structure.hpp"
#include "fabsynth/filigree/synthesis.hpp"

namespace fabsynth::filigree {

/// How a flat piece is held and which way its weight pulls (planar form; on a base surface the
/// supports are the lowest 5% along `up` and these must stay at their defaults). Positions in mm, in
/// the domain's frame (y down, as drawn). At most one of box and hang.
struct planar_support {
    support_side side = support_side::top;  ///< clamp the band of `fraction` of the piece's bounding box on this side
    double fraction = 0.05;                 ///< in [0, 1]
    std::optional<box2> box;                ///< instead: clamp the nodes inside this box
    std::optional<vec2> hang;               ///< instead: clamp the nodes within hang_radius of this point (an eyelet)
    double hang_radius = 0;                 ///< mm; 0: the median strip width
    bool upright = false;                   ///< gravity in the plane toward the drawing's bottom (+y) instead of out of it (-z)
};

struct reinforcement_options {
    bool enabled = true;                 ///< false: strips only, no FEM
    material_preset material = material_preset::abs;
    double thickness = 1.0;              ///< initial shell / extrusion thickness, mm
    /// Thickest the piece may get, mm; 0: no bound (phase 2 thickens, at most 30 x 10%, until no node
    /// is weak, else solver_error). With a bound, phase 2 stops at the last step <= it and the record
    /// says whether weak nodes remain (structural_record::strong, weak_nodes_final) instead of failing.
    double max_thickness = 0;
    planar_support support;              ///< where the flat piece is held (planar form only)
    double pressure_pa = 1000.0;         ///< external pressure, Pa (§5)
    double weak_limit = 0.005;           ///< phase 1 target: weak nodes / nodes (§5: 0.5%)
    int max_insertion_rounds = 3;
    int resynthesis_rounds = 2;          ///< rounds of placement + boosting after an insertion
    double mesh_edge = 0.0;              ///< FEM mesh edge length, mm; 0 = 0.6 x the median strip width
    /// Longest bridge strip joining a cut-off piece to the rest (mm); 0 = 4 x the narrowest strip
    /// width in the plane, surface_bridge_widths (8) x on a surface (surface/structure.hpp);
    /// < 0: no bridges (pieces are dropped or trimmed).
    double max_bridge_mm = 0.0;
    // The re-syntheses of phase 1 take their seeds from the synthesis options' (seed + 1000 x round).
};

/// The record of §5 that both forms (planar: reinforce; on a surface: reinforce_on_surface) keep:
/// the piece's bookkeeping, the analyses before and after, and what each phase did.
struct structural_record {
    std::size_t pieces_dropped = 0;           ///< pieces removed because they were not attached to the largest
    std::size_t pieces_bridged = 0;           ///< pieces joined to it by a bridge strip
    std::size_t pieces_trimmed = 0;           ///< pieces removed as shorter than a printable strip
    double dropped_area_fraction = 0;         ///< area removed (dropped and trimmed) / the area of all pieces
    double thickness = 0;                     ///< final, mm
    bool analysed = false;
    std::vector<std::size_t> histogram_before, histogram_after;  ///< node counts per 5 MPa bin (Fig. 21)
    double histogram_bin_mpa = 5.0;
    double yield_mpa = 0;
    std::vector<double> weak_fraction_phase1;    ///< per analysis of phase 1 (first = before)
    std::vector<std::size_t> inserted_per_round; ///< elements added per phase-1 round
    std::vector<double> thickness_phase2, weak_fraction_phase2;
    bool strong = true;                       ///< no node is weak at the final thickness (false only under max_thickness)
    std::size_t weak_nodes_final = 0;         ///< nodes above the yield stress at the final thickness
    double max_von_mises_before = 0, max_von_mises_after = 0;  ///< MPa
    std::size_t fem_nodes = 0;
    std::string solver;
    double seconds = 0;
};

/// What reinforce produced in a planar domain.
struct reinforcement_result : structural_record {
    std::vector<instance> instances;
    std::vector<graph::skeleton_graph<vec2>> skeletons;  ///< of the final layout after its topology cut (world mm)
    std::vector<polygon_with_holes> outline;  ///< the printable piece (mm), one polygon with holes
    std::size_t components = 0;               ///< connected pieces of the final outline (1)
    fem_triangulation fem;                    ///< the FEM triangulation of the final outline (empty without analysis)
    structural_report final_report;           ///< the last analysis (stresses per fem vertex; empty without analysis)
    std::vector<vec2> weak_points;            ///< positions of the nodes still weak at the final thickness (mm)
};

/// The two phases of §5, once for both forms (see the file comment). `layout` is the form's
/// current candidate (its instances, its printable piece and the FEM model of that piece); the
/// callables know what it holds:
///   analyse(layout, thickness mm)            -> structural_report of the piece at that thickness;
///   grow(layout, report, round, added&, span) -> the re-synthesized layout with `added` elements
///                                               inserted at the weak regions (nullopt when none was);
///   thicken(layout, thickness mm, span)       -> phase 2's thickening_result.
/// `progress` receives the analyses (phase 1 in its first 60%, phase 2 after); grow and thicken
/// report their own loops through the span they are given.
/// Phase 1 keeps a round only if it lowers the weak fraction (else the previous layout stays and
/// the phase ends). Fills r's analyses and phases (not fem_nodes, which each form counts);
/// throws solver_error when weak nodes remain after thickening, unless opt.max_thickness bounds it
/// (then r.strong is false and r.weak_nodes_final counts them).
template <class Layout, class Analyse, class Grow, class Thicken>
void reinforcement_loop(Layout& layout, structural_record& r, const reinforcement_options& opt, Analyse&& analyse, Grow&& grow,
                        Thicken&& thicken, const progress_span& progress = {}) {
    const double per_round = 0.6 / (opt.max_insertion_rounds + 1);
    progress(0.0, "structural analysis");
    structural_report rep = analyse(layout, r.thickness);
    r.analysed = true;
    r.histogram_before = rep.histogram;
    r.max_von_mises_before = rep.max_von_mises;
    r.weak_fraction_phase1.push_back(rep.weak_fraction);
    // Phase 1: new elements where the piece is weak, then re-synthesis.
    for (int round = 0; round < opt.max_insertion_rounds && rep.weak_fraction > opt.weak_limit; ++round) {
        std::size_t added = 0;
        const double at = per_round * (round + 1);
        std::optional<Layout> next = grow(std::as_const(layout), std::as_const(rep), round, added, progress.part(at, at + 0.8 * per_round));
        r.inserted_per_round.push_back(added);
        if (!next) break;
        progress(at + 0.8 * per_round, "structural analysis");
        structural_report rep2 = analyse(*next, r.thickness);
        r.weak_fraction_phase1.push_back(rep2.weak_fraction);
        if (rep2.weak_fraction >= rep.weak_fraction) break;  // no better: keep the previous layout
        layout = std::move(*next);
        rep = std::move(rep2);
    }
    // Phase 2: +10% thickness per iteration until no node is weak.
    const thickening_result th = thicken(std::as_const(layout), r.thickness, progress.part(0.6, 1.0));
    if (!th.converged && !(opt.max_thickness > 0))
        throw solver_error("filigree: weak nodes remain after thickening to " + std::to_string(th.thickness) + " mm");
    r.strong = th.converged;
    r.weak_nodes_final = th.report.weak_nodes.size();
    r.thickness = th.thickness;
    r.thickness_phase2 = th.thickness_history;
    r.weak_fraction_phase2 = th.weak_fraction_history;
    r.histogram_after = th.report.histogram;
    r.max_von_mises_after = th.report.max_von_mises;
    r.solver = th.report.solver;
}

/// The class inserted by phase 1: the one of largest weight (the first on ties).
[[nodiscard]] inline std::uint32_t reinforcement_class(std::span<const double> weights) {
    std::uint32_t cls = 0;
    for (std::uint32_t c = 1; c < weights.size(); ++c)
        if (weights[c] > weights[cls]) cls = c;
    return cls;
}

/// The same among the classes `allowed` accepts (element sets per region); UINT32_MAX when none
/// with a weight > 0 is.
template <class Allowed>
[[nodiscard]] std::uint32_t reinforcement_class(std::span<const double> weights, Allowed&& allowed) {
    std::uint32_t cls = UINT32_MAX;
    for (std::uint32_t c = 0; c < weights.size(); ++c)
        if (weights[c] > 0 && allowed(c) && (cls == UINT32_MAX || weights[c] > weights[cls])) cls = c;
    return cls;
}

namespace detail::reinforce {

// What one_piece did with the pieces that are not the largest.
struct piece_bookkeeping {
    std::size_t dropped = 0, bridged = 0, trimmed = 0;
    double dropped_fraction = 0;  // area removed (dropped and trimmed) / area of all pieces
};

// The nearest pair of boundary vertices (piece vertex, main vertex) of `piece` to the polygons
// whose vertices are in `tree` (over `cloud`); returns the distance.
inline double nearest_contact(const polygon_with_holes& piece, const detail::matching::kd_tree& tree, std::span<const vec2> cloud, vec2& from,
                              vec2& to) {
    double best = std::numeric_limits<double>::infinity();
    auto visit = [&](const ring2& r) {
        for (const vec2& p : r) {
            const std::size_t idx = detail::matching::nearest_index(tree, p);
            const double d = glm::distance(p, cloud[idx]);
            if (d < best) best = d, from = p, to = cloud[idx];
        }
    };
    visit(piece.outer);
    for (const ring2& h : piece.holes) visit(h);
    return best;
}

// The united strips clipped to the domain and opened by a fifth of the narrowest strip width (so
// that pieces touching at a point, which would print as a hinge, count as separate). Pieces other
// than the largest (element ends cut off by the domain's boundary, the topology cut never
// disconnects) are joined to it by a straight strip of the narrowest width along their nearest
// contact when that is at most `max_bridge` mm long and lies in the domain (up to 4 passes, so a
// piece may join through another); what is left is trimmed (a piece of less area than a square of
// twice the width: shorter than a printable strip) or dropped, and counted.
inline std::vector<polygon_with_holes> one_piece(const std::vector<graph::skeleton_graph<vec2>>& sk, const planar_domain& d, double max_bridge,
                                                 piece_bookkeeping& book) {
    double w = std::numeric_limits<double>::infinity();
    for (const auto& g : sk)
        for (graph::vertex_id v = 0; v < g.num_vertices(); ++v)
            if (g.width(v) > 0) w = std::min(w, g.width(v));
    std::vector<polygon_with_holes> all = strip_outline(std::span<const graph::skeleton_graph<vec2>>(sk), d.region);
    if (all.empty() || !std::isfinite(w)) throw solver_error("filigree: the strips are empty");
    const double eps = 0.1 * w;
    all = polygon_offset(polygon_offset(all, -eps, 0.1 * eps), eps, 0.1 * eps);
    if (all.empty()) throw solver_error("filigree: the strips are empty");
    all = bridge_pinches(std::move(all), 1e-3 * w, 0.1 * w);  // tangencies the opening leaves
    const double total = area(all);
    auto largest = [](const std::vector<polygon_with_holes>& p) {
        std::size_t best = 0;
        for (std::size_t i = 1; i < p.size(); ++i)
            if (area(p[i]) > area(p[best])) best = i;
        return best;
    };
    book = {};
    const std::size_t pieces_before = all.size();
    for (int pass = 0; pass < 4 && all.size() > 1 && max_bridge > 0; ++pass) {
        const std::size_t m = largest(all);
        // The largest piece's boundary, sampled at most half a strip width apart (a straight strip's
        // side has vertices only at its ends), so the nearest sample is within w / 4 of the nearest point.
        std::vector<vec2> cloud;
        auto sample = [&](const ring2& r) {
            for (std::size_t k = 0; k < r.size(); ++k) {
                const vec2 a = r[k], b = r[(k + 1) % r.size()];
                const int n = std::max(1, static_cast<int>(std::ceil(glm::distance(a, b) / (0.5 * w))));
                for (int j = 0; j < n; ++j) cloud.push_back(a + (b - a) * (static_cast<double>(j) / n));
            }
        };
        sample(all[m].outer);
        for (const ring2& h : all[m].holes) sample(h);
        const detail::matching::point_cloud pc{cloud};
        detail::matching::kd_tree tree(2, pc, nanoflann::KDTreeSingleIndexAdaptorParams(10));
        tree.buildIndex();
        std::vector<std::vector<vec2>> bridges;
        for (std::size_t i = 0; i < all.size(); ++i) {
            if (i == m) continue;
            vec2 a, b;
            if (nearest_contact(all[i], tree, cloud, a, b) > max_bridge) continue;
            // the bridge must stay in the domain (a concave boundary or a hole may lie between)
            bool inside = true;
            for (int k = 0; k <= 8 && inside; ++k) inside = d.contains(a + (b - a) * (k / 8.0));
            if (inside) bridges.push_back({a, b});
        }
        if (bridges.empty()) break;
        std::vector<polygon_with_holes> joined = stroke_outline(bridges, 0.5 * w);
        joined = polygon_intersection(joined, d.region);
        joined.insert(joined.end(), all.begin(), all.end());
        all = polygon_union(joined, {});
    }
    const std::size_t m = largest(all);
    book.bridged = pieces_before - all.size();  // each joined piece removes one
    double removed = 0;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (i == m) continue;
        const double a = area(all[i]);
        removed += a;
        (a < 4 * w * w ? book.trimmed : book.dropped) += 1;
    }
    book.dropped_fraction = total > 0 ? removed / total : 0.0;
    return {all[m]};
}

[[nodiscard]] inline double narrowest_width(std::span<const element> classes) {
    double w = std::numeric_limits<double>::infinity();
    for (const element& e : classes)
        for (const double x : e.widths)
            if (x > 0) w = std::min(w, x);
    return std::isfinite(w) ? w : 0.0;
}

[[nodiscard]] inline double median_width(std::span<const element> classes) {
    std::vector<double> w;
    for (const element& e : classes) w.push_back(e.median_width());
    std::sort(w.begin(), w.end());
    return w[w.size() / 2];
}

// The options of both forms' reinforcement that every form checks (thickness bounds).
inline void check_thickness(const reinforcement_options& opt) {
    require_positive(opt.thickness, "reinforce: thickness (mm)");
    if (!(std::isfinite(opt.max_thickness) && opt.max_thickness >= 0))
        throw invalid_input("reinforce: max_thickness must be finite and >= 0 mm (0: no bound), got " + std::to_string(opt.max_thickness));
    if (opt.max_thickness > 0 && opt.thickness > opt.max_thickness)
        throw invalid_input("reinforce: the thickness " + std::to_string(opt.thickness) + " mm exceeds max_thickness " +
                            std::to_string(opt.max_thickness) + " mm");
}

// The analysis options of the planar form: material, pressure and opt.support (validated here, by
// name). `median_width`: the default radius of a hanging point (mm).
[[nodiscard]] inline structure_options planar_structure_options(const reinforcement_options& opt, double median_width) {
    const planar_support& ps = opt.support;
    structure_options sopt;
    sopt.material = preset_material(opt.material);
    sopt.pressure_pa = opt.pressure_pa;
    sopt.side = ps.side;
    sopt.support_fraction = ps.fraction;
    if (ps.box && ps.hang) throw invalid_input("reinforce: support: give at most one of box and hang");
    if (ps.box) {
        const box2 b = *ps.box;
        if (!(std::isfinite(b.lo.x) && std::isfinite(b.lo.y) && std::isfinite(b.hi.x) && std::isfinite(b.hi.y)) || b.empty())
            throw invalid_input("reinforce: support box must be finite with lo <= hi (mm)");
        sopt.support = [b](const vec2& p) { return b.contains(p); };
        sopt.support_description = "the support box [" + std::to_string(b.lo.x) + ", " + std::to_string(b.hi.x) + "] x [" +
                                   std::to_string(b.lo.y) + ", " + std::to_string(b.hi.y) + "] mm";
    }
    if (ps.hang) {
        const vec2 c = *ps.hang;
        if (!(std::isfinite(c.x) && std::isfinite(c.y))) throw invalid_input("reinforce: support hang point must be finite (mm)");
        if (!(std::isfinite(ps.hang_radius) && ps.hang_radius >= 0))
            throw invalid_input("reinforce: support hang_radius must be finite and >= 0 mm (0: the median strip width)");
        const double rad = ps.hang_radius > 0 ? ps.hang_radius : median_width;
        sopt.support = [c, rad](const vec2& p) { return glm::distance(p, c) <= rad; };
        sopt.support_description = "the hanging point (" + std::to_string(c.x) + ", " + std::to_string(c.y) + ") mm, radius " +
                                   std::to_string(rad) + " mm: put it on a strip or enlarge the radius";
    }
    if (ps.upright) sopt.gravity_down = {0.0, 1.0, 0.0};
    sopt.validate();
    return sopt;
}

// planar_support at its defaults (what the surface form requires: its supports follow `up`).
[[nodiscard]] inline bool default_support(const planar_support& ps) {
    return ps.side == support_side::top && ps.fraction == 0.05 && !ps.box && !ps.hang && ps.hang_radius == 0 && !ps.upright;
}

}  // namespace detail::reinforce

/// Strips, one piece and the structural optimization (see the file comment) of a synthesized
/// pattern `syn` (from synthesize_pattern with the same classes, domain, field and options).
template <control_field F>
[[nodiscard]] reinforcement_result reinforce(std::span<const element> classes, std::span<const double> weights, const planar_domain& domain,
                                             const F& field, const synthesis_options& so, const synthesis_result& syn,
                                             const reinforcement_options& opt = {}, const progress_span& progress = {}) {
    namespace dr = detail::reinforce;
    dr::check_thickness(opt);
    const auto t0 = std::chrono::steady_clock::now();
    reinforcement_result r;
    r.instances = syn.instances;
    r.skeletons = syn.skeletons;
    r.thickness = opt.thickness;
    const double max_bridge = opt.max_bridge_mm < 0 ? 0.0 : opt.max_bridge_mm > 0 ? opt.max_bridge_mm : 4 * dr::narrowest_width(classes);
    dr::piece_bookkeeping book;
    r.outline = dr::one_piece(syn.skeletons, domain, max_bridge, book);
    auto keep_book = [&](const dr::piece_bookkeeping& b) {
        r.pieces_dropped = b.dropped, r.pieces_bridged = b.bridged, r.pieces_trimmed = b.trimmed, r.dropped_area_fraction = b.dropped_fraction;
    };
    keep_book(book);
    if (opt.enabled) {
        const double h = opt.mesh_edge > 0 ? opt.mesh_edge : 0.6 * dr::median_width(classes);
        const structure_options sopt = dr::planar_structure_options(opt, dr::median_width(classes));
        r.yield_mpa = sopt.material.yield_mpa;
        r.histogram_bin_mpa = sopt.histogram_bin_mpa;
        struct layout {
            std::vector<instance> instances;
            std::vector<graph::skeleton_graph<vec2>> skeletons;
            std::vector<polygon_with_holes> outline;
            dr::piece_bookkeeping book;
            fem_triangulation tri;
        };
        layout best{r.instances, r.skeletons, r.outline, book,
                    piece_triangulation(r.outline, h)};
        const std::uint32_t cls = reinforcement_class(weights);
        reinforcement_loop(
            best, r, opt, [&](const layout& l, double t) { return analyse_structure(l.tri, t, sopt); },
            [&](const layout& l, const structural_report& rep, int round, std::size_t& added, const progress_span& grow_progress) -> std::optional<layout> {
                std::vector<instance> in = l.instances;
                for (const vec2& c : weak_region_centres(rep, 0.5 * classes[cls].size)) {
                    if (!domain.contains(c)) continue;
                    const std::uint32_t here = reinforcement_class(weights, [&](std::uint32_t k) { return !domain.class_allowed || domain.class_allowed(k, c); });
                    if (here != UINT32_MAX) in.push_back(make_instance(classes, here, c, field)), ++added;
                }
                if (added == 0) return std::nullopt;
                pattern_state s(classes, std::move(in), any_field(field), domain, so.gamma_boundary);
                synthesis_options again = so;
                again.max_rounds = opt.resynthesis_rounds;
                again.seed = so.seed + 1000 * static_cast<std::uint64_t>(round + 1);
                synthesis_result res;
                optimize_pattern(s, again, res, grow_progress);
                layout next;
                next.outline = dr::one_piece(res.skeletons, domain, max_bridge, next.book);
                next.tri = piece_triangulation(next.outline, h);
                next.instances = std::move(res.instances);
                next.skeletons = std::move(res.skeletons);
                return next;
            },
            [&](const layout& l, double t, const progress_span& thicken_progress) {
                thickening_result th = thicken_until_strong(l.tri, t, sopt, {.max_thickness = opt.max_thickness}, thicken_progress);
                r.fem_nodes = th.report.node_positions.size();
                r.fem = l.tri;
                r.final_report = th.report;
                for (const std::uint32_t n : th.report.weak_nodes) r.weak_points.push_back(th.report.node_positions[n]);
                return th;
            },
            progress);
        r.instances = std::move(best.instances), r.skeletons = std::move(best.skeletons), r.outline = std::move(best.outline);
        keep_book(best.book);
    }
    r.components = r.outline.size();
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace fabsynth::filigree
