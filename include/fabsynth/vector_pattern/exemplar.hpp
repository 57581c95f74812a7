// SPDX-License-Identifier: MIT
#pragma once
/// @file exemplar.hpp  Vector-pattern exemplars (Zhou et al. 2014, "Topology-constrained synthesis
/// of vector patterns", §3.2): simple general polygons with holes, several components allowed.
///
/// An exemplar is a band lying along x (the curve's U axis); y is the band's V axis. Coordinates
/// stay as given (for SVG input: user units, y pointing down, so "top" = smallest y). Outer rings
/// are oriented with positive signed area (shoelace, in those coordinates), holes negative: the
/// orientation is recovered from nesting, whatever the input orientation (§3.2).
///
/// Invalid geometry (self-intersecting rings, rings crossing or overlapping one another) is
/// repaired by a boolean union under each shape's fill rule (geometry/clip.hpp), or rejected when
/// repair is off. Open subpaths are rejected by default (a fill would silently close them), or
/// closed on request.
///
/// Usage:
///   auto doc = fabsynth::io::read_svg("data/vector/greek_key.svg");     // the driver reads files
///   fabsynth::vector_pattern::exemplar ex = fabsynth::vector_pattern::exemplar_from_svg(doc);
///   ex.components();  // 1
///   ex.holes();       // 6
///   auto band = fabsynth::vector_pattern::scaled(ex, 10.0 / ex.height());  // 10 mm high
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/geometry/drawing.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth::vector_pattern {

/// A vector exemplar: non-overlapping simple polygons with holes.
struct exemplar {
    std::vector<polygon_with_holes> polygons;  ///< one per connected component (outer ccw-positive, holes negative)
    /// The band's extent (mm). y: the outer rings' extent. x: the outer rings' extent, widened by
    /// exemplar_from_svg to the document's viewBox when that holds every ring, so that empty
    /// margins at the band's ends count: they are half the spacing of separate motifs (beads,
    /// dots), which slicing (pieces.hpp) would otherwise lose at P_0 and P_t.
    box2 bounds;
    bool repaired = false;                     ///< true if the input needed a boolean union to become valid

    [[nodiscard]] std::size_t components() const noexcept { return polygons.size(); }
    [[nodiscard]] std::size_t holes() const noexcept {
        std::size_t h = 0;
        for (const auto& p : polygons) h += p.holes.size();
        return h;
    }
    /// Width W along x (the sweep axis) and height along y (mm).
    [[nodiscard]] double width() const noexcept { return bounds.size().x; }
    [[nodiscard]] double height() const noexcept { return bounds.size().y; }
    /// Filled area (mm^2).
    [[nodiscard]] double area() const noexcept { return fabsynth::area(polygons); }
};

/// What to do with open subpaths.
enum class open_path_policy {
    reject,  ///< throw invalid_input naming the shape and subpath (default)
    close    ///< close them, as an SVG fill does
};

/// Options for building exemplars.
struct exemplar_options {
    bool repair = true;                                  ///< repair invalid geometry by a union (else reject)
    open_path_policy open_paths = open_path_policy::reject;
    double relative_area_tolerance = 1e-9;               ///< |union area - nested area| / area above this = invalid
    /// exemplar_from_svg: the band spans the document's viewBox along x when it holds every ring
    /// (false: the rings' own extent, no end margins).
    bool document_extent = true;
};

/// One filled shape: its subpaths (closed[i] tells whether subpath i is closed) and fill rule.
struct exemplar_shape {
    std::vector<std::vector<vec2>> subpaths;
    std::vector<bool> closed;  ///< same size as subpaths (empty = all closed)
    fill_rule rule = fill_rule::nonzero;
    std::string name;          ///< for error messages (e.g. the SVG id)
};

namespace detail {
inline std::string shape_name(const exemplar_shape& s, std::size_t i) {
    return "shape " + std::to_string(i) + (s.name.empty() ? std::string() : " ('" + s.name + "')");
}
}  // namespace detail

/// Builds an exemplar from filled shapes. Throws invalid_input for: no shape with area, non-finite
/// coordinates, open subpaths (policy reject), invalid geometry with repair off. O(R^2 n) for R
/// rings of n points (ring nesting) plus one Clipper union.
[[nodiscard]] inline exemplar make_exemplar(const std::vector<exemplar_shape>& shapes, const exemplar_options& opt = {}) {
    if (!(opt.relative_area_tolerance >= 0.0)) throw invalid_input("exemplar: relative_area_tolerance must be >= 0");
    std::vector<ring2> all;                     // every ring, for nesting
    std::vector<std::vector<ring2>> per_shape;  // rings per shape, for the union under each rule
    bool valid = true;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        const exemplar_shape& s = shapes[i];
        if (!s.closed.empty() && s.closed.size() != s.subpaths.size())
            throw invalid_input("exemplar: " + detail::shape_name(s, i) + " has " + std::to_string(s.closed.size()) +
                                " closed flags for " + std::to_string(s.subpaths.size()) + " subpaths");
        std::vector<ring2> rings;
        for (std::size_t k = 0; k < s.subpaths.size(); ++k) {
            const auto& sp = s.subpaths[k];
            for (const vec2& p : sp)
                if (!all_finite(p))
                    throw invalid_input("exemplar: " + detail::shape_name(s, i) + " subpath " + std::to_string(k) +
                                        " has a non-finite coordinate");
            if (!s.closed.empty() && !s.closed[k] && opt.open_paths == open_path_policy::reject)
                throw invalid_input("exemplar: " + detail::shape_name(s, i) + " subpath " + std::to_string(k) +
                                    " is an open path; exemplars need closed outlines (close it, or use "
                                    "open_path_policy::close)");
            if (sp.size() < 3) continue;  // draws nothing (zero-area rings are left to the repair)
            if (!is_simple(sp)) valid = false;
            rings.push_back(sp);
        }
        all.insert(all.end(), rings.begin(), rings.end());
        per_shape.push_back(std::move(rings));
    }
    if (all.empty()) throw invalid_input("exemplar: no closed shape with at least 3 points (empty input)");

    box2 b;
    for (const ring2& r : all) b.extend(bounding_box(r));
    const clip_grid grid = clip_grid::for_bounds(b);
    // The filled region, by Clipper: union of every shape filled by its own rule.
    std::vector<polygon_with_holes> region;
    for (std::size_t i = 0; i < per_shape.size(); ++i) {
        if (per_shape[i].empty()) continue;
        region = polygon_union(region, polygon_union(per_shape[i], shapes[i].rule, grid), grid);
    }
    exemplar ex;
    std::vector<polygon_with_holes> nested;
    if (valid) {
        // Valid input keeps its own vertices: nesting parity (group_rings) is the even-odd fill, which
        // equals the union only if no two rings cross or overlap and the fill rules agree with it.
        nested = group_rings(all);
        const double a = fabsynth::area(region), an = fabsynth::area(nested);
        if (!(std::abs(a - an) <= opt.relative_area_tolerance * std::max(a, an))) valid = false;
    }
    if (!valid) {
        if (!opt.repair)
            throw invalid_input("exemplar: invalid geometry (self-intersecting, crossing or overlapping rings) and "
                                "repair is off");
        nested = std::move(region);
        ex.repaired = true;
    }
    std::erase_if(nested, [](const polygon_with_holes& p) { return area(p) <= 0.0; });
    if (nested.empty()) throw invalid_input("exemplar: the shapes fill no area (every ring is degenerate)");
    ex.polygons = std::move(nested);
    for (const auto& p : ex.polygons) ex.bounds.extend(bounding_box(p.outer));
    return ex;
}

/// The exemplar scaled about the origin by s > 0 (mm per input unit; e.g. to a band height H:
/// s = H / ex.height()). A similarity with a positive factor, so simple rings stay simple and
/// orientations are kept; `repaired` is carried over. Throws invalid_input unless s is finite and > 0.
[[nodiscard]] inline exemplar scaled(const exemplar& ex, double s) {
    if (!(std::isfinite(s) && s > 0.0)) throw invalid_input("exemplar scaled: the factor must be finite and > 0, got " + std::to_string(s));
    exemplar out = ex;
    auto scale_ring = [s](ring2& r) {
        for (vec2& p : r) p *= s;
    };
    for (auto& p : out.polygons) {
        scale_ring(p.outer);
        for (ring2& h : p.holes) scale_ring(h);
    }
    out.bounds = box2(ex.bounds.lo * s, ex.bounds.hi * s);
    return out;
}

/// What exemplar_from_svg reads from a document: geometry/drawing.hpp's svg_like_document
/// (io::svg_document satisfies it; a template so that this building block does not depend on io/).
using fabsynth::svg_like_document;

/// Exemplar from the filled shapes of an SVG document (unfilled shapes, e.g. fill="none" strokes,
/// draw no area and are skipped); its x extent is the document's viewBox when that holds every
/// shape (exemplar_options::document_extent). Throws invalid_input as make_exemplar, and for a document with
/// no filled shape.
template <svg_like_document Doc>
[[nodiscard]] exemplar exemplar_from_svg(const Doc& doc, const exemplar_options& opt = {}) {
    std::vector<exemplar_shape> shapes;
    for (const auto& s : doc.shapes) {
        if (!s.filled()) continue;
        exemplar_shape e;
        e.subpaths.assign(s.subpaths.begin(), s.subpaths.end());
        e.closed.assign(s.closed.begin(), s.closed.end());
        e.rule = s.rule;
        e.name = s.id;
        shapes.push_back(std::move(e));
    }
    if (shapes.empty()) throw invalid_input("exemplar: the SVG document has no filled shape");
    exemplar ex = make_exemplar(shapes, opt);
    if constexpr (requires { doc.view_box->min_x; doc.view_box->width; }) {
        if (opt.document_extent && doc.view_box) {
            const double x0 = doc.view_box->min_x, x1 = doc.view_box->min_x + doc.view_box->width;
            const double slack = 1e-9 * std::max(1.0, ex.width());
            if (std::isfinite(x0) && std::isfinite(x1) && x0 <= ex.bounds.lo.x + slack && x1 >= ex.bounds.hi.x - slack)
                ex.bounds.lo.x = std::min(x0, ex.bounds.lo.x), ex.bounds.hi.x = std::max(x1, ex.bounds.hi.x);
        }
    }
    return ex;
}

}  // namespace fabsynth::vector_pattern
