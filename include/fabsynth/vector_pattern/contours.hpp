// SPDX-License-Identifier: MIT
#pragma once
/// @file contours.hpp  Final contours of a synthesized band and their topology (Zhou et al. 2014, §4.3).
///
/// merge_contours() merges the stitched piece boundaries into closed contours: the rings of all
/// pieces (outer rings positive, holes negative, nonzero fill) are united by Clipper and clipped to
/// the band's u range [0, L] in one boolean, on one integer grid. Neighbouring pieces share their
/// portal segments exactly (stitching gives both sides the same endpoints), so the union joins them
/// along those segments. The result is oriented as vector_pattern::exemplar (outer rings positive area,
/// holes negative; the paper's "outer clockwise" is the same thing seen in a y-down frame), rings
/// are simple unless they touch themselves at a vertex (see below), islands inside holes are separate polygons. Vertices on the clipping line
/// u = L are put back on L exactly (the grid may not hold L itself).
///
/// band_topology() counts components and holes of the polygons. On a closed band the two ends are
/// glued: the cuts at u = 0 and u = L must be identical (same v intervals, else solver_error), every
/// pair of matching cut segments glues the polygon at u = L to the polygon at u = 0, and a union-find
/// with winding potentials (core/union_find.hpp) tells components that wind around the
/// loop (rings). holes = holes of the polygons + glues closing a cycle - rings, the convention of
/// topology::close_loop (the region a ring surrounds is not a hole of the band).
///
/// Usage:
///   auto polys = fabsynth::vector_pattern::merge_contours(rings, L, grid);
///   auto t = fabsynth::vector_pattern::band_topology(polys, L, /*closed=*/true);   // t.components, t.holes
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/vector_pattern/pieces.hpp"
#include "fabsynth/core/union_find.hpp"

namespace fabsynth::vector_pattern {

namespace detail {
/// Splits a closed ring at every vertex it visits twice into loops that visit no vertex twice.
inline std::vector<ring2> split_at_repeated_vertices(const ring2& r) {
    std::vector<ring2> out;
    std::vector<vec2> stack;
    auto less = [](vec2 a, vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); };
    std::vector<std::pair<vec2, std::size_t>> where;  // point -> position in stack, kept sorted
    auto find = [&](vec2 p) {
        auto it = std::lower_bound(where.begin(), where.end(), p, [&](const auto& e, vec2 q) { return less(e.first, q); });
        return it != where.end() && it->first == p ? it : where.end();
    };
    for (const vec2& p : r) {
        auto it = find(p);
        if (it == where.end()) {
            auto pos = std::lower_bound(where.begin(), where.end(), p, [&](const auto& e, vec2 q) { return less(e.first, q); });
            where.insert(pos, {p, stack.size()});
            stack.push_back(p);
            continue;
        }
        // p closes the loop stack[it->second .. end]; keep p on the stack as the loop's junction.
        const std::size_t from = it->second;
        ring2 loop(stack.begin() + static_cast<std::ptrdiff_t>(from), stack.end());
        for (std::size_t k = from + 1; k < stack.size(); ++k) {
            auto e = find(stack[k]);
            if (e != where.end()) where.erase(e);
        }
        stack.resize(from + 1);
        if (loop.size() >= 3) out.push_back(std::move(loop));
    }
    if (stack.size() >= 3) out.push_back(std::move(stack));
    return out;
}
}  // namespace detail

/// Union of the rings (nonzero fill) clipped to 0 <= u <= length, on `grid` (0 and length should be
/// given exactly). Rings come piece by piece along the band: `piece` (optional, one id per ring)
/// names the piece of each ring; without it each hole (negative area) must follow the outline it
/// lies in. Throws invalid_input for non-finite input or a `piece` of the wrong size.
[[nodiscard]] inline std::vector<polygon_with_holes> merge_contours(const std::vector<ring2>& rings, double length,
                                                                    const clip_grid& grid, const std::vector<std::size_t>* piece = nullptr) {
    if (!(std::isfinite(length) && length > 0.0)) throw invalid_input("merge_contours: length must be finite and > 0");
    if (piece && piece->size() != rings.size()) throw invalid_input("merge_contours: piece needs one id per ring");
    box2 b;
    for (const ring2& r : rings)
        for (const vec2& p : r) b.extend(p);
    if (b.empty()) return {};
    const double m = std::max(1.0, b.size().y);
    const ring2 strip{{0.0, b.lo.y - m}, {length, b.lo.y - m}, {length, b.hi.y + m}, {0.0, b.hi.y + m}};
    // Pieces share every portal segment, and Clipper's strictly-simple pass is very slow (quadratic
    // in practice) on such coincident edges: it is off, and a ring that touches itself at a vertex
    // (e.g. a hole touching the outer boundary at one point, as in hearts.svg) is split there into
    // simple loops, which are regrouped into polygons with holes by nesting.
    // One boolean of every ring is quadratic in the band's length: Clipper 6 fixes up the nesting
    // of its output rings after each join of coincident edges by visiting every output ring
    // (JoinCommonEdges -> FixupFirstLefts2), and a band of n pieces has O(n) of both (a Greek key of
    // 300 band heights: 52 s, of 400: 4x that). The rings are united instead in a balanced tree of
    // runs along x, so that each union joins only the seams between its two halves; the last step
    // is the clip to the strip. The region is the same (booleans are exact on the grid up to the
    // rounding of created intersections); O(n log n) joins. Pieces follow one another along the
    // band, so consecutive runs of rings are runs along x.
    // Leaves are runs of consecutive rings cut only between pieces (at a change of `piece`, or
    // without it before a ring of positive area), so a hole stays with its outline.
    constexpr std::size_t run = 32;  // rings per leaf union
    std::vector<std::vector<ring2>> level(1);
    for (std::size_t i = 0; i < rings.size(); ++i) {
        const bool boundary = i > 0 && (piece ? (*piece)[i] != (*piece)[i - 1] : signed_area(rings[i]) > 0.0);
        if (boundary && level.back().size() >= run) level.emplace_back();
        level.back().push_back(rings[i]);
    }
    while (level.size() > 2) {
        std::vector<std::vector<ring2>> next;
        for (std::size_t i = 0; i < level.size(); i += 2) {
            std::vector<ring2> both = std::move(level[i]);
            if (i + 1 < level.size()) both.insert(both.end(), level[i + 1].begin(), level[i + 1].end());
            next.push_back(to_rings(polygon_boolean(clip_op::union_, both, fill_rule::nonzero, {}, fill_rule::nonzero, grid, false)));
        }
        level = std::move(next);
    }
    std::vector<ring2> all = std::move(level[0]);
    if (level.size() > 1) all.insert(all.end(), level[1].begin(), level[1].end());
    const std::vector<polygon_with_holes> merged =
        polygon_boolean(clip_op::intersection, all, fill_rule::nonzero, {strip}, fill_rule::nonzero, grid, false);
    bool pinched = false;
    std::vector<ring2> loops;
    for (const ring2& r : to_rings(merged)) {
        std::vector<ring2> parts = detail::split_at_repeated_vertices(r);
        pinched = pinched || parts.size() != 1;
        for (ring2& q : parts) loops.push_back(std::move(q));
    }
    std::vector<polygon_with_holes> out = pinched ? group_rings(loops) : merged;
    const double snapped_end = grid.snap(length);
    auto fix = [&](ring2& r) {
        for (vec2& p : r)
            if (p.x == snapped_end) p.x = length;
    };
    for (polygon_with_holes& p : out) {
        fix(p.outer);
        for (ring2& h : p.holes) fix(h);
    }
    return out;
}

/// Topology of a band pattern (see the file comment).
struct band_counts {
    std::uint32_t components = 0;
    std::uint32_t holes = 0;
    std::uint32_t rings = 0;  ///< closed bands: components winding around the loop
};

/// Counts of `polys` (open band: as they are; closed band: glued at u = 0 and u = length).
/// Throws solver_error if a closed band's two cuts differ.
[[nodiscard]] inline band_counts band_topology(const std::vector<polygon_with_holes>& polys, double length, bool closed) {
    band_counts c;
    std::uint64_t holes = 0;
    for (const polygon_with_holes& p : polys) holes += p.holes.size();
    if (!closed) {
        c.components = static_cast<std::uint32_t>(polys.size());
        c.holes = static_cast<std::uint32_t>(holes);
        return c;
    }
    const std::vector<portal> at0 = detail::side_portals(polys, 0.0), atL = detail::side_portals(polys, length);
    if (at0.size() != atL.size())
        throw solver_error("band topology: the closed pattern is cut in " + std::to_string(at0.size()) + " segments at u = 0 but " +
                           std::to_string(atL.size()) + " at u = L");
    potential_union_find uf(polys.size());
    std::uint64_t self_glues = 0;
    for (std::size_t k = 0; k < at0.size(); ++k) {
        if (at0[k].top != atL[k].top || at0[k].bottom != atL[k].bottom)
            throw solver_error("band topology: the cuts of the closed pattern at u = 0 and u = L differ (segment " +
                               std::to_string(k) + ")");
        if (uf.link(atL[k].component, at0[k].component, 1)) ++self_glues;
    }
    std::uint64_t roots = 0, rings = 0;
    for (std::uint32_t x = 0; x < polys.size(); ++x)
        if (uf.find(x) == x) ++roots, rings += uf.winds(x) ? 1 : 0;
    c.components = static_cast<std::uint32_t>(roots);
    c.rings = static_cast<std::uint32_t>(rings);
    c.holes = static_cast<std::uint32_t>(holes + self_glues - rings);
    return c;
}

}  // namespace fabsynth::vector_pattern
