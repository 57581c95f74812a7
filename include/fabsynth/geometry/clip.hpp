// SPDX-License-Identifier: MIT
#pragma once
/// @file clip.hpp  Polygon booleans (union, intersection, difference, xor) and clipping by a
/// vertical strip: a thin wrapper around Clipper 6 (Angus Johnson, libpolyclipping).
///
/// Clipper works on integer coordinates. Points are mapped to integers by a clip_grid: x_int =
/// round(x * scale) with scale a power of two chosen so that the largest |coordinate| maps near
/// 2^50. Because the scale is a power of two, the way back (x_int / scale) is exact, every input
/// coordinate representable on the grid survives unchanged, and grids for nested bounds are nested
/// (a finer grid holds every point of a coarser one). Coordinates created by the booleans
/// (intersections) are rounded to the grid: relative error ~2^-50 of the largest coordinate.
/// Pass one grid to several calls (e.g. clipping one shape into strips) so that they round alike.
///
/// Results are polygons with holes (geometry/polygon.hpp) oriented by orient(): outer rings with
/// positive signed area, holes negative; islands inside holes are separate polygons. Outputs are
/// "strictly simple" (Clipper's StrictlySimple): rings touching at a vertex are split.
///
/// Usage:
///   auto fixed = fabsynth::polygon_union(rings, fabsynth::fill_rule::nonzero);   // repair
///   auto both  = fabsynth::polygon_intersection(a, b);
///   auto strip = fabsynth::clip_strip(shape, 10.0, 20.0);                         // 10 <= x <= 20
///   double a   = fabsynth::area(strip);
///
/// Errors: invalid_input for non-finite coordinates or an empty/inverted strip; solver_error if
/// Clipper reports a failure.
#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth {

/// Integer grid for Clipper: x_int = round(x * scale), scale a power of two.
struct clip_grid {
    double scale = 1.0;  ///< integer units per input unit (a power of two)

    /// The grid for points within `b` (|coordinate| * scale <= 2^50). Throws invalid_input if b is
    /// empty or not finite.
    [[nodiscard]] static clip_grid for_bounds(const box2& b) {
        if (b.empty() || !all_finite(b.lo) || !all_finite(b.hi))
            throw invalid_input("clip grid: bounds are empty or not finite");
        double m = std::max({std::abs(b.lo.x), std::abs(b.lo.y), std::abs(b.hi.x), std::abs(b.hi.y)});
        if (m == 0.0) m = 1.0;
        int e = 0;
        (void)std::frexp(m, &e);  // m < 2^e
        clip_grid g;
        g.scale = std::ldexp(1.0, std::clamp(50 - e, -1000, 1000));
        return g;
    }
    /// x rounded to the grid (what a cut at x becomes).
    [[nodiscard]] double snap(double x) const { return std::nearbyint(x * scale) / scale; }
    [[nodiscard]] ClipperLib::IntPoint to_int(vec2 p) const {
        return {static_cast<ClipperLib::cInt>(std::nearbyint(p.x * scale)),
                static_cast<ClipperLib::cInt>(std::nearbyint(p.y * scale))};
    }
    [[nodiscard]] vec2 to_point(const ClipperLib::IntPoint& p) const {
        return {static_cast<double>(p.X) / scale, static_cast<double>(p.Y) / scale};
    }
};

/// Total area of polygons with holes (sum of area(p); mm^2).
[[nodiscard]] inline double area(const std::vector<polygon_with_holes>& polys) noexcept {
    double a = 0.0;
    for (const polygon_with_holes& p : polys) a += area(p);
    return a;
}

/// Every ring of the polygons (outer rings then their holes, polygon by polygon).
[[nodiscard]] inline std::vector<ring2> to_rings(const std::vector<polygon_with_holes>& polys) {
    std::vector<ring2> r;
    for (const polygon_with_holes& p : polys) {
        r.push_back(p.outer);
        r.insert(r.end(), p.holes.begin(), p.holes.end());
    }
    return r;
}

/// Bounding box of polygons (empty box if none).
[[nodiscard]] inline box2 bounding_box(const std::vector<polygon_with_holes>& polys) noexcept {
    box2 b;
    for (const polygon_with_holes& p : polys) b.extend(bounding_box(p.outer));
    return b;
}

/// The boolean operations.
enum class clip_op { union_, intersection, difference, xor_ };

namespace detail::clip {

inline box2 bounds_of(const std::vector<ring2>& rings, const char* what) {
    box2 b;
    for (std::size_t i = 0; i < rings.size(); ++i)
        for (const vec2& p : rings[i]) {
            if (!all_finite(p))
                throw invalid_input(std::string(what) + ": ring " + std::to_string(i) + " has a non-finite point");
            b.extend(p);
        }
    return b;
}

inline ClipperLib::Paths to_paths(const std::vector<ring2>& rings, const clip_grid& g) {
    ClipperLib::Paths out;
    out.reserve(rings.size());
    for (const ring2& r : rings) {
        if (r.size() < 3) continue;
        ClipperLib::Path p;
        p.reserve(r.size());
        for (const vec2& v : r) p.push_back(g.to_int(v));
        out.push_back(std::move(p));
    }
    return out;
}

inline void collect(const ClipperLib::PolyNode& outer, const clip_grid& g, std::vector<polygon_with_holes>& out) {
    auto ring_of = [&](const ClipperLib::Path& p) {
        ring2 r;
        r.reserve(p.size());
        for (const auto& q : p) r.push_back(g.to_point(q));
        return r;
    };
    polygon_with_holes poly{ring_of(outer.Contour), {}};
    for (const ClipperLib::PolyNode* hole : outer.Childs) {
        poly.holes.push_back(ring_of(hole->Contour));
        for (const ClipperLib::PolyNode* island : hole->Childs) collect(*island, g, out);
    }
    orient(poly);
    out.push_back(std::move(poly));
}

inline ClipperLib::PolyFillType fill_of(fill_rule r) {
    return r == fill_rule::evenodd ? ClipperLib::pftEvenOdd : ClipperLib::pftNonZero;
}

}  // namespace detail::clip

/// General boolean of two ring sets, each filled by its own rule: subject OP clip. `grid` defaults
/// to clip_grid::for_bounds of both inputs. Rings with fewer than 3 points are ignored. Output
/// polygons are ordered as Clipper returns them (deterministic for equal inputs). O((n + k) log n)
/// for n edges and k intersections. strictly_simple = false skips Clipper's splitting of rings
/// that touch at a vertex, which is much faster when many edges coincide (e.g. re-uniting
/// slices), at the price of rings that may touch themselves at a point.
[[nodiscard]] inline std::vector<polygon_with_holes> polygon_boolean(clip_op op, const std::vector<ring2>& subject,
                                                                     fill_rule subject_rule, const std::vector<ring2>& clip,
                                                                     fill_rule clip_rule,
                                                                     std::optional<clip_grid> grid = std::nullopt,
                                                                     bool strictly_simple = true) {
    box2 b = detail::clip::bounds_of(subject, "polygon boolean: subject");
    b.extend(detail::clip::bounds_of(clip, "polygon boolean: clip"));
    if (b.empty()) return {};
    const clip_grid g = grid ? *grid : clip_grid::for_bounds(b);
    if (!(g.scale > 0.0) || !std::isfinite(g.scale)) throw invalid_input("polygon boolean: grid scale must be finite and > 0");
    constexpr double limit = 4.0e18;  // below Clipper's hiRange (2^62 - 1)
    for (double c : {b.lo.x, b.lo.y, b.hi.x, b.hi.y})
        if (std::abs(c * g.scale) > limit) throw invalid_input("polygon boolean: coordinates too large for the grid");
    static constexpr ClipperLib::ClipType types[] = {ClipperLib::ctUnion, ClipperLib::ctIntersection,
                                                     ClipperLib::ctDifference, ClipperLib::ctXor};
    ClipperLib::PolyTree tree;
    try {
        ClipperLib::Clipper c;
        c.StrictlySimple(strictly_simple);
        const bool any_subject = c.AddPaths(detail::clip::to_paths(subject, g), ClipperLib::ptSubject, true);
        const bool any_clip = c.AddPaths(detail::clip::to_paths(clip, g), ClipperLib::ptClip, true);
        if (!any_subject && !any_clip) return {};  // only degenerate rings: nothing is filled
        if (!c.Execute(types[static_cast<int>(op)], tree, detail::clip::fill_of(subject_rule), detail::clip::fill_of(clip_rule)))
            throw solver_error("polygon boolean: Clipper failed");
    } catch (const error&) {
        throw;
    } catch (const std::exception& e) {
        throw solver_error(std::string("polygon boolean: Clipper failed: ") + e.what());
    }
    std::vector<polygon_with_holes> out;
    for (const ClipperLib::PolyNode* n : tree.Childs) detail::clip::collect(*n, g, out);
    return out;
}

/// The region filled by `rings` under `rule`, as simple polygons with holes: repairs
/// self-intersecting or overlapping rings.
[[nodiscard]] inline std::vector<polygon_with_holes> polygon_union(const std::vector<ring2>& rings, fill_rule rule,
                                                                   std::optional<clip_grid> grid = std::nullopt) {
    return polygon_boolean(clip_op::union_, rings, rule, {}, rule, grid);
}

/// a OR b. Polygon sets are filled by the nonzero rule after orienting (they may overlap).
[[nodiscard]] inline std::vector<polygon_with_holes> polygon_union(const std::vector<polygon_with_holes>& a,
                                                                   const std::vector<polygon_with_holes>& b,
                                                                   std::optional<clip_grid> grid = std::nullopt) {
    auto oa = a, ob = b;
    for (auto& p : oa) orient(p);
    for (auto& p : ob) orient(p);
    return polygon_boolean(clip_op::union_, to_rings(oa), fill_rule::nonzero, to_rings(ob), fill_rule::nonzero, grid);
}

namespace detail::clip {
inline std::vector<polygon_with_holes> binary(clip_op op, const std::vector<polygon_with_holes>& a,
                                              const std::vector<polygon_with_holes>& b, std::optional<clip_grid> grid) {
    auto oa = a, ob = b;
    for (auto& p : oa) orient(p);
    for (auto& p : ob) orient(p);
    return polygon_boolean(op, to_rings(oa), fill_rule::nonzero, to_rings(ob), fill_rule::nonzero, grid);
}
}  // namespace detail::clip

/// a AND b.
[[nodiscard]] inline std::vector<polygon_with_holes> polygon_intersection(const std::vector<polygon_with_holes>& a,
                                                                          const std::vector<polygon_with_holes>& b,
                                                                          std::optional<clip_grid> grid = std::nullopt) {
    return detail::clip::binary(clip_op::intersection, a, b, grid);
}
/// a minus b.
[[nodiscard]] inline std::vector<polygon_with_holes> polygon_difference(const std::vector<polygon_with_holes>& a,
                                                                        const std::vector<polygon_with_holes>& b,
                                                                        std::optional<clip_grid> grid = std::nullopt) {
    return detail::clip::binary(clip_op::difference, a, b, grid);
}
/// Symmetric difference (a XOR b); its area measures how much two shapes differ.
[[nodiscard]] inline std::vector<polygon_with_holes> polygon_xor(const std::vector<polygon_with_holes>& a,
                                                                 const std::vector<polygon_with_holes>& b,
                                                                 std::optional<clip_grid> grid = std::nullopt) {
    return detail::clip::binary(clip_op::xor_, a, b, grid);
}

/// Outline of open polylines stroked with round caps and joins: the union of all discs of radius
/// `half_width` (mm) centred on the polylines (a filigree strip, an SVG stroke). Arcs are
/// flattened to `arc_tolerance` (mm, > 0). Throws invalid_input for a non-finite or non-positive
/// width or tolerance, or non-finite points.
[[nodiscard]] inline std::vector<polygon_with_holes> stroke_outline(const std::vector<std::vector<vec2>>& polylines,
                                                                    double half_width, double arc_tolerance = 0.01) {
    if (!(std::isfinite(half_width) && half_width > 0)) throw invalid_input("stroke_outline: half width must be finite and > 0");
    if (!(std::isfinite(arc_tolerance) && arc_tolerance > 0))
        throw invalid_input("stroke_outline: arc tolerance must be finite and > 0");
    box2 b;
    for (const auto& line : polylines)
        for (const vec2& p : line) {
            if (!all_finite(p)) throw invalid_input("stroke_outline: a polyline point is not finite");
            b.extend(p);
        }
    if (b.empty()) return {};
    const clip_grid grid = clip_grid::for_bounds(box2(b.lo - vec2(2 * half_width), b.hi + vec2(2 * half_width)));
    ClipperLib::ClipperOffset offset(2.0, arc_tolerance * grid.scale);
    for (const auto& line : polylines) {
        ClipperLib::Path path;
        for (const vec2& p : line) path.push_back(grid.to_int(p));
        offset.AddPath(path, ClipperLib::jtRound, ClipperLib::etOpenRound);
    }
    ClipperLib::PolyTree tree;
    offset.Execute(tree, half_width * grid.scale);
    std::vector<polygon_with_holes> out;
    for (const ClipperLib::PolyNode* outer : tree.Childs) detail::clip::collect(*outer, grid, out);
    return out;
}

/// Drops every vertex closer than `spacing` to the previous kept vertex of its ring, then unites
/// again (a merge may touch a neighbour in a narrow gap). Removes the tiny edges Clipper leaves
/// where two arcs cross next to a vertex, and the notches of one grid unit a boolean can leave, which
/// stop an ear clipper; each merge moves the outline by < spacing. Rings of area <= spacing^2 go.
[[nodiscard]] inline std::vector<polygon_with_holes> merge_close_vertices(const std::vector<polygon_with_holes>& polys, double spacing,
                                                                        std::optional<clip_grid> grid = std::nullopt) {
    std::vector<ring2> rings;
    for (const ring2& r : to_rings(polys)) {
        ring2 kept;
        for (const vec2& p : r)
            if (kept.empty() || glm::distance(p, kept.back()) >= spacing) kept.push_back(p);
        while (kept.size() > 1 && glm::distance(kept.back(), kept.front()) < spacing) kept.pop_back();
        if (kept.size() >= 3 && std::abs(signed_area(kept)) > spacing * spacing) rings.push_back(std::move(kept));
    }
    if (rings.empty()) return {};
    return polygon_union(rings, fill_rule::nonzero, grid);
}


/// `polys` grown (delta > 0) or shrunk (delta < 0) by |delta| mm with round joins (Clipper's
/// closed-polygon offset), arcs flattened to `arc_tolerance` (mm, > 0). Shrinking then growing by
/// the same amount (an opening) removes necks narrower than 2 |delta| and point contacts between
/// rings, where a printed piece would hinge. Throws invalid_input for non-finite values or a
/// non-positive tolerance.
[[nodiscard]] inline std::vector<polygon_with_holes> polygon_offset(const std::vector<polygon_with_holes>& polys, double delta,
                                                                    double arc_tolerance = 0.01) {
    if (!std::isfinite(delta)) throw invalid_input("polygon_offset: delta must be finite");
    if (!(std::isfinite(arc_tolerance) && arc_tolerance > 0)) throw invalid_input("polygon_offset: arc tolerance must be finite and > 0");
    auto oriented = polys;
    for (auto& p : oriented) orient(p);
    const std::vector<ring2> rings = to_rings(oriented);
    const box2 b = detail::clip::bounds_of(rings, "polygon_offset");
    if (b.empty()) return {};
    const double pad = 2 * std::abs(delta) + arc_tolerance;
    const clip_grid grid = clip_grid::for_bounds(box2(b.lo - vec2(pad), b.hi + vec2(pad)));
    ClipperLib::ClipperOffset offset(2.0, arc_tolerance * grid.scale);
    offset.AddPaths(detail::clip::to_paths(rings, grid), ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    ClipperLib::Paths grown;
    offset.Execute(grown, delta * grid.scale);
    // The offset's rings may touch at vertices: a strictly simple union splits them, as every
    // boolean here does.
    ClipperLib::Clipper c;
    c.StrictlySimple(true);
    c.AddPaths(grown, ClipperLib::ptSubject, true);
    ClipperLib::PolyTree tree;
    if (!c.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero)) throw solver_error("polygon_offset: Clipper failed");
    std::vector<polygon_with_holes> out;
    for (const ClipperLib::PolyNode* outer : tree.Childs) detail::clip::collect(*outer, grid, out);
    return out;
}

/// The part of `polys` with x0 <= x <= x1 (x0, x1 rounded to the grid; the strip reaches past the
/// shape in y). Throws invalid_input unless x0 < x1 are finite.
[[nodiscard]] inline std::vector<polygon_with_holes> clip_strip(const std::vector<polygon_with_holes>& polys, double x0,
                                                                double x1, std::optional<clip_grid> grid = std::nullopt) {
    if (!(std::isfinite(x0) && std::isfinite(x1) && x0 < x1))
        throw invalid_input("clip strip: need finite x0 < x1, got [" + std::to_string(x0) + ", " + std::to_string(x1) + "]");
    const box2 b = bounding_box(polys);
    if (b.empty()) return {};
    const double margin = std::max(1.0, b.size().y);
    box2 all = b;
    all.extend(vec2(x0, b.lo.y - margin)).extend(vec2(x1, b.hi.y + margin));
    const clip_grid g = grid ? *grid : clip_grid::for_bounds(all);
    const polygon_with_holes rect{{{x0, b.lo.y - margin}, {x1, b.lo.y - margin}, {x1, b.hi.y + margin}, {x0, b.hi.y + margin}}, {}};
    return polygon_intersection(polys, {rect}, g);
}

}  // namespace fabsynth
