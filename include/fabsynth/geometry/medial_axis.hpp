// SPDX-License-Identifier: MIT
#pragma once
/// @file medial_axis.hpp  The 2D medial axis of a polygon with holes as a skeleton: vertices with a
/// position and the local half-width (radius of the maximal inscribed disc there = distance to the
/// boundary), and straight edges between them (filigree-synthesis.md §3.3: strips reduced to their
/// skeleton graph, approximated by polylines to a user accuracy).
///
/// Engine: the segment Voronoi diagram of Boost.Polygon (boost/polygon/voronoi.hpp, Boost licence),
/// which is exact on integer input. The medial axis is the part of that diagram inside the polygon
/// without the secondary edges (the normals at polygon vertices between a segment and its own
/// endpoint): what remains are bisectors of two segments (straight), of two reflex vertices
/// (straight) and of a reflex vertex and a segment (parabolic arcs, flattened to polylines).
/// Bisectors of the two edges at a convex vertex run into that vertex, where the half-width is 0;
/// they are kept (they are the medial axis), and prune_length removes them where wanted.
///
/// Integer grid: x_int = round(x * scale) - c, with scale the smallest power of two >= 64 /
/// flattening_tolerance (so a grid step is at most 1/64 of the tolerance and moves the axis by
/// far less than the tolerance) and c the grid point nearest the centre of the bounding box. Since
/// the scale is a power of two, the way back (x_int + c) / scale is exact. Grid coordinates must
/// stay within +-2^30 (Boost's 32-bit input, and 64-bit exact predicates here); a polygon spanning
/// more than 2^31 grid steps (about 3.3e7 flattening tolerances) is rejected. Exactly collinear
/// vertices (after rounding) are dropped before the diagram is built: they would only add
/// zero-width spikes.
///
/// Half-widths are not taken from the rounded diagram: at every output vertex the distance to the
/// *input* boundary is computed (nearest input segment through a k-d tree over boundary pieces), so
/// half_widths[i] equals the exact distance from positions[i] to the input polygon up to rounding.
/// Positions carry the grid's error (about a grid step, well below the tolerance), except that a
/// vertex on a polygon vertex (the end of a corner branch) is that input vertex exactly.
///
/// Pruning (prune_length > 0), iterated: a *leaf branch* is a chain from a leaf (degree 1) through
/// degree-2 vertices to the nearest junction (degree >= 3). In each round every leaf branch shorter
/// than prune_length is removed at once, except that at a junction all of whose chains are such
/// branches the two longest stay (so a component is never pruned away, only down to a path); then
/// the degrees are recomputed and the rounds repeat until nothing changes, so a chain that becomes
/// a leaf branch after its junction lost its other branches is tested with its full new length.
/// A rectangle thus loses its four corner branches at once and keeps its middle segment.
///
/// Usage:
///   fabsynth::polygon_with_holes strip = ...;                       // mm
///   auto sk = fabsynth::medial_axis(strip, {.flattening_tolerance = 0.01, .prune_length = 1.0});
///   // sk.positions[i], sk.half_widths[i], sk.edges[e] = {i, j}
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include <boost/polygon/point_data.hpp>
#include <boost/polygon/segment_data.hpp>
#include <boost/polygon/voronoi.hpp>
#include <nanoflann.hpp>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth {

/// Options of medial_axis(); lengths in the polygon's units (mm).
struct medial_axis_options {
    double flattening_tolerance = 0.01;  ///< max distance of a flattened parabolic arc from the arc; > 0
    double prune_length = 0.0;           ///< leaf branches shorter than this are removed (iterated); 0 = none
};

/// A medial-axis skeleton: plain vectors, so a graph type (e.g. graph::skeleton_graph) can be built
/// from it directly. Vertex i is at positions[i] with half_widths[i] = distance to the boundary;
/// every edge {i, j} (i != j, no duplicates) is a straight segment between two vertices.
struct medial_skeleton {
    std::vector<vec2> positions;                    ///< #V vertex positions (input units)
    std::vector<double> half_widths;                ///< #V radii of the maximal inscribed discs, >= 0
    std::vector<std::array<std::size_t, 2>> edges;  ///< #E vertex index pairs
    double grid_scale = 0.0;                        ///< integer grid units per input unit used
};

namespace detail::medial {

using i64 = std::int64_t;
struct ipoint {
    i64 x, y;
    friend bool operator==(const ipoint&, const ipoint&) = default;
};

inline constexpr i64 coordinate_limit = i64{1} << 30;  // |x_int| < 2^30: exact int64 predicates

/// Twice the signed area of (a, b, c), exact for |coordinates| < 2^30.
[[nodiscard]] inline i64 orient(ipoint a, ipoint b, ipoint c) noexcept {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}
[[nodiscard]] inline int sign(i64 v) noexcept { return (v > 0) - (v < 0); }
[[nodiscard]] inline bool on_segment(ipoint a, ipoint b, ipoint p) noexcept {
    return orient(a, b, p) == 0 && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}
[[nodiscard]] inline bool segments_touch(ipoint a, ipoint b, ipoint c, ipoint d) noexcept {
    const int o1 = sign(orient(a, b, c)), o2 = sign(orient(a, b, d)), o3 = sign(orient(c, d, a)), o4 = sign(orient(c, d, b));
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    return on_segment(a, b, c) || on_segment(a, b, d) || on_segment(c, d, a) || on_segment(c, d, b);
}
/// Winding number of an integer ring around p (p not on the ring).
[[nodiscard]] inline int winding(const std::vector<ipoint>& r, ipoint p) noexcept {
    int w = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
        const ipoint a = r[i], b = r[(i + 1) % r.size()];
        if (a.y <= p.y) {
            if (b.y > p.y && orient(a, b, p) > 0) ++w;
        } else if (b.y <= p.y && orient(a, b, p) < 0) {
            --w;
        }
    }
    return w;
}

[[nodiscard]] inline double point_segment_distance(vec2 p, vec2 a, vec2 b) noexcept {
    const vec2 ab = b - a;
    const double l2 = glm::dot(ab, ab);
    const double t = l2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

inline std::string ring_name(std::size_t r) { return r == 0 ? std::string("the outer ring") : "hole " + std::to_string(r - 1); }

/// The polygon on the integer grid, validated: simple rings, no two rings touching, holes inside
/// the outer ring and not inside each other. Ring 0 is the outer ring (counter-clockwise), the
/// others holes (clockwise), so the interior is left of every directed edge.
struct integer_polygon {
    double scale = 1.0;
    ipoint centre{0, 0};
    std::vector<std::vector<ipoint>> rings;
    std::map<std::pair<i64, i64>, vec2> input_vertex;  ///< grid point -> the input vertex rounded to it

    [[nodiscard]] vec2 to_input(double x, double y) const {
        return {(x + static_cast<double>(centre.x)) / scale, (y + static_cast<double>(centre.y)) / scale};
    }
};

inline integer_polygon make_integer_polygon(const polygon_with_holes& input, double tolerance) {
    polygon_with_holes poly = input;
    std::vector<const ring2*> rings{&poly.outer};
    for (const ring2& h : poly.holes) rings.push_back(&h);
    box2 bounds;
    for (std::size_t r = 0; r < rings.size(); ++r) {
        if (rings[r]->size() < 3)
            throw invalid_input("medial_axis: " + ring_name(r) + " has " + std::to_string(rings[r]->size()) +
                                " vertices (at least 3 needed)");
        for (std::size_t i = 0; i < rings[r]->size(); ++i)
            if (!all_finite((*rings[r])[i]))
                throw invalid_input("medial_axis: " + ring_name(r) + " vertex " + std::to_string(i) + " is not finite");
        if (!is_simple(*rings[r]))
            throw invalid_input("medial_axis: " + ring_name(r) + " is not simple (it intersects itself or repeats a point)");
        bounds.extend(bounding_box(*rings[r]));
    }
    orient(poly);

    integer_polygon ip;
    ip.scale = std::ldexp(1.0, static_cast<int>(std::ceil(std::log2(64.0 / tolerance))));
    const vec2 c = bounds.center() * ip.scale;
    const double span = std::max(bounds.size().x, bounds.size().y) * ip.scale;
    if (!(span < 2.0 * static_cast<double>(coordinate_limit) - 4.0) || !(std::abs(c.x) < 0x1p62) || !(std::abs(c.y) < 0x1p62))
        throw invalid_input("medial_axis: the polygon spans " + std::to_string(span) +
                            " grid steps (flattening_tolerance / 64 each), more than the 2^31 the 32-bit Voronoi "
                            "input allows; use a larger flattening_tolerance");
    ip.centre = {static_cast<i64>(std::nearbyint(c.x)), static_cast<i64>(std::nearbyint(c.y))};
    auto to_grid = [&](vec2 p) {
        return ipoint{static_cast<i64>(std::nearbyint(p.x * ip.scale)) - ip.centre.x,
                      static_cast<i64>(std::nearbyint(p.y * ip.scale)) - ip.centre.y};
    };
    for (std::size_t r = 0; r < rings.size(); ++r) {
        const ring2& src = r == 0 ? poly.outer : poly.holes[r - 1];
        std::vector<ipoint> q;
        for (const vec2& p : src) {
            const ipoint g = to_grid(p);
            ip.input_vertex.try_emplace({g.x, g.y}, p);
            if (q.empty() || !(q.back() == g)) q.push_back(g);
        }
        while (q.size() > 1 && q.front() == q.back()) q.pop_back();
        // Drop exactly collinear vertices (repeat: dropping one can make its neighbour collinear).
        for (bool changed = true; changed && q.size() >= 3;) {
            changed = false;
            std::vector<ipoint> kept;
            for (std::size_t i = 0; i < q.size(); ++i) {
                const ipoint a = kept.empty() ? q[(i + q.size() - 1) % q.size()] : kept.back();
                if (orient(a, q[i], q[(i + 1) % q.size()]) == 0)
                    changed = true;
                else
                    kept.push_back(q[i]);
            }
            q.swap(kept);
        }
        double twice_area = 0.0;  // orientation must survive the rounding (sign only, so double suffices)
        for (std::size_t i = 1; i + 1 < q.size(); ++i) twice_area += static_cast<double>(orient(q[0], q[i], q[i + 1]));
        if (q.size() < 3 || (r == 0 ? !(twice_area > 0.0) : !(twice_area < 0.0)))
            throw invalid_input("medial_axis: " + ring_name(r) + " collapses on the grid of step flattening_tolerance / 64; "
                                "use a smaller flattening_tolerance");
        ip.rings.push_back(std::move(q));
    }
    // Every pair of non-adjacent edges (of any rings) must be disjoint; sweep over x-extents.
    struct seg {
        std::size_t ring, index;
        i64 lo, hi;
    };
    std::vector<seg> segs;
    for (std::size_t r = 0; r < ip.rings.size(); ++r)
        for (std::size_t i = 0; i < ip.rings[r].size(); ++i) {
            const ipoint a = ip.rings[r][i], b = ip.rings[r][(i + 1) % ip.rings[r].size()];
            segs.push_back({r, i, std::min(a.x, b.x), std::max(a.x, b.x)});
        }
    std::sort(segs.begin(), segs.end(), [](const seg& a, const seg& b) {
        return a.lo < b.lo || (a.lo == b.lo && (a.ring < b.ring || (a.ring == b.ring && a.index < b.index)));
    });
    auto end_points = [&](const seg& s) {
        const auto& rr = ip.rings[s.ring];
        return std::pair{rr[s.index], rr[(s.index + 1) % rr.size()]};
    };
    std::vector<std::size_t> active;
    for (std::size_t k = 0; k < segs.size(); ++k) {
        std::erase_if(active, [&](std::size_t f) { return segs[f].hi < segs[k].lo; });
        const auto [a, b] = end_points(segs[k]);
        for (std::size_t f : active) {
            const seg& o = segs[f];
            if (o.ring == segs[k].ring) {
                const std::size_t n = ip.rings[o.ring].size(), d = o.index > segs[k].index ? o.index - segs[k].index : segs[k].index - o.index;
                if (d == 1 || d == n - 1) continue;  // adjacent, not collinear: share only their vertex
            }
            const auto [c2, d2] = end_points(o);
            if (segments_touch(a, b, c2, d2)) {
                const bool same = o.ring == segs[k].ring;
                throw invalid_input("medial_axis: " + (same ? ring_name(o.ring) + " intersects itself"
                                                             : ring_name(o.ring) + " and " + ring_name(segs[k].ring) + " intersect") +
                                    " (on the grid of step flattening_tolerance / 64)");
            }
        }
        active.push_back(k);
    }
    for (std::size_t h = 1; h < ip.rings.size(); ++h) {
        if (winding(ip.rings[0], ip.rings[h][0]) == 0)
            throw invalid_input("medial_axis: " + ring_name(h) + " is not inside the outer ring");
        for (std::size_t g = 1; g < ip.rings.size(); ++g)
            if (g != h && winding(ip.rings[g], ip.rings[h][0]) != 0)
                throw invalid_input("medial_axis: " + ring_name(h) + " lies inside " + ring_name(g));
    }
    return ip;
}

/// Exact distance to the input boundary: k-d tree over the midpoints of boundary pieces (input
/// edges cut into pieces no longer than the mean edge length). The nearest midpoint bounds the
/// distance from above; every edge that can be closer has a piece midpoint within that bound plus
/// half a piece.
class boundary_distance {
public:
    explicit boundary_distance(const polygon_with_holes& p) {
        auto add_ring = [&](const ring2& r) {
            for (std::size_t i = 0; i < r.size(); ++i) edges_.push_back({r[i], r[(i + 1) % r.size()]});
        };
        add_ring(p.outer);
        for (const ring2& h : p.holes) add_ring(h);
        double total = 0.0;
        for (const auto& e : edges_) total += glm::length(e[1] - e[0]);
        piece_ = std::max(total / static_cast<double>(edges_.size()), std::numeric_limits<double>::min());
        for (std::size_t e = 0; e < edges_.size(); ++e) {
            const double len = glm::length(edges_[e][1] - edges_[e][0]);
            const std::size_t n = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(len / piece_)));
            for (std::size_t k = 0; k < n; ++k) {
                mids_.push_back(edges_[e][0] + (edges_[e][1] - edges_[e][0]) * ((static_cast<double>(k) + 0.5) / static_cast<double>(n)));
                owner_.push_back(e);
            }
        }
        tree_ = std::make_unique<tree>(2, *this, nanoflann::KDTreeSingleIndexAdaptorParams(8));
    }
    boundary_distance(const boundary_distance&) = delete;
    boundary_distance& operator=(const boundary_distance&) = delete;

    [[nodiscard]] double operator()(vec2 q) const {
        const double qd[2] = {q.x, q.y};
        std::size_t nearest = 0;
        double nearest_d2 = 0.0;
        tree_->knnSearch(qd, 1, &nearest, &nearest_d2);
        const double bound = std::sqrt(nearest_d2) * (1.0 + 1e-12) + 0.5 * piece_ * (1.0 + 1e-12);
        std::vector<std::size_t> found;
        collector rs{bound * bound, &found};
        tree_->findNeighbors(rs, qd, {});
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t i : found) best = std::min(best, point_segment_distance(q, edges_[owner_[i]][0], edges_[owner_[i]][1]));
        return best;
    }

    // nanoflann dataset interface
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return mids_.size(); }
    [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t d) const { return d == 0 ? mids_[i].x : mids_[i].y; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;
    }

private:
    struct collector {
        double r2;
        std::vector<std::size_t>* out;
        [[nodiscard]] double worstDist() const { return r2; }
        [[nodiscard]] bool full() const { return true; }
        bool addPoint(double, std::size_t i) {
            out->push_back(i);
            return true;
        }
    };
    using tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, boundary_distance, double>,
                                                     boundary_distance, 2, std::size_t>;
    std::vector<std::array<vec2, 2>> edges_;
    std::vector<vec2> mids_;
    std::vector<std::size_t> owner_;
    double piece_ = 1.0;
    std::unique_ptr<tree> tree_;
};

/// Iterated leaf-branch pruning (see the file comment). Marks removed edges in `alive`.
inline void prune(const std::vector<vec2>& pos, const std::vector<std::array<std::size_t, 2>>& edges,
                  std::vector<char>& alive, double min_length) {
    const std::size_t nv = pos.size();
    std::vector<std::vector<std::size_t>> incident(nv);
    for (std::size_t e = 0; e < edges.size(); ++e) incident[edges[e][0]].push_back(e), incident[edges[e][1]].push_back(e);
    std::vector<int> degree(nv);
    struct branch {
        std::size_t leaf, junction;
        double length;
        std::vector<std::size_t> edges;
    };
    for (;;) {
        for (std::size_t v = 0; v < nv; ++v) {
            degree[v] = 0;
            for (std::size_t e : incident[v]) degree[v] += alive[e];
        }
        std::vector<branch> shorts;
        for (std::size_t v = 0; v < nv; ++v) {
            if (degree[v] != 1) continue;
            branch b{v, v, 0.0, {}};
            std::size_t cur = v, came = edges.size();
            for (;;) {
                std::size_t next_edge = edges.size();
                for (std::size_t e : incident[cur])
                    if (alive[e] && e != came) {
                        next_edge = e;
                        break;
                    }
                const std::size_t nxt = edges[next_edge][0] == cur ? edges[next_edge][1] : edges[next_edge][0];
                b.length += glm::length(pos[nxt] - pos[cur]);
                b.edges.push_back(next_edge);
                came = next_edge, cur = nxt;
                if (degree[cur] != 2 || b.length >= min_length) break;
            }
            b.junction = cur;
            if (degree[cur] >= 3 && b.length < min_length) shorts.push_back(std::move(b));
        }
        if (shorts.empty()) return;
        // Group by junction; where every chain of a junction is a short branch, keep the two longest.
        std::map<std::size_t, std::vector<std::size_t>> at;
        for (std::size_t i = 0; i < shorts.size(); ++i) at[shorts[i].junction].push_back(i);
        std::vector<char> keep(shorts.size(), 0);
        for (auto& [j, list] : at) {
            if (static_cast<int>(list.size()) < degree[j]) continue;
            std::sort(list.begin(), list.end(), [&](std::size_t a, std::size_t b) {
                return shorts[a].length > shorts[b].length || (shorts[a].length == shorts[b].length && shorts[a].leaf < shorts[b].leaf);
            });
            keep[list[0]] = keep[list[1]] = 1;
        }
        bool removed = false;
        for (std::size_t i = 0; i < shorts.size(); ++i)
            if (!keep[i])
                for (std::size_t e : shorts[i].edges) alive[e] = 0, removed = true;
        if (!removed) return;
    }
}

}  // namespace detail::medial

/// The medial axis of a polygon with holes (see the file comment for the construction, the grid
/// and the pruning). Orientation of the input rings does not matter; holes must lie inside the
/// outer ring, rings must be simple and must not touch each other.
/// @param polygon  outer ring and holes, >= 3 vertices each (input units, mm by convention)
/// @param options  flattening_tolerance > 0 (mm), prune_length >= 0 (mm)
/// Throws invalid_input naming the ring for fewer than 3 vertices, non-finite coordinates, a
/// self-intersecting ring, rings that intersect or are wrongly nested (also when that happens only
/// on the integer grid), a bad tolerance or prune length, or a polygon too large for the grid.
/// Cost: O(n log n) for n boundary vertices, plus the flattened arcs.
[[nodiscard]] inline medial_skeleton medial_axis(const polygon_with_holes& polygon, const medial_axis_options& options = {}) {
    namespace bp = boost::polygon;
    using namespace detail::medial;
    if (!(std::isfinite(options.flattening_tolerance) && options.flattening_tolerance > 0.0))
        throw invalid_input("medial_axis: flattening_tolerance must be finite and > 0, got " +
                            std::to_string(options.flattening_tolerance));
    if (!(std::isfinite(options.prune_length) && options.prune_length >= 0.0))
        throw invalid_input("medial_axis: prune_length must be finite and >= 0, got " + std::to_string(options.prune_length));
    const integer_polygon ip = make_integer_polygon(polygon, options.flattening_tolerance);

    // Boost input: one segment per ring edge, with (ring, index) kept for the reflex tests.
    using bpoint = bp::point_data<int>;
    std::vector<bp::segment_data<int>> segments;
    std::vector<std::array<std::size_t, 2>> origin;  // segment -> {ring, index of its first vertex}
    for (std::size_t r = 0; r < ip.rings.size(); ++r)
        for (std::size_t i = 0; i < ip.rings[r].size(); ++i) {
            const ipoint a = ip.rings[r][i], b = ip.rings[r][(i + 1) % ip.rings[r].size()];
            segments.emplace_back(bpoint(static_cast<int>(a.x), static_cast<int>(a.y)), bpoint(static_cast<int>(b.x), static_cast<int>(b.y)));
            origin.push_back({r, i});
        }
    bp::voronoi_diagram<double> vd;
    bp::construct_voronoi(segments.begin(), segments.end(), &vd);

    using cell_t = bp::voronoi_diagram<double>::cell_type;
    using edge_t = bp::voronoi_diagram<double>::edge_type;
    auto ring_vertex = [&](std::size_t r, std::size_t i) { return ip.rings[r][i % ip.rings[r].size()]; };
    // The polygon vertex a point cell stands for, as (ring, index).
    auto point_site = [&](const cell_t& c) {
        const auto [r, i] = origin[c.source_index()];
        return std::array<std::size_t, 2>{r, c.source_category() == bp::SOURCE_CATEGORY_SEGMENT_START_POINT ? i : (i + 1) % ip.rings[r].size()};
    };
    auto segment_ends = [&](const cell_t& c) {
        const auto [r, i] = origin[c.source_index()];
        return std::pair{ring_vertex(r, i), ring_vertex(r, i + 1)};
    };
    auto as_vec = [](ipoint p) { return vec2(static_cast<double>(p.x), static_cast<double>(p.y)); };
    // Interior test of a finite primary edge (each lies entirely inside or outside the polygon,
    // touching the boundary at most in its end points).
    auto interior = [&](const edge_t& e) {
        const cell_t* cells[2] = {e.cell(), e.twin()->cell()};
        for (const cell_t* c : cells) {
            if (!c->contains_segment()) continue;
            const auto [a, b] = segment_ends(*c);
            if (e.is_curved()) {  // the arc lies between the line and the reflex vertex
                const cell_t* pc = c == cells[0] ? cells[1] : cells[0];
                const auto [r, i] = point_site(*pc);
                return orient(a, b, ring_vertex(r, i)) > 0;
            }
            // Straight edge: the side of its end point farthest from the line decides.
            const vec2 va = as_vec(a), vb = as_vec(b);
            const double o0 = orient2d(va, vb, vec2(e.vertex0()->x(), e.vertex0()->y()));
            const double o1 = orient2d(va, vb, vec2(e.vertex1()->x(), e.vertex1()->y()));
            return (std::abs(o0) >= std::abs(o1) ? o0 : o1) > 0.0;
        }
        // Bisector of two vertices: inside iff they are reflex (interior is left of every edge).
        const auto [r, i] = point_site(*cells[0]);
        const std::size_t n = ip.rings[r].size();
        return orient(ring_vertex(r, i + n - 1), ring_vertex(r, i), ring_vertex(r, i + 1)) < 0;
    };

    medial_skeleton out;
    out.grid_scale = ip.scale;
    std::vector<vec2> pos;  // grid coordinates (doubles)
    std::map<std::pair<double, double>, std::size_t> vertex_at;
    auto vertex_index = [&](double x, double y) {
        const auto [it, added] = vertex_at.try_emplace({x, y}, pos.size());
        if (added) pos.emplace_back(x, y);
        return it->second;
    };
    std::vector<std::array<std::size_t, 2>> edges;
    auto add_edge = [&](std::size_t a, std::size_t b) {
        if (a != b) edges.push_back({std::min(a, b), std::max(a, b)});
    };
    const double tol_grid = options.flattening_tolerance * ip.scale;
    for (const edge_t& e : vd.edges()) {
        if (&e > e.twin() || !e.is_finite() || !e.is_primary() || !interior(e)) continue;
        const std::size_t i0 = vertex_index(e.vertex0()->x(), e.vertex0()->y());
        const std::size_t i1 = vertex_index(e.vertex1()->x(), e.vertex1()->y());
        if (!e.is_curved()) {
            add_edge(i0, i1);
            continue;
        }
        // Parabola with focus P and directrix the segment's line: in the frame (F, dir, nrm) with F
        // the foot of P, y = (x^2 + d^2) / (2d); its chord error over dx is dx^2 / (8d).
        const cell_t* sc = e.cell()->contains_segment() ? e.cell() : e.twin()->cell();
        const cell_t* pc = sc == e.cell() ? e.twin()->cell() : e.cell();
        const auto [sa, sb] = segment_ends(*sc);
        const auto [pr, pi] = point_site(*pc);
        const vec2 a = as_vec(sa), p = as_vec(ring_vertex(pr, pi));
        const vec2 dir = glm::normalize(as_vec(sb) - a);
        const vec2 foot = a + dir * glm::dot(p - a, dir);
        const double d = glm::length(p - foot);
        const vec2 nrm = (p - foot) / d;
        const double x0 = glm::dot(pos[i0] - foot, dir), x1 = glm::dot(pos[i1] - foot, dir);
        const double steps = std::ceil(std::abs(x1 - x0) / std::sqrt(8.0 * d * tol_grid));
        const std::size_t n = static_cast<std::size_t>(std::clamp(steps, 1.0, 1e7));
        std::size_t prev = i0;
        for (std::size_t k = 1; k < n; ++k) {
            const double x = x0 + (x1 - x0) * (static_cast<double>(k) / static_cast<double>(n));
            const vec2 q = foot + dir * x + nrm * ((x * x + d * d) / (2.0 * d));
            const std::size_t cur = pos.size();
            pos.push_back(q);
            add_edge(prev, cur);
            prev = cur;
        }
        add_edge(prev, i1);
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

    // Back to input units; a diagram vertex on a polygon vertex (a convex corner) becomes that
    // input vertex exactly, so corner branches end on the input boundary with half-width 0.
    std::vector<vec2> input_pos(pos.size());
    for (std::size_t v = 0; v < pos.size(); ++v) {
        input_pos[v] = ip.to_input(pos[v].x, pos[v].y);
        if (pos[v].x == std::nearbyint(pos[v].x) && pos[v].y == std::nearbyint(pos[v].y) &&
            std::abs(pos[v].x) < 0x1p31 && std::abs(pos[v].y) < 0x1p31) {
            const auto it = ip.input_vertex.find({static_cast<i64>(pos[v].x), static_cast<i64>(pos[v].y)});
            if (it != ip.input_vertex.end()) input_pos[v] = it->second;
        }
    }
    std::vector<char> alive(edges.size(), 1);
    if (options.prune_length > 0.0) prune(input_pos, edges, alive, options.prune_length);

    // Compact: vertices in order of first use by a surviving edge.
    std::vector<std::size_t> slot(pos.size(), pos.size());
    const boundary_distance dist(polygon);
    for (std::size_t e = 0; e < edges.size(); ++e) {
        if (!alive[e]) continue;
        std::array<std::size_t, 2> ne{};
        for (int k = 0; k < 2; ++k) {
            std::size_t& s = slot[edges[e][k]];
            if (s == pos.size()) {
                s = out.positions.size();
                out.positions.push_back(input_pos[edges[e][k]]);
                out.half_widths.push_back(dist(input_pos[edges[e][k]]));
            }
            ne[k] = s;
        }
        out.edges.push_back(ne);
    }
    return out;
}

}  // namespace fabsynth
