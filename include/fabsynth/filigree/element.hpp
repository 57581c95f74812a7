// SPDX-License-Identifier: MIT
#pragma once
/// @file element.hpp  Filigree elements (filigree-synthesis.md §3.3, §4.1, §4.2): the skeleton graph
/// of one exemplar element as polylines with a width per vertex, its reference point, and its
/// covering region, read from an SVG drawing.
///
/// Usage:
///   auto doc = fabsynth::io::read_svg("data/filigree/spiral.svg", 0.01);
///   fabsynth::filigree::element e = fabsynth::filigree::element_from_svg(doc, {.size_mm = 20, .width_mm = 0.8});
///   // e.vertices / e.widths / e.edges: the skeleton in mm, reference point at (0, 0)
///   // e.covering: convex rings whose union is the covering region (§4.2)
///
/// What becomes the skeleton (§3.3):
///  - stroked shapes (stroke not "none", fill "none"): each subpath is a skeleton polyline, the
///    stroke width is the strip width; closed subpaths are closed loops;
///  - filled shapes (fill not "none"): the filled region (its fill rule) is reduced to its medial axis
///    (geometry/medial_axis.hpp), each vertex keeping twice its distance to the outline as width;
///    spurs shorter than `prune` times the widest strip width are removed;
///  - shapes whose `id` starts with "cover" are not skeleton: their convex hulls are the convex parts
///    of the covering region (the paper lets the user decompose a non-convex element, §4.2). Without
///    them the covering region is the convex hull of the strips (skeleton dilated by width / 2).
/// Polylines are approximated to `tolerance_mm` (Douglas-Peucker), then edges longer than
/// `max_edge_mm` are split evenly: the pattern matching energy compares skeleton *vertices* (§4.2,
/// eq. 2), so a long straight run must still carry points.
///
/// Frame: SVG user space (y down) scaled uniformly so that the element's size, the diagonal of the
/// skeleton's bounding box (§4.1), is `size_mm`; then translated so that the reference point is the
/// origin. Rotations elsewhere in filigree/ are counter-clockwise in a y-up frame (clockwise on an
/// SVG screen).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/drawing.hpp"
#include "fabsynth/geometry/hull_simplify.hpp"
#include "fabsynth/geometry/medial_axis.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/graph/skeleton_graph.hpp"

namespace fabsynth::filigree {

/// What element_from_svg and planar_domain::from_svg read from a drawing (geometry/drawing.hpp;
/// io::svg_document satisfies it; a template so that the pipeline does not depend on io/).

/// Edge of an element skeleton: two vertex indices.
using skeleton_edge = std::array<std::uint32_t, 2>;

/// How an SVG drawing becomes an element. Lengths in mm (after scaling) unless noted.
struct element_options {
    double size_mm = 20.0;          ///< bounding-box diagonal of the skeleton after scaling; > 0
    double width_mm = 0.0;          ///< strip width for every vertex; 0 = from the SVG (stroke width or medial axis)
    double tolerance_mm = 0.05;     ///< polygonal approximation tolerance; > 0
    double max_edge_mm = 0.0;       ///< longest skeleton edge; 0 = max(2 * median width, size / 40)
    double prune = 1.0;             ///< medial-axis spurs shorter than prune x the widest strip width are removed
    std::optional<vec2> reference;  ///< reference point in SVG user units; default the skeleton's bounding-box centre
    std::string name;               ///< for messages and reports
};

/// One element class: skeleton, widths and covering region in the element frame (mm, reference
/// point at the origin).
struct element {
    std::string name;
    std::vector<vec2> vertices;       ///< #V skeleton vertices
    std::vector<double> widths;       ///< #V strip widths (full width, mm), > 0
    std::vector<skeleton_edge> edges; ///< #E straight edges
    std::vector<ring2> covering;      ///< convex rings (counter-clockwise), their union is the covering region
    double covering_area = 0.0;       ///< mm^2, area of the union of `covering`
    double size = 0.0;                ///< mm, diagonal of the skeleton's bounding box (§4.1)

    /// Total skeleton length (mm).
    [[nodiscard]] double length() const {
        double l = 0;
        for (const skeleton_edge& e : edges) l += glm::distance(vertices[e[0]], vertices[e[1]]);
        return l;
    }
    /// Median strip width (mm).
    [[nodiscard]] double median_width() const {
        std::vector<double> w = widths;
        std::nth_element(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(w.size() / 2), w.end());
        return w.empty() ? 0.0 : w[w.size() / 2];
    }
};

namespace detail::element_build {

struct raw_skeleton {  // in SVG user units
    std::vector<graph::skeleton_polyline<vec2>> lines;
    std::vector<std::vector<vec2>> cover_parts;
};

template <class Shape>
bool is_cover(const Shape& s) {
    return std::string(s.id).rfind("cover", 0) == 0;
}

// Stroked subpaths -> polylines (closed subpaths repeat their first point at the end).
template <class Shape>
void add_stroked(const Shape& s, raw_skeleton& raw) {
    for (std::size_t i = 0; i < s.subpaths.size(); ++i) {
        std::vector<vec2> pts = s.subpaths[i];
        if (pts.size() < 2) continue;
        if (s.closed[i]) pts.push_back(pts.front());
        raw.lines.push_back({pts, std::vector<double>(pts.size(), s.stroke_width)});
    }
}

// Filled region -> medial-axis edges, each edge a 2-point polyline (welded later).
template <class Shape>
void add_filled(const Shape& s, double tolerance_units, double prune, raw_skeleton& raw) {
    std::vector<ring2> rings;
    for (const auto& sp : s.subpaths)
        if (sp.size() >= 3) rings.emplace_back(sp.begin(), sp.end());
    const std::vector<polygon_with_holes> polys = polygon_union(rings, s.rule);
    for (const polygon_with_holes& p : polys) {
        medial_axis_options mo;
        mo.flattening_tolerance = tolerance_units;
        mo.prune_length = 0.0;
        const medial_skeleton m = medial_axis(p, mo);
        // Spurs run from the strip's axis into its corners, about one width long: prune by the
        // widest inscribed disc; a vertex thinner than a tenth of that keeps that tenth (a strip
        // end tapering to a point would otherwise print as nothing).
        double max_w = 0;
        for (double h : m.half_widths) max_w = std::max(max_w, 2 * h);
        mo.prune_length = prune * max_w;
        const medial_skeleton pr = prune > 0 && max_w > 0 ? medial_axis(p, mo) : m;
        for (const auto& e : pr.edges)
            raw.lines.push_back({{pr.positions[e[0]], pr.positions[e[1]]},
                                 {std::max(2 * pr.half_widths[e[0]], 0.1 * max_w), std::max(2 * pr.half_widths[e[1]], 0.1 * max_w)}});
    }
}

// Douglas-Peucker on the points of one polyline, widths carried by the kept points.
inline graph::skeleton_polyline<vec2> simplified(const graph::skeleton_polyline<vec2>& l, double tol) {
    if (l.points.size() <= 2) return l;
    const std::vector<vec2> kept = simplify_polyline(l.points, tol);
    graph::skeleton_polyline<vec2> out;
    std::size_t k = 0;
    for (const vec2& q : kept) {
        while (k < l.points.size() && l.points[k] != q) ++k;
        out.points.push_back(q);
        out.widths.push_back(k < l.points.size() ? l.widths[k] : l.widths.back());
    }
    return out;
}

}  // namespace detail::element_build

/// The element drawn in `doc` (see the file comment). Throws invalid_input naming the problem: no
/// stroked or filled shape, bad options, a degenerate (zero-size) skeleton.
template <stroked_document Doc>
[[nodiscard]] element element_from_svg(const Doc& doc, const element_options& opt = {}) {
    namespace eb = detail::element_build;
    const std::string who = opt.name.empty() ? std::string("element") : opt.name;
    if (!(std::isfinite(opt.size_mm) && opt.size_mm > 0)) throw invalid_input(who + ": the element size must be finite and > 0 mm");
    if (!(std::isfinite(opt.width_mm) && opt.width_mm >= 0)) throw invalid_input(who + ": the strip width must be finite and >= 0 mm");
    if (!(std::isfinite(opt.tolerance_mm) && opt.tolerance_mm > 0)) throw invalid_input(who + ": the tolerance must be finite and > 0 mm");
    if (!(std::isfinite(opt.max_edge_mm) && opt.max_edge_mm >= 0)) throw invalid_input(who + ": the longest edge must be finite and >= 0 mm");
    if (opt.reference && !all_finite(*opt.reference)) throw invalid_input(who + ": the reference point is not finite");

    // Bounding box of the drawn skeleton geometry in user units gives the scale before the medial
    // axis is taken (its tolerance is in user units).
    box2 drawn;
    for (const auto& s : doc.shapes)
        if (!eb::is_cover(s) && (s.stroked() || s.filled()))
            for (const auto& sp : s.subpaths)
                for (const vec2& p : sp) drawn.extend(p);
    if (drawn.empty()) throw invalid_input(who + ": the SVG has no stroked path or filled shape to take a skeleton from");
    const double drawn_diag = glm::length(drawn.hi - drawn.lo);
    if (!(drawn_diag > 0)) throw invalid_input(who + ": the drawing has zero size");
    const double tol_units = opt.tolerance_mm * drawn_diag / opt.size_mm;

    eb::raw_skeleton raw;
    for (const auto& s : doc.shapes) {
        if (eb::is_cover(s)) {
            std::vector<vec2> pts;
            for (const auto& sp : s.subpaths) pts.insert(pts.end(), sp.begin(), sp.end());
            if (pts.size() >= 3) raw.cover_parts.push_back(pts);
        } else if (s.filled()) {
            eb::add_filled(s, tol_units, opt.prune, raw);
        } else if (s.stroked()) {
            eb::add_stroked(s, raw);
        }
    }
    if (raw.lines.empty()) throw invalid_input(who + ": the SVG has no stroked path or filled shape to take a skeleton from");

    // Skeleton in user units: simplify, weld shared endpoints, then measure it.
    std::vector<graph::skeleton_polyline<vec2>> lines;
    for (const auto& l : raw.lines) lines.push_back(eb::simplified(l, tol_units));
    const graph::skeleton_graph<vec2> g = graph::skeleton_from_polylines(lines, 1e-9 * drawn_diag);
    box2 sk;
    for (graph::vertex_id v = 0; v < g.num_vertices(); ++v) sk.extend(g.position(v));
    const double diag = glm::length(sk.hi - sk.lo);
    if (!(diag > 0)) throw invalid_input(who + ": the skeleton has zero size");
    const double k = opt.size_mm / diag;
    const vec2 ref = opt.reference ? *opt.reference : 0.5 * (sk.lo + sk.hi);
    auto to_mm = [&](vec2 p) { return (p - ref) * k; };

    element e;
    e.name = who;
    e.size = opt.size_mm;
    std::vector<std::uint32_t> id(g.num_vertices(), UINT32_MAX);
    for (graph::vertex_id v = 0; v < g.num_vertices(); ++v) {
        if (g.valence(v) == 0) continue;
        id[v] = static_cast<std::uint32_t>(e.vertices.size());
        e.vertices.push_back(to_mm(g.position(v)));
        const double w = opt.width_mm > 0 ? opt.width_mm : g.width(v) * k;
        if (!(w > 0)) throw invalid_input(who + ": a skeleton vertex has zero width (give --width)");
        e.widths.push_back(w);
    }
    const double max_edge = opt.max_edge_mm > 0 ? opt.max_edge_mm : std::max(2 * e.median_width(), opt.size_mm / 40);
    for (graph::edge_id ed = 0; ed < g.edge_slots(); ++ed) {
        if (!g.edge_alive(ed)) continue;
        const auto [a, b] = g.endpoints(ed);
        std::uint32_t prev = id[a];
        const vec2 pa = e.vertices[id[a]], pb = e.vertices[id[b]];
        const int pieces = std::max(1, static_cast<int>(std::ceil(glm::distance(pa, pb) / max_edge)));
        for (int i = 1; i < pieces; ++i) {  // split long edges evenly
            const double t = static_cast<double>(i) / pieces;
            e.vertices.push_back(pa + t * (pb - pa));
            e.widths.push_back(e.widths[id[a]] + t * (e.widths[id[b]] - e.widths[id[a]]));
            const auto v = static_cast<std::uint32_t>(e.vertices.size() - 1);
            e.edges.push_back({prev, v});
            prev = v;
        }
        e.edges.push_back({prev, id[b]});
    }

    // Covering region: the user's convex parts, else the hull of the strips.
    if (!raw.cover_parts.empty()) {
        for (const auto& part : raw.cover_parts) {
            std::vector<vec2> mm;
            for (const vec2& p : part) mm.push_back(to_mm(p));
            ring2 h = convex_hull(mm);
            if (h.size() >= 3) e.covering.push_back(std::move(h));
        }
    } else {
        std::vector<vec2> pts;
        for (std::size_t i = 0; i < e.vertices.size(); ++i)
            for (int a = 0; a < 8; ++a) {
                const double t = a * std::numbers::pi / 4;
                pts.push_back(e.vertices[i] + 0.5 * e.widths[i] * vec2(std::cos(t), std::sin(t)));
            }
        e.covering.push_back(convex_hull(pts));
    }
    if (e.covering.empty()) throw invalid_input(who + ": the covering parts have no area");
    e.covering_area = area(polygon_union(e.covering, fill_rule::nonzero));
    if (!(e.covering_area > 0)) throw invalid_input(who + ": the covering region has no area");
    return e;
}

}  // namespace fabsynth::filigree
