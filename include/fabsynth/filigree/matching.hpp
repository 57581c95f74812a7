// SPDX-License-Identifier: MIT
#pragma once
/// @file matching.hpp  The pattern matching energy (filigree-synthesis.md §4.2): the modified
/// Hausdorff distance between point sets (Dubuisson & Jain 1994, eq. 1), the matching quality of two
/// overlapping elements (eq. 2) and the PME of a pattern (eq. 3).
///
/// Usage:
///   double d = fabsynth::filigree::dist_mh(U, V);                 // eq. 1, mm
///   double q = fabsynth::filigree::pair_distance(pa, pb);         // eq. 2, +inf without overlap
///   double e = fabsynth::filigree::boundary_term(pa, boundary);   // the Theta term of one element
///
/// pair_distance(P, Q): U' = the skeleton vertices of P inside Q's covering region and V' = those
/// of Q inside P's (each vertex lies in its own element's covering region by construction, so both
/// sets lie in the overlapping region, Fig. 5). Both empty: +inf (the paper's rule: no overlap).
/// One empty (the regions overlap but only one skeleton reaches into the overlap): the paper leaves
/// this open; here the empty side is replaced by that element's whole skeleton, i.e. the vertices
/// of the overlap are measured against the other skeleton, which is finite and still rewards
/// alignment.
///
/// Theta (eq. 3) is used for the domain boundary (§7.2: elements next to the boundary should touch
/// it tangentially): for an element whose covering region contains boundary samples B', with U'
/// its vertices within `band` of B', Theta_i = dist_mh(U' or all vertices, B'). The control field
/// needs no Theta term: every candidate is rotated and scaled by the field before it is scored.
///
/// dist_mh uses k-d trees (nanoflann) when both sets are large and a direct scan otherwise; both
/// compute the same exact minimum, so the result does not depend on the path taken.
#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/filigree/pattern.hpp"

namespace fabsynth::filigree {

namespace detail::matching {

struct point_cloud {
    std::span<const vec2> pts;
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return pts.size(); }
    [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t d) const { return pts[i][static_cast<int>(d)]; }
    template <class B>
    bool kdtree_get_bbox(B&) const {
        return false;
    }
};
using kd_tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, point_cloud, double>, point_cloud, 2, std::size_t>;

// Index of the point of the tree's cloud nearest to p.
[[nodiscard]] inline std::size_t nearest_index(const kd_tree& tree, vec2 p) {
    std::size_t idx = 0;
    double d2 = 0;
    nanoflann::KNNResultSet<double, std::size_t> rs(1);
    rs.init(&idx, &d2);
    const double q[2] = {p.x, p.y};
    tree.findNeighbors(rs, q, nanoflann::SearchParams());
    return idx;
}

inline constexpr std::size_t tree_threshold = 48;  // below this many points a scan is faster than building a tree

// Mean over u in U of the distance from u to the nearest point of V (V non-empty).
[[nodiscard]] inline double mean_nearest(std::span<const vec2> U, std::span<const vec2> V) {
    double sum = 0;
    if (U.size() < tree_threshold || V.size() < tree_threshold) {
        for (const vec2& u : U) {
            double best = std::numeric_limits<double>::infinity();
            for (const vec2& v : V) {
                const vec2 d = u - v;
                best = std::min(best, d.x * d.x + d.y * d.y);
            }
            sum += std::sqrt(best);
        }
    } else {
        point_cloud cloud{V};
        kd_tree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
        tree.buildIndex();
        for (const vec2& u : U) {
            const vec2 d = u - V[nearest_index(tree, u)];  // the same formula as the scan: identical results
            sum += std::sqrt(d.x * d.x + d.y * d.y);
        }
    }
    return sum / static_cast<double>(U.size());
}

}  // namespace detail::matching

/// Modified Hausdorff distance (eq. 1): max(mean_u dist(u, V), mean_v dist(v, U)). Symmetric; 0
/// for identical sets. Throws invalid_input if a set is empty.
[[nodiscard]] inline double dist_mh(std::span<const vec2> U, std::span<const vec2> V) {
    if (U.empty() || V.empty()) throw invalid_input("dist_mh: both point sets must be non-empty");
    return std::max(detail::matching::mean_nearest(U, V), detail::matching::mean_nearest(V, U));
}

/// Matching quality of two placed instances (eq. 2; see the file comment), mm; +inf when their
/// skeletons do not reach into each other's covering region.
[[nodiscard]] inline double pair_distance(const placed& a, const placed& b) {
    if (!boxes_meet(a, b)) return std::numeric_limits<double>::infinity();
    std::vector<vec2> U, V;
    for (const vec2& u : a.vertices)
        if (b.covers(u)) U.push_back(u);
    for (const vec2& v : b.vertices)
        if (a.covers(v)) V.push_back(v);
    if (U.empty() && V.empty()) return std::numeric_limits<double>::infinity();
    return dist_mh(U.empty() ? std::span<const vec2>(a.vertices) : std::span<const vec2>(U),
                   V.empty() ? std::span<const vec2>(b.vertices) : std::span<const vec2>(V));
}

/// Transversal crossings of the skeletons of two placed instances: pairs of skeleton edges, one of
/// each, that cross at an angle whose cosine is below `cos_min` (edges crossing at a smaller angle
/// are a near-tangent contact, collinear ones a matched overlap). Only edges reaching into the
/// intersection of the two covering boxes can cross (each skeleton lies in its covering region).
/// 0 when either has no edges attached.
[[nodiscard]] inline std::size_t transversal_crossings(const placed& a, const placed& b, double cos_min) {
    if (!a.edges || !b.edges || !boxes_meet(a, b)) return 0;
    const box2 common(glm::max(a.box.lo, b.box.lo), glm::min(a.box.hi, b.box.hi));
    auto inside = [&](const placed& p, const skeleton_edge& e) {
        const vec2 u = p.vertices[e[0]], v = p.vertices[e[1]];
        return std::max(u.x, v.x) >= common.lo.x && std::min(u.x, v.x) <= common.hi.x && std::max(u.y, v.y) >= common.lo.y &&
               std::min(u.y, v.y) <= common.hi.y;
    };
    std::vector<skeleton_edge> eb;
    for (const skeleton_edge& e : *b.edges)
        if (inside(b, e)) eb.push_back(e);
    std::size_t n = 0;
    for (const skeleton_edge& e : *a.edges) {
        if (!inside(a, e)) continue;
        const vec2 p0 = a.vertices[e[0]], p1 = a.vertices[e[1]];
        const vec2 dp = p1 - p0;
        const double lp = glm::length(dp);
        for (const skeleton_edge& f : eb) {
            const vec2 q0 = b.vertices[f[0]], q1 = b.vertices[f[1]];
            if (!fabsynth::detail::segments_intersect(p0, p1, q0, q1)) continue;
            const vec2 dq = q1 - q0;
            const double lq = glm::length(dq);
            if (lp > 0 && lq > 0 && std::abs(glm::dot(dp, dq)) < cos_min * lp * lq) ++n;
        }
    }
    return n;
}

/// True if the covering regions of a and b share a skeleton vertex of either (the connectivity
/// relation of the pattern graph: pair_distance is finite).
[[nodiscard]] inline bool overlapping(const placed& a, const placed& b) {
    if (!boxes_meet(a, b)) return false;
    for (const vec2& u : a.vertices)
        if (b.covers(u)) return true;
    for (const vec2& v : b.vertices)
        if (a.covers(v)) return true;
    return false;
}

/// The boundary term of one placed instance (see the file comment): 0 when no boundary sample lies
/// in its covering region. `boundary` = domain boundary samples, `band` in mm.
[[nodiscard]] inline double boundary_term(const placed& a, std::span<const vec2> boundary, double band) {
    std::vector<vec2> B;
    for (const vec2& q : boundary)
        if (a.covers(q)) B.push_back(q);
    if (B.empty()) return 0.0;
    std::vector<vec2> U;
    const double b2 = band * band;
    for (const vec2& u : a.vertices)
        for (const vec2& q : B) {
            const vec2 d = u - q;
            if (d.x * d.x + d.y * d.y <= b2) {
                U.push_back(u);
                break;
            }
        }
    return dist_mh(U.empty() ? std::span<const vec2>(a.vertices) : std::span<const vec2>(U), B);
}

}  // namespace fabsynth::filigree
