// SPDX-License-Identifier: MIT
#pragma once
/// @file reconstruct.hpp  From filigree skeletons to solid outlines, printable slabs and quality
/// triangle meshes for shell analysis (filigree-synthesis.md §6 "Reconstruction", whose baked
/// mesh M_b "serves as both the input of stress analysis and the base mesh for generating a
/// printable mesh", §5).
///
/// strip_outline: the contours C of §6.1. A skeleton edge (u, v) with full widths w_u, w_v (mm)
/// becomes the union of the discs of radius w/2 centred along it: the convex hull of its two end
/// discs (round caps and joins). All strips are united by Clipper (geometry/clip.hpp); a skeleton
/// whose live edges all have one width is stroked by stroke_outline along its branches. Arcs are
/// flattened with vertices on the circles (chord error <= arc_tolerance), so areas fall short of the
/// exact discs' by at most perimeter * arc_tolerance. Outline vertices closer than arc_tolerance
/// are merged (Clipper leaves edges of any length down to its grid where two arcs cross next to a
/// vertex; such edges would force needless tiny elements on the FEM mesh).
///
/// printable_extrusion: §6.2 for a flat piece of constant thickness tau. For a planar M_b the
/// volume of eq. (6)-(7) with the normal offset (both sides, tau / 2 each) is the straight prism of
/// the outline, so the Poisson reconstruction the paper needs for curved bases is replaced by
/// the exact prism: ear clipping (geometry/triangulate.hpp) and extrude() (geometry/extrude.hpp),
/// watertight, z in [0, tau].
///
/// make_fem_triangulation: ear clipping gives the slivers that make shell stresses meaningless,
/// so the FEM mesh is a constrained Delaunay triangulation (CDT) refined after Ruppert
/// (J. Ruppert, "A Delaunay refinement algorithm for quality 2-dimensional mesh generation",
/// J. Algorithms 18, 1995; in the form of J. R. Shewchuk, "Delaunay refinement algorithms for
/// triangular mesh generation", CGTA 22, 2002). Phases, each a function of detail::cdt:
///   1. resample: every outline edge is split into equal pieces of length <= h;
///   2. the resampled polygons are ear-clipped, vertices at the same position merged, and Lawson
///      flips of every non-locally-Delaunay interior edge turn the triangulation into the CDT of
///      the outline (the flip algorithm reaches the CDT from any triangulation of the domain);
///   3. points of a triangular lattice of spacing h that lie at least clearance * h inside the
///      outline (outline minus the stroke of its boundary, Clipper) are inserted, each followed by
///      Lawson flips (incremental CDT insertion);
///   4. refinement: a boundary segment whose diametral circle holds the apex of its triangle is
///      split at its midpoint; a triangle with an angle below min_angle_deg or a circumradius above
///      h gets its circumcentre, unless that point encroaches boundary segments (or lies behind
///      one), which are then split instead.
/// Guarantees: the result is a conforming triangulation of exactly the outline (every vertex of
/// the outline kept, added boundary vertices on outline edges, so the area is the outline's up to
/// rounding; every interior edge in two triangles, boundary edges in one, triangles
/// counter-clockwise with positive area). Refinement stops only when no triangle is left to
/// treat, so on return every triangle has all angles >= min_angle_deg and circumradius <= h,
/// except (a) triangles with an edge shorter than min_edge_length (features of the outline finer
/// than that, e.g. tiny edges where Clipper cut two arcs), left alone, (b) all that remain when the
/// vertex budget runs out (budget_exhausted), and (c) triangles whose circumcentre cannot be placed
/// (a walk that fails, a point on a vertex: numerical corner cases); below_target counts the angle
/// violations left. Ruppert's proof of termination holds for min_angle_deg <= 20.7 degrees on
/// outlines without corners sharper than 60 degrees; a union of round strips has only reflex
/// corners (where strips meet) and nearly flat ones (flattened arcs); a domain clip may add sharp
/// ones, which (a) and the budget cover. Predicates are plain double arithmetic; a flip needs an
/// incircle violation well above rounding, so every flip is genuine and flips cannot cycle.
///
/// Usage:
///   auto outline = fabsynth::filigree::strip_outline(std::span(&skeleton, 1), 0.01);
///   fabsynth::triangle_mesh slab = fabsynth::filigree::printable_extrusion(outline, 1.5);   // STL-ready
///   auto tri = fabsynth::filigree::make_fem_triangulation(outline, 0.5);                    // h = 0.5 mm
///   // tri.mesh: vertices + counter-clockwise triangles; tri.min_angle_deg, tri.below_target
///
/// Errors: invalid_input for an empty outline, non-finite coordinates, widths, tolerances, h or
/// thickness out of range; solver_error if the outline cannot be triangulated (rings crossing).
/// Everything is serial and deterministic.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <unordered_map>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/cdt.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/extrude.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/raster.hpp"
#include "fabsynth/geometry/triangulate.hpp"
#include "fabsynth/graph/skeleton_graph.hpp"

namespace fabsynth::filigree {

namespace detail::strips {

/// Number of chords for a full circle of radius r with chord error <= tol (at least 8).
inline std::size_t circle_segments(double r, double tol) {
    if (!(r > tol)) return 8;
    const double step = 2.0 * std::acos(1.0 - tol / r);  // chord whose sagitta is tol
    return std::max<std::size_t>(8, static_cast<std::size_t>(std::ceil(2.0 * std::numbers::pi / step)));
}

/// Appends the points of the arc of circle (c, r) from angle a0 to a1 > a0 (both ends included).
inline void append_arc(ring2& out, vec2 c, double r, double a0, double a1, double tol) {
    if (r == 0.0) {
        out.push_back(c);
        return;
    }
    const double full = 2.0 * std::numbers::pi;
    const auto n = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil((a1 - a0) / full * static_cast<double>(circle_segments(r, tol)))));
    for (std::size_t k = 0; k <= n; ++k) {
        const double a = a0 + (a1 - a0) * static_cast<double>(k) / static_cast<double>(n);
        out.push_back(c + r * vec2(std::cos(a), std::sin(a)));
    }
}

/// Counter-clockwise ring of the convex hull of the discs (c1, r1) and (c2, r2) (r >= 0, not both
/// 0). One disc inside the other gives that disc. Tangent normals n satisfy n . u = (r1 - r2) / d.
inline ring2 disc_hull(vec2 c1, double r1, vec2 c2, double r2, double tol) {
    const double d = glm::length(c2 - c1);
    ring2 out;
    if (d <= std::abs(r1 - r2)) {
        const vec2 c = r1 >= r2 ? c1 : c2;
        const double r = std::max(r1, r2);
        const std::size_t n = circle_segments(r, tol);
        for (std::size_t k = 0; k < n; ++k) {
            const double a = 2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n);
            out.push_back(c + r * vec2(std::cos(a), std::sin(a)));
        }
        return out;
    }
    const double theta = std::atan2(c2.y - c1.y, c2.x - c1.x);
    const double gamma = std::acos(std::clamp((r1 - r2) / d, -1.0, 1.0));
    append_arc(out, c1, r1, theta + gamma, theta + 2.0 * std::numbers::pi - gamma, tol);  // back of disc 1
    append_arc(out, c2, r2, theta - gamma, theta + gamma, tol);                            // front of disc 2
    return out;
}

/// Rings of one skeleton's strips (stroke_outline when every live edge has one width).
inline std::vector<ring2> skeleton_rings(const graph::skeleton_graph<vec2>& s, double tol) {
    std::vector<ring2> rings;
    double common = -1.0;
    bool uniform = true;
    for (graph::edge_id e = 0; e < s.edge_slots(); ++e) {
        if (!s.edge_alive(e)) continue;
        const auto [u, v] = s.endpoints(e);
        for (const double w : {s.width(u), s.width(v)}) {
            if (common < 0.0) common = w;
            uniform = uniform && w == common;
        }
    }
    if (common < 0.0) return rings;  // no live edge
    if (uniform) {
        if (common == 0.0) return rings;
        std::vector<std::vector<vec2>> lines;
        for (const graph::skeleton_branch& b : s.branches()) {
            std::vector<vec2> line;
            for (const graph::vertex_id v : b.vertices) line.push_back(s.position(v));
            lines.push_back(std::move(line));
        }
        return to_rings(stroke_outline(lines, 0.5 * common, tol));
    }
    for (graph::edge_id e = 0; e < s.edge_slots(); ++e) {
        if (!s.edge_alive(e)) continue;
        const auto [u, v] = s.endpoints(e);
        if (s.width(u) == 0.0 && s.width(v) == 0.0) continue;
        rings.push_back(disc_hull(s.position(u), 0.5 * s.width(u), s.position(v), 0.5 * s.width(v), tol));
    }
    return rings;
}

}  // namespace detail::strips

namespace detail {

/// The region of `polys` as simple, non-overlapping polygons (Clipper union; unchanged for
/// strip_outline's output), so that the ear clipper's input requirements hold. Throws
/// invalid_input for non-finite points or an empty region.
inline std::vector<polygon_with_holes> normalized_outline(const std::vector<polygon_with_holes>& polys, const char* what) {
    for (const ring2& r : to_rings(polys))
        for (const vec2& p : r)
            if (!all_finite(p)) throw invalid_input(std::string(what) + ": the outline has a non-finite point");
    std::vector<polygon_with_holes> out = polygon_union(polys, std::vector<polygon_with_holes>{});
    if (!(area(out) > 0.0)) throw invalid_input(std::string(what) + ": the outline has zero area");
    return out;
}

}  // namespace detail

/// The filled contours of §6.1: the union of every live edge's strip (the discs of radius w/2
/// along it, w the full width at its endpoints, mm) over all skeletons, as simple polygons with
/// holes (outer rings counter-clockwise). Edges whose two widths are 0 add nothing.
/// @param skeletons      2D skeleton graphs (positions and widths in mm)
/// @param arc_tolerance  max chord error of the flattened arcs (mm), finite and > 0
/// Throws invalid_input for a tolerance out of range. Empty if no edge has a width.
[[nodiscard]] inline std::vector<polygon_with_holes> strip_outline(std::span<const graph::skeleton_graph<vec2>> skeletons,
                                                                   double arc_tolerance = 0.01) {
    require_positive(arc_tolerance, "strip_outline: arc tolerance");
    std::vector<ring2> rings;
    for (const auto& s : skeletons) {
        std::vector<ring2> r = detail::strips::skeleton_rings(s, arc_tolerance);
        rings.insert(rings.end(), std::make_move_iterator(r.begin()), std::make_move_iterator(r.end()));
    }
    if (rings.empty()) return {};
    // stroke_outline's holes are clockwise and hulls counter-clockwise: the nonzero fill is the union
    return merge_close_vertices(polygon_union(rings, fill_rule::nonzero), arc_tolerance);
}

/// strip_outline(skeletons, arc_tolerance) intersected with `domain` (polygons with holes, mm;
/// e.g. the piece's boundary, §6.1's boolean with the base mesh).
[[nodiscard]] inline std::vector<polygon_with_holes> strip_outline(std::span<const graph::skeleton_graph<vec2>> skeletons,
                                                                   const std::vector<polygon_with_holes>& domain,
                                                                   double arc_tolerance = 0.01) {
    const std::vector<polygon_with_holes> strips = strip_outline(skeletons, arc_tolerance);
    if (strips.empty() || domain.empty()) return {};
    return merge_close_vertices(polygon_intersection(strips, domain), arc_tolerance);
}

/// The outline with every solid corner sharper than `max_angle` (radians) cut off where its tip
/// reaches `width` (mm): the two sides are followed from the corner by equal arc lengths until
/// their points are `width` apart (at most 8 * width along each side), and the tip beyond that
/// chord is removed. A cut whose chord would meet another edge is not made. Such corners come from
/// a strip that meets the domain's boundary or another strip's side at a grazing angle; a
/// triangulation cannot give them good triangles, and Ruppert's refinement (make_fem_triangulation)
/// splits toward their apex down to its shortest edge, leaving triangles of 1e-6 mm^2 whose
/// drilling stiffness makes the shell system singular. The tip removed is a wedge narrower than
/// `width`, which does not print as a strip either. Rings come back oriented (outer
/// counter-clockwise) and united.
[[nodiscard]] inline std::vector<polygon_with_holes> blunt_sharp_corners(std::vector<polygon_with_holes> polys, double max_angle, double width) {
    require_positive(width, "blunt_sharp_corners: width (mm)");
    if (!(std::isfinite(max_angle) && max_angle > 0 && max_angle < std::numbers::pi))
        throw invalid_input("blunt_sharp_corners: the angle must lie in (0, pi) radians");
    for (polygon_with_holes& p : polys) orient(p);  // solid on the left of every ring
    const std::vector<ring2> rings = to_rings(polys);
    const double cos_max = std::cos(max_angle);
    auto crosses_any = [&](vec2 a, vec2 b, std::size_t ring, std::size_t from, std::size_t to) {
        // does chord a-b meet an edge other than ring `ring`'s edges from..to (cyclic, the cut sides)?
        for (std::size_t r = 0; r < rings.size(); ++r)
            for (std::size_t i = 0, n = rings[r].size(); i < n; ++i) {
                if (r == ring && ((from <= to && i >= from && i < to) || (from > to && (i >= from || i < to)))) continue;
                if (fabsynth::detail::segments_intersect(a, b, rings[r][i], rings[r][(i + 1) % n])) return true;
            }
        return false;
    };
    std::vector<ring2> out;
    for (std::size_t r = 0; r < rings.size(); ++r) {
        const ring2& R = rings[r];
        const std::size_t n = R.size();
        std::vector<char> removed(n, 0);
        std::vector<std::pair<std::size_t, vec2>> insert_after;  // new points after vertex index
        for (std::size_t b = 0; b < n && n >= 3; ++b) {
            if (removed[b]) continue;
            const vec2 pa = R[(b + n - 1) % n], pb = R[b], pc = R[(b + 1) % n];
            const vec2 u = pa - pb, v = pc - pb;
            const double lu = glm::length(u), lv = glm::length(v);
            if (!(lu > 0 && lv > 0) || orient2d(pa, pb, pc) <= 0) continue;  // reflex or flat: no solid tip
            if (glm::dot(u, v) / (lu * lv) <= cos_max) continue;             // not sharper than max_angle
            // walk both sides by equal arc lengths s until the points are `width` apart
            auto point_at = [&](double s, int dir, std::size_t& last) {  // last: index of the last vertex passed
                std::size_t i = b;
                for (std::size_t k = 0; k < std::max<std::size_t>(1, n / 2); ++k) {
                    const std::size_t j = dir > 0 ? (i + 1) % n : (i + n - 1) % n;
                    const double l = glm::distance(R[i], R[j]);
                    if (s <= l) {
                        last = i;
                        return R[i] + (R[j] - R[i]) * (l > 0 ? s / l : 0.0);
                    }
                    s -= l, i = j;
                }
                last = n;  // ran out of ring
                return vec2(0);
            };
            const double step = 0.125 * width;
            for (double s = step; s <= 8 * width; s += step) {
                std::size_t lb = 0, lf = 0;
                const vec2 P = point_at(s, -1, lb), Q = point_at(s, +1, lf);
                if (lb == n || lf == n) break;
                if (glm::distance(P, Q) < width) continue;
                // the vertices strictly between P (after lb going back) and Q: lb is the last vertex
                // passed going backwards, so the removed run is lb .. b .. lf (cyclic)
                bool clash = false;
                for (std::size_t i = lb;; i = (i + 1) % n) {
                    if (removed[i]) clash = true;
                    if (i == lf) break;
                }
                // the chord must not meet the ring's other edges or other rings
                const std::size_t first_edge = (lb + n - 1) % n, end_edge = (lf + 1) % n;
                if (clash || crosses_any(P, Q, r, first_edge, end_edge)) break;
                for (std::size_t i = lb;; i = (i + 1) % n) {
                    removed[i] = 1;
                    if (i == lf) break;
                }
                insert_after.push_back({lb, P});
                insert_after.push_back({lb, Q});
                break;
            }
        }
        ring2 kept;
        std::size_t next_insert = 0;
        std::sort(insert_after.begin(), insert_after.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        for (std::size_t i = 0; i < n; ++i) {
            if (!removed[i]) kept.push_back(R[i]);
            while (next_insert < insert_after.size() && insert_after[next_insert].first == i) kept.push_back(insert_after[next_insert++].second);
        }
        if (kept.size() >= 3) out.push_back(std::move(kept));
    }
    if (out.empty()) return {};
    return polygon_union(out, fill_rule::nonzero);
}

/// The outline with vertices closer than `spacing` (mm) merged, the polygons united again, and
/// its solid corners sharper than 60 degrees (below which Ruppert's refinement is not proven to
/// end) cut where they are `spacing` wide
/// (blunt_sharp_corners): the input of make_fem_triangulation, where outline features finer than
/// the mesh would only make slivers (a sliver's drilling stiffness vanishes with its area, so the
/// shell system turns singular).
[[nodiscard]] inline std::vector<polygon_with_holes> coarsened_outline(const std::vector<polygon_with_holes>& outline, double spacing) {
    require_positive(spacing, "coarsened_outline: spacing (mm)");
    return blunt_sharp_corners(merge_close_vertices(outline, spacing), std::numbers::pi / 3, spacing);
}

/// The outline with its pinches bridged: wherever two boundary vertices that are not neighbours
/// on one ring come closer than `gap` (mm), a disc of radius `bridge` (mm, > gap) is united into the
/// solid there, so the piece has no point contact (it would print as a hinge, and a watertight
/// extrusion would need a non-manifold edge there once rounded to the single precision of STL).
/// Repeated until no pinch is left (at most 4 passes). Vertices are bucketed in a grid of cell
/// `gap`: O(n) for n outline vertices.
[[nodiscard]] inline std::vector<polygon_with_holes> bridge_pinches(std::vector<polygon_with_holes> outline, double gap, double bridge) {
    require_positive(gap, "bridge_pinches: gap (mm)");
    if (!(bridge > gap)) throw invalid_input("bridge_pinches: the bridge radius must exceed the gap");
    for (int pass = 0; pass < 4; ++pass) {
        struct at {
            vec2 p;
            std::size_t ring, index, size;
        };
        std::vector<at> pts;
        const std::vector<ring2> rings = to_rings(outline);
        for (std::size_t r = 0; r < rings.size(); ++r)
            for (std::size_t i = 0; i < rings[r].size(); ++i) pts.push_back({rings[r][i], r, i, rings[r].size()});
        std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells;
        auto cell = [gap](vec2 p, int dx, int dy) {
            const auto x = static_cast<std::int64_t>(std::floor(p.x / gap)) + dx, y = static_cast<std::int64_t>(std::floor(p.y / gap)) + dy;
            return (static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint64_t>(y & 0xffffffff);
        };
        for (std::size_t k = 0; k < pts.size(); ++k) cells[cell(pts[k].p, 0, 0)].push_back(k);
        std::vector<ring2> discs;
        for (std::size_t k = 0; k < pts.size(); ++k)
            for (int dx = -1; dx <= 1; ++dx)
                for (int dy = -1; dy <= 1; ++dy) {
                    const auto it = cells.find(cell(pts[k].p, dx, dy));
                    if (it == cells.end()) continue;
                    for (const std::size_t m : it->second) {
                        if (m <= k) continue;
                        const at &a = pts[k], &b = pts[m];
                        if (a.ring == b.ring) {
                            const std::size_t d = a.index > b.index ? a.index - b.index : b.index - a.index;
                            if (std::min(d, a.size - d) <= 2) continue;  // neighbours along the ring
                        }
                        if (glm::distance(a.p, b.p) >= gap) continue;
                        const vec2 c = 0.5 * (a.p + b.p);
                        ring2 disc;
                        for (int t = 0; t < 16; ++t)
                            disc.push_back(c + bridge * vec2(std::cos(t * std::numbers::pi / 8), std::sin(t * std::numbers::pi / 8)));
                        discs.push_back(std::move(disc));
                    }
                }
        if (discs.empty()) return outline;
        std::vector<polygon_with_holes> add;
        for (ring2& d : discs) add.push_back({std::move(d), {}});
        outline = polygon_union(outline, add);
    }
    return outline;
}

/// The printable slab of §6.2 for a flat piece: the outline (polygons with holes, mm; united by
/// Clipper first, so overlaps are allowed) ear-clipped and extruded between z = 0 and
/// z = thickness_mm. Watertight and outward oriented; volume = area(outline) * thickness. Throws
/// invalid_input for an empty or zero-area outline, or a thickness that is not finite and > 0.
[[nodiscard]] inline triangle_mesh printable_extrusion(const std::vector<polygon_with_holes>& outline, double thickness_mm) {
    if (outline.empty()) throw invalid_input("printable_extrusion: the outline is empty");
    require_positive(thickness_mm, "printable_extrusion: thickness (mm)");
    return extrude(triangulate(detail::normalized_outline(outline, "printable_extrusion")), thickness_mm);
}

/// Options of make_fem_triangulation (see the file comment for the method).
struct fem_mesh_options {
    double min_angle_deg = 20.0;   ///< refinement target, degrees, in (0, 30] (termination proven <= 20.7)
    double clearance = 0.5;        ///< lattice points keep clearance * h from the outline, in [0.25, 2]
    /// Triangles with a shorter edge are not refined (mm); 0 = h / 200. It bounds the smallest
    /// elements: the shell's drilling stiffness scales with element area (fem/shell3.hpp), so
    /// elements far smaller than the thickness leave near-zero pivots that fem reports as a mechanism.
    double min_edge_length = 0.0;
    std::size_t max_vertices = 0;  ///< vertex budget; 0 = 20 x (boundary + lattice points) + 10000
};

/// A quality triangulation of an outline for shell FEM.
struct fem_triangulation {
    planar_triangulation mesh;     ///< vertices (mm) and counter-clockwise triangles
    double edge_length = 0;        ///< the target h (mm)
    double min_angle_deg = 0;      ///< smallest angle of any triangle (degrees)
    std::size_t below_target = 0;  ///< triangles with an angle < min_angle_deg (small input features, budget)
    bool budget_exhausted = false; ///< refinement stopped at the vertex budget
};

namespace detail::cdt {

// the triangulation and its predicates live in geometry/cdt.hpp
using namespace ::fabsynth::detail::cdt;

/// Phase 1: each edge of every ring cut into ceil(length / h) equal pieces.
inline std::vector<polygon_with_holes> resample(const std::vector<polygon_with_holes>& outline, double h) {
    auto ring = [h](const ring2& r) {
        ring2 out;
        for (std::size_t i = 0; i < r.size(); ++i) {
            const vec2 a = r[i], b = r[(i + 1) % r.size()];
            const auto n = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(glm::length(b - a) / h)));
            for (std::size_t k = 0; k < n; ++k) out.push_back(k == 0 ? a : a + (b - a) * (static_cast<double>(k) / static_cast<double>(n)));
        }
        return out;
    };
    std::vector<polygon_with_holes> out;
    for (const polygon_with_holes& p : outline) {
        polygon_with_holes q{ring(p.outer), {}};
        for (const ring2& hole : p.holes) q.holes.push_back(ring(hole));
        orient(q);
        out.push_back(std::move(q));
    }
    return out;
}

/// Phase 3's points: a triangular lattice of spacing h (rows h sqrt(3)/2 apart, odd rows shifted by
/// h/2) restricted to the outline minus the stroke of its boundary of half width clearance * h.
inline std::vector<vec2> lattice_points(const std::vector<polygon_with_holes>& outline, double h, double clearance) {
    std::vector<std::vector<vec2>> boundary;
    for (const ring2& r : to_rings(outline)) {
        std::vector<vec2> line(r.begin(), r.end());
        line.push_back(r.front());
        boundary.push_back(std::move(line));
    }
    const std::vector<polygon_with_holes> inner = polygon_difference(outline, stroke_outline(boundary, clearance * h, 0.01 * h));
    const box2 b = bounding_box(inner);
    std::vector<vec2> pts;
    if (b.empty()) return pts;
    polygon_rasterizer r;
    for (const polygon_with_holes& p : inner) r.add_polygon(p);
    std::vector<polygon_rasterizer::crossing> scratch;
    const double dy = h * std::sqrt(3.0) / 2.0;
    for (std::size_t j = 0;; ++j) {
        const double y = b.lo.y + (static_cast<double>(j) + 0.5) * dy;
        if (y > b.hi.y) break;
        const double shift = (j % 2) ? 0.5 * h : 0.0;
        r.intervals(y, scratch, [&](double x0, double x1) {
            const double k0 = std::ceil((x0 - b.lo.x - shift) / h);
            for (double k = k0;; k += 1.0) {
                const double x = b.lo.x + shift + k * h;
                if (!(x < x1)) break;
                if (x > x0) pts.push_back({x, y});
            }
        });
    }
    return pts;
}

/// Phase 3: inserts the lattice points in row order, each located by a walk from the previous one.
inline void insert_lattice(triangulation& T, const std::vector<vec2>& points) {
    std::uint32_t hint = 0;
    for (const vec2& p : points) {
        if (T.tris.empty()) return;
        location at = T.walk(std::min<std::uint32_t>(hint, static_cast<std::uint32_t>(T.tris.size() - 1)), p);
        std::uint32_t t = at.kind == location::inside ? at.tri : T.scan(p);
        if (t == none) continue;
        if (T.insert(t, p)) hint = static_cast<std::uint32_t>(T.tris.size() - 1);
    }
    T.touched.clear();
}

/// Phase 4: Ruppert's refinement (see the file comment): a queue of encroached outline segments,
/// served first, and a FIFO queue of bad triangles. Queue items name their vertices, so an item
/// whose segment or triangle has changed since is recognised as stale and dropped.
class refiner {
public:
    refiner(triangulation& T, double h, double min_angle, double min_edge)
        : T_(T), h_(h), sin_min_(std::sin(min_angle)), min_edge_(min_edge), vertex_tri_(T.pts.size(), none), fans_(T.pts.size(), 0) {
        for (std::uint32_t t = 0; t < T_.tris.size(); ++t)
            for (int i = 0; i < 3; ++i) {
                vertex_tri_[T_.tris[t].v[i]] = t;
                if (T_.tris[t].nbr[i] == none) {
                    std::uint8_t& f = fans_[T_.tris[t].v[next(i)]];
                    f = static_cast<std::uint8_t>(std::min(2, f + 1));
                }
            }
    }

    /// Refines until nothing is left to treat (true) or the vertex budget is reached (false).
    bool run(std::size_t max_vertices) {
        for (std::uint32_t t = 0; t < T_.tris.size(); ++t) examine(t);
        for (;;) {
            if (T_.pts.size() >= max_vertices) return false;
            if (!segments_.empty()) {
                split_next_segment();
                continue;
            }
            if (head_ == bad_.size()) return true;
            const triangle_item item = bad_[head_++];
            if (head_ > 4096 && 2 * head_ > bad_.size()) bad_.erase(bad_.begin(), bad_.begin() + static_cast<std::ptrdiff_t>(head_)), head_ = 0;
            if (item.t < T_.tris.size() && T_.tris[item.t].v == item.v && is_bad(item.t)) treat(item);
        }
    }

private:
    struct segment_item {
        std::uint32_t a, b;  // endpoints
        bool force;          // split without re-testing the apex (encroached by a circumcentre)
    };
    struct triangle_item {
        std::uint32_t t;
        std::array<std::uint32_t, 3> v;
    };

    /// An angle below the target or a circumradius above h, unless an edge is below min_edge.
    [[nodiscard]] bool is_bad(std::uint32_t t) const {
        const vec2 a = T_.P(t, 0), b = T_.P(t, 1), c = T_.P(t, 2);
        const double la = glm::length(c - b), lb = glm::length(a - c), lc = glm::length(b - a);
        const double shortest = std::min({la, lb, lc});
        if (shortest < min_edge_) return false;                  // a feature finer than the mesh: left alone
        const double R = la * lb * lc / (2.0 * orient2d(a, b, c));  // circumradius
        return R > h_ || shortest < 2.0 * R * sin_min_;            // shortest edge = 2 R sin(smallest angle)
    }
    /// The apex of t lies inside the diametral circle of its edge i.
    [[nodiscard]] bool encroached(std::uint32_t t, int i) const {
        const vec2 a = T_.P(t, next(i)), b = T_.P(t, prev(i)), c = T_.P(t, i);
        return glm::dot(a - c, b - c) < 0.0;
    }
    [[nodiscard]] bool splittable(std::uint32_t a, std::uint32_t b) const { return 0.5 * glm::length(T_.pts[a] - T_.pts[b]) >= min_edge_; }

    /// Queues t's encroached outline edges and t itself if it is bad.
    void examine(std::uint32_t t) {
        for (int i = 0; i < 3; ++i)
            if (T_.tris[t].nbr[i] == none && encroached(t, i)) {
                const std::uint32_t a = T_.tris[t].v[next(i)], b = T_.tris[t].v[prev(i)];
                if (splittable(a, b)) segments_.push_back({a, b, false});
            }
        if (is_bad(t)) bad_.push_back({t, T_.tris[t].v});
    }

    /// After an insertion: updates vertex_tri_ (exact, as every changed triangle is touched) and
    /// examines the changed triangles.
    void flush_touched(std::uint8_t fans_of_new_vertex) {
        fans_.push_back(fans_of_new_vertex);
        std::vector<std::uint32_t> list;
        list.swap(T_.touched);
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        vertex_tri_.resize(T_.pts.size(), none);
        for (std::uint32_t t : list)
            for (std::uint32_t v : T_.tris[t].v) vertex_tri_[v] = t;
        for (std::uint32_t t : list) examine(t);
    }

    /// The triangle holding outline segment a -> b and its edge index: turn around a to the outline
    /// edge leaving it; a scan where two rings touch at a (two fans). False if there is none.
    bool find_segment(std::uint32_t a, std::uint32_t b, std::uint32_t& t, int& i) const {
        std::uint32_t k = vertex_tri_[a];
        for (std::size_t guard = 0; k != none && guard < T_.tris.size(); ++guard) {
            const int ia = T_.index_of(k, a);
            const std::uint32_t n = T_.tris[k].nbr[prev(ia)];  // across edge (a, v[next(ia)])
            if (n == none) {
                if (T_.tris[k].v[next(ia)] != b) break;
                t = k, i = prev(ia);
                return true;
            }
            k = n;
            if (k == vertex_tri_[a]) return false;  // a is interior
        }
        if (fans_[a] < 2) return false;
        for (k = 0; k < T_.tris.size(); ++k) {
            const int ia = T_.index_of(k, a);
            if (ia < 0 || T_.tris[k].v[next(ia)] != b || T_.tris[k].nbr[prev(ia)] != none) continue;
            t = k, i = prev(ia);
            return true;
        }
        return false;
    }

    void split_next_segment() {
        const segment_item s = segments_.back();
        segments_.pop_back();
        std::uint32_t t = none;
        int i = -1;
        if (!find_segment(s.a, s.b, t, i)) return;  // already split
        if (!s.force && !encroached(t, i)) return;
        T_.split_segment(t, i);
        flush_touched(1);
    }

    /// Queues the splittable outline edge i of t for a forced split; false if it is too short.
    bool defer_to(std::uint32_t t, int i) {
        const std::uint32_t a = T_.tris[t].v[next(i)], b = T_.tris[t].v[prev(i)];
        if (!splittable(a, b)) return false;
        segments_.push_back({a, b, true});
        return true;
    }

    /// A bad triangle: its circumcentre c is inserted unless c lies behind an outline segment or
    /// encroaches the outline edges of its cavity (the triangles whose circumcircle holds c: the
    /// segments c would be joined to); those are split first and the triangle is queued again.
    void treat(const triangle_item& item) {
        const vec2 c = circumcentre(T_.P(item.t, 0), T_.P(item.t, 1), T_.P(item.t, 2));
        const location at = T_.walk(item.t, c);
        if (at.kind == location::not_found) return;
        bool deferred = false;
        if (at.kind == location::behind_boundary) {
            deferred = defer_to(at.tri, at.edge);
            if (!deferred) return;
        } else {
            std::vector<std::uint32_t> cavity{at.tri}, stack{at.tri};
            while (!stack.empty()) {
                const std::uint32_t t = stack.back();
                stack.pop_back();
                for (int i = 0; i < 3; ++i) {
                    const std::uint32_t u = T_.tris[t].nbr[i];
                    if (u == none) {
                        if (glm::dot(T_.P(t, next(i)) - c, T_.P(t, prev(i)) - c) < 0.0) deferred = defer_to(t, i) || deferred;
                    } else if (std::find(cavity.begin(), cavity.end(), u) == cavity.end() &&
                               clearly_in_circle(T_.P(u, 0), T_.P(u, 1), T_.P(u, 2), c)) {
                        cavity.push_back(u);
                        stack.push_back(u);
                    }
                }
            }
        }
        if (deferred) {
            bad_.push_back(item);
            return;
        }
        if (T_.insert(at.tri, c)) flush_touched(0);
        else T_.touched.clear();
    }

    triangulation& T_;
    double h_, sin_min_, min_edge_;
    std::vector<std::uint32_t> vertex_tri_;  ///< vertex -> one triangle holding it
    std::vector<std::uint8_t> fans_;         ///< outline edges leaving a vertex (capped at 2: rings touch)
    std::vector<segment_item> segments_;     ///< LIFO
    std::vector<triangle_item> bad_;         ///< FIFO through head_
    std::size_t head_ = 0;
};

/// The output: the triangulation and its quality figures.
inline fem_triangulation result(triangulation&& T, double h, double min_angle_deg, bool finished) {
    fem_triangulation out;
    out.edge_length = h;
    out.budget_exhausted = !finished;
    out.mesh.vertices = std::move(T.pts);
    out.min_angle_deg = 180.0;
    const auto& V = out.mesh.vertices;
    for (const triangle& t : T.tris) {
        out.mesh.triangles.push_back(t.v);
        const double a = min_angle(V[t.v[0]], V[t.v[1]], V[t.v[2]]) * 180.0 / std::numbers::pi;
        out.min_angle_deg = std::min(out.min_angle_deg, a);
        if (a < min_angle_deg) ++out.below_target;
    }
    return out;
}

}  // namespace detail::cdt

/// A quality triangulation of the outline (polygons with holes, mm; united by Clipper first, which
/// leaves strip_outline's output unchanged) with target edge length h (mm) for shell FEM: the
/// refined constrained Delaunay triangulation of the file comment, with its guarantees. Cost ~O(n log n) for n output vertices on typical outlines (walks of O(sqrt n)
/// steps), with O(n) scans where a walk is blocked by a hole.
/// Throws invalid_input for an empty outline (or one of zero area), non-finite points, or h / options
/// out of range; solver_error if the outline cannot be triangulated (crossing rings).
[[nodiscard]] inline fem_triangulation make_fem_triangulation(const std::vector<polygon_with_holes>& outline, double h,
                                                              const fem_mesh_options& opt = {}) {
    require_positive(h, "fem triangulation: edge length h (mm)");
    if (!(std::isfinite(opt.min_angle_deg) && opt.min_angle_deg > 0.0 && opt.min_angle_deg <= 30.0))
        throw invalid_input("fem triangulation: min_angle_deg must lie in (0, 30], got " + std::to_string(opt.min_angle_deg));
    if (!(std::isfinite(opt.clearance) && opt.clearance >= 0.25 && opt.clearance <= 2.0))
        throw invalid_input("fem triangulation: clearance must lie in [0.25, 2], got " + std::to_string(opt.clearance));
    if (!(std::isfinite(opt.min_edge_length) && opt.min_edge_length >= 0.0))
        throw invalid_input("fem triangulation: min_edge_length must be finite and >= 0");
    if (outline.empty()) throw invalid_input("fem triangulation: the outline is empty");
    const std::vector<polygon_with_holes> region = detail::normalized_outline(outline, "fem triangulation");

    const std::vector<polygon_with_holes> boundary = detail::cdt::resample(region, h);
    detail::cdt::triangulation T;
    T.adopt(triangulate(boundary));
    const std::vector<vec2> lattice = detail::cdt::lattice_points(region, h, opt.clearance);
    const std::size_t budget = opt.max_vertices ? opt.max_vertices : 20 * (T.pts.size() + lattice.size()) + 10000;
    detail::cdt::insert_lattice(T, lattice);
    const double min_edge = opt.min_edge_length > 0.0 ? opt.min_edge_length : 0.005 * h;
    const bool finished = detail::cdt::refiner(T, h, opt.min_angle_deg * std::numbers::pi / 180.0, min_edge).run(budget);

    return detail::cdt::result(std::move(T), h, opt.min_angle_deg, finished);
}

/// The shortest edge of a triangulation (mm; infinity if it has no triangle).
[[nodiscard]] inline double shortest_edge(const fem_triangulation& t) noexcept {
    double s = std::numeric_limits<double>::infinity();
    for (const auto& f : t.mesh.triangles)
        for (int i = 0; i < 3; ++i) s = std::min(s, glm::distance(t.mesh.vertices[f[i]], t.mesh.vertices[f[(i + 1) % 3]]));
    return s;
}

/// The shell-FEM triangulation of a printed piece (§5) with target edge h (mm):
/// make_fem_triangulation of coarsened_outline(outline, h / 4). Merging vertices moves the outline
/// by up to h / 4, which can leave a wall or a gap between two rings far thinner than the mesh;
/// refinement then goes down to h / 200 there, and triangles of 1e-6 mm^2 make the shell system
/// singular (their drilling stiffness scales with their area). Where the triangulation has an edge
/// shorter than h / 50, the coarsened outline is opened and closed by h / 8 (no wall or gap
/// thinner than h / 4 is left) and triangulated again; that result is taken when it has no more
/// pieces than `outline` (the merge may have cut a thin neck, which the closing restores) and
/// longer shortest edges.
[[nodiscard]] inline fem_triangulation piece_triangulation(const std::vector<polygon_with_holes>& outline, double h) {
    require_positive(h, "piece_triangulation: edge length h (mm)");
    const std::vector<polygon_with_holes> coarse = coarsened_outline(outline, 0.25 * h);
    fem_triangulation tri = make_fem_triangulation(coarse, h);
    const double shortest = shortest_edge(tri);
    if (shortest >= 0.02 * h) return tri;
    const double r = 0.125 * h;
    std::vector<polygon_with_holes> f = polygon_offset(polygon_offset(coarse, -r, 0.25 * r), r, 0.25 * r);
    f = polygon_offset(polygon_offset(f, r, 0.25 * r), -r, 0.25 * r);
    f = merge_close_vertices(f, 0.5 * r);
    if (f.size() > outline.size()) return tri;  // the opening would split the piece
    fem_triangulation filtered = make_fem_triangulation(f, h);
    return shortest_edge(filtered) > shortest ? filtered : tri;
}

}  // namespace fabsynth::filigree
