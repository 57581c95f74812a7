// SPDX-License-Identifier: MIT
#pragma once
/// @file topology_cut.hpp  Topology cut of a synthesized filigree (filigree-synthesis.md §4.5,
/// Fig. 9, eq. 4): where the skeletons of two connected elements P and Q cross, trim the short
/// protruding pieces (case 1) and, where two or more crossings are close, remove the less important
/// of the two conflicting branches (case 2), without ever disconnecting the pattern.
///
/// Usage:
///   std::vector<fabsynth::graph::skeleton_graph<fabsynth::vec2>> elements = ...;  // world mm
///   std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs = ...;             // connected (P, Q)
///   auto r = fabsynth::filigree::topology_cut(elements, pairs, {});               // width-based thresholds
///   r.protrusions_trimmed; r.branches_cut; r.cuts_refused_for_connectivity;
///
/// How, for each pair (P, Q) in the given order:
///  1. Crossings: every point where a live edge of P meets a live edge of Q (candidate edge pairs
///     from a uniform grid over the edge boxes). Both skeletons are split there: the edge is
///     replaced by a chain through a new vertex whose width is interpolated along the edge; a
///     crossing at (or within rounding of) an existing vertex uses that vertex. Collinear overlaps
///     have no single crossing point and are not crossings (they still make contact, below).
///     Hits that share a vertex of P or of Q form one crossing site t_i.
///  2. Clusters: two sites are close when their geodesic distance is below close_intersections
///     along G(P) and along G(Q); clusters are the classes of "close" (single linkage).
///  3. Case 2 (Fig. 9b-d): G(P) and G(Q) are decomposed at the sites into subgraphs G_k (the
///     components of the skeleton with every site vertex cut open). A subgraph of G(P) and one of
///     G(Q) attached to the same set of >= 2 sites, all in one cluster, are conflicting branches
///     (two curves sharing their end points); when several subgraphs of one skeleton have the same
///     set, the shortest is the one in conflict (a subgraph that is all that is left of its
///     skeleton is no branch). Each gets the importance of eq. 4,
///     I(G_k) = alpha L(G_k) + beta F(G_k), L = total edge length, F = min over the other
///     (not yet removed) subgraphs G_j, j != k, of the same skeleton of L(G_j) (0 if there is
///     none); the one with the lower I is cut (equal I: the branch of the higher instance index).
///     Conflicts are taken in increasing order of their site sets.
///  4. Case 1 (Fig. 9a): at a site that is alone in its cluster, the pieces of P and Q running from
///     the site vertex (valence >= 2 there) to a valence-1 end, through valence-2 vertices that are
///     not sites, and shorter than protrusion_length, are candidates; the shortest whose cut keeps
///     the pattern connected is cut, and only it (the crossing becomes a T joint; equal lengths:
///     P's first, in edge order). The same applies, after case 2, to every site of a larger
///     cluster through which both skeletons still pass: the paper gives case 2 for close crossings
///     and case 1 for a single one, and says nothing of close crossings that case 2 cannot resolve
///     (no subgraph of P and of Q attached to the same site set, as when Q's arc between two
///     crossings with P's outer turn also crosses P's inner turn, or a cut refused for
///     connectivity); left alone they stay crossings. Measured on the eight 2D cases of the
///     filigree main job (transversal crossings per instance, appearance.hpp): spiral 0.54 ->
///     0.17, multi_class 0.49 -> 0.14, mean 0.18 -> 0.07 (benchmarks/README.md).
/// A cut either happens whole or not at all (refused, counted).
///
/// Connected (the constraint: never disconnect the pattern):
///  - Two edges of different instances touch when they intersect, or their distance is at most
///    (w_a + w_b) / 2 with the widths interpolated at the closest points of the two edges (strips
///    that touch are connected).
///  - The pattern's components are those of the graph whose nodes are the skeleton vertices of all
///    instances, joined along live edges and across touching edge pairs (whether or not the two
///    instances are listed in connected_pairs): the printed strips' components.
/// A cut is applied only if the cut instance keeps at least one edge and the pattern does not get
/// more components. An instance may fall into several pieces (Fig. 9c: the remains of an element
/// whose conflicting branch was removed continue in the other element), each of them still joined
/// to the pattern. A case-2 branch whose removal would detach pieces of its instance takes along
/// the detached pieces shorter than detached_length (what is left of a removed dangling
/// branch, Fig. 9d, would be a protrusion), keeping the longest. Touching edge pairs are found once
/// on the input and again for the two instances of a pair after their edges are split at the
/// crossings; a candidate cut recounts the components over the kept pairs, O(V + E + T).
/// Determinism: pairs in the given order, sites, subgraphs and pieces in increasing ids; no
/// randomness, no threads. Complexity per pair: O(E_P + E_Q + K) for K candidate edge pairs of
/// the grid (near-linear unless edges crowd into few cells), plus bounded Dijkstra searches
/// around each site, O(V + E) of the instance per candidate cut for its pieces, and the pattern
/// recount, O(V + E + T) over all instances (T touching edge pairs), per candidate cut.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/geometry/box_pairs.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/rigid_motion.hpp"
#include "fabsynth/geometry/segment.hpp"
#include "fabsynth/graph/shortest_paths.hpp"
#include "fabsynth/graph/skeleton_graph.hpp"

namespace fabsynth::filigree {

/// Thresholds and weights of topology_cut (§4.5).
struct topology_cut_options {
    /// Value of a length threshold that asks for the width-based default.
    static constexpr double from_widths = -1.0;
    /// Width-based protrusion_length: this times the larger strip width (of P and Q) at the site.
    /// The paper says only "shorter than some threshold" (Fig. 9a). Measured on the eight 2D cases
    /// of the filigree main job (transversal crossings per instance, mean; case 1 cutting the
    /// shortest dangling piece per site): 1.5 -> 0.44, 8 -> 0.39, 20 -> 0.23, 30 -> 0.18. At 30
    /// (24 mm for 0.8 mm strips, about a 20 mm element's outer turn) a spiral's tail that enters
    /// a neighbour and crosses one of its turns ends at that turn, a T joint, where 1.5 widths only
    /// took the shortest ends and left the tail crossing. Only one piece goes per site, so an element loses
    /// at most one tail per single crossing.
    static constexpr double protrusion_width_factor = 30.0;
    /// Width-based detached_length: this times the largest strip width at a conflict's sites.
    static constexpr double detached_width_factor = 1.5;
    /// Width-based close_intersections: this times the largest strip width at the pair's sites.
    /// The paper says only "close to each other". Measured on the eight 2D cases of the filigree
    /// main job (transversal crossings per instance of the result, appearance.hpp, mean): 4 ->
    /// 0.84, 8 -> 0.63, 16 -> 0.44; at 16 (12.8 mm for 0.8 mm strips, about two thirds of a 20 mm
    /// element) the two crossings of two overlapping round branches (a lens) are one conflict and
    /// the weaker branch goes, where at 4 most lenses stayed as two crossings.
    static constexpr double close_width_factor = 16.0;

    /// mm: case 1 cuts the shortest dangling piece beyond a single crossing when it is shorter
    /// than this. < 0 (from_widths): protrusion_width_factor x the larger strip width at the site.
    /// Finite.
    double protrusion_length = from_widths;
    /// mm: a case-2 cut takes along the pieces of its instance it would detach when they are
    /// shorter than this (what is left of a removed dangling branch). < 0 (from_widths):
    /// detached_width_factor x the largest strip width at the conflict's sites. Finite.
    double detached_length = from_widths;
    /// mm: case 2 applies to crossings closer than this along both skeletons. < 0 (from_widths):
    /// close_width_factor x the largest strip width at the pair's crossings. Finite.
    double close_intersections = from_widths;
    /// Weights of eq. 4 (dimensionless, so I is in mm); the paper uses alpha = beta = 1. Finite and
    /// >= 0.
    double alpha = 1.0, beta = 1.0;
};

/// What topology_cut did.
struct topology_cut_report {
    std::size_t protrusions_trimmed = 0;            ///< case-1 pieces removed
    std::size_t branches_cut = 0;                   ///< case-2 conflicting branches removed
    std::size_t cuts_refused_for_connectivity = 0;  ///< candidate cuts (either case) left undone
};

/// Coordinates of instances whose skeletons live in frames of their own (each instance's local
/// parameterization of a surface), for topology_cut_in_frames.
struct instance_frames {
    /// Where instance b's coordinates lie in instance a's frame (a rigid motion taking b's
    /// coordinates to a's), or nothing when b is out of a's sight.
    std::function<std::optional<rigid_motion2>(std::uint32_t a, std::uint32_t b)> pose;
    /// The instances that can touch instance a and have a pose in its frame (a itself is ignored).
    std::function<std::vector<std::uint32_t>(std::uint32_t a)> neighbours;
};

namespace detail::topocut {

using skeleton = graph::skeleton_graph<vec2>;
using graph::edge_id;
using graph::vertex_id;
inline constexpr std::uint32_t none = 0xffffffffu;
inline constexpr double infinity = std::numeric_limits<double>::infinity();

/// Per edge slot of one skeleton: 1 = the edge belongs to the cut under consideration.
using edge_mask = std::vector<std::uint8_t>;

/// True iff e is a live edge of g outside the cut (cut may be null: nothing is cut).
[[nodiscard]] inline bool usable(const skeleton& g, edge_id e, const edge_mask* cut) {
    return g.edge_alive(e) && !(cut && (*cut)[e]);
}

// ---- geometry -------------------------------------------------------------------------------


/// Parameters along [a, b] (t) and [c, d] (s) of the point where the two segments cross or touch.
struct crossing_parameters {
    double t, s;
};

/// The single common point of segments [a, b] and [c, d], or nothing if they are disjoint or
/// parallel within 1e-12 rad (overlapping collinear segments share no single crossing point; the
/// tolerance keeps two copies of one segment collinear after each was moved from its own frame,
/// where rounding tilts them by ~1e-16).
[[nodiscard]] inline std::optional<crossing_parameters> segment_crossing(vec2 a, vec2 b, vec2 c, vec2 d) {
    if (!fabsynth::detail::segments_intersect(a, b, c, d)) return std::nullopt;
    const vec2 r = b - a, q = d - c, ac = c - a;
    const double denom = r.x * q.y - r.y * q.x;
    if (!(std::abs(denom) > 1e-12 * std::sqrt(glm::dot(r, r) * glm::dot(q, q)))) return std::nullopt;
    // a + t r = c + s q, crossed with q and with r
    const double t = (ac.x * q.y - ac.y * q.x) / denom, s = (ac.x * r.y - ac.y * r.x) / denom;
    return crossing_parameters{std::clamp(t, 0.0, 1.0), std::clamp(s, 0.0, 1.0)};
}

/// True iff the strips around edge e of g and edge f of h touch: the edges intersect, or their
/// distance is at most (w_e + w_f) / 2 with both widths interpolated at the closest points.
[[nodiscard]] inline bool edges_touch(const skeleton& g, edge_id e, const skeleton& h, edge_id f) {
    const auto [u0, u1] = g.endpoints(e);
    const auto [v0, v1] = h.endpoints(f);
    const vec2 a0 = g.position(u0), a1 = g.position(u1), b0 = h.position(v0), b1 = h.position(v1);
    if (fabsynth::detail::segments_intersect(a0, a1, b0, b1)) return true;
    // Disjoint segments in the plane: an end point of one of them is one of the closest points.
    double best = infinity, reach = 0.0;
    auto consider = [&](vec2 p, double wp, vec2 s0, vec2 s1, double w0, double w1) {
        const double t = segment_closest_parameter(p, s0, s1);
        const vec2 d = p - (s0 + t * (s1 - s0));
        const double d2 = glm::dot(d, d);
        if (d2 < best) best = d2, reach = 0.5 * (wp + w0 + t * (w1 - w0));
    };
    consider(a0, g.width(u0), b0, b1, h.width(v0), h.width(v1));
    consider(a1, g.width(u1), b0, b1, h.width(v0), h.width(v1));
    consider(b0, h.width(v0), a0, a1, g.width(u0), g.width(u1));
    consider(b1, h.width(v1), a0, a1, g.width(u0), g.width(u1));
    return best <= reach * reach;
}

/// The live edges of g outside the cut and their boxes (grown by half the larger end width when
/// `grown`, so that touching strips have intersecting boxes).
struct edge_boxes {
    std::vector<edge_id> ids;
    std::vector<box2> boxes;
};

[[nodiscard]] inline edge_boxes boxes_of(const skeleton& g, const edge_mask* cut, bool grown) {
    edge_boxes r;
    for (edge_id e = 0; e < g.edge_slots(); ++e) {
        if (!usable(g, e, cut)) continue;
        const auto [u, v] = g.endpoints(e);
        box2 b;
        b.extend(g.position(u)).extend(g.position(v));
        r.ids.push_back(e);
        r.boxes.push_back(grown ? b.inflated(0.5 * std::max(g.width(u), g.width(v))) : b);
    }
    return r;
}

/// A touching edge pair (edge of g outside the cut, edge of h), or nothing.
[[nodiscard]] inline std::optional<std::pair<edge_id, edge_id>> touching_edges(const skeleton& g, const edge_mask* g_cut, const skeleton& h) {
    const edge_boxes eg = boxes_of(g, g_cut, true), eh = boxes_of(h, nullptr, true);
    std::optional<std::pair<edge_id, edge_id>> found;
    for_each_overlapping_box(eg.boxes, eh.boxes, [&](std::size_t i, std::size_t j) {
        if (!edges_touch(g, eg.ids[i], h, eh.ids[j])) return false;
        found.emplace(eg.ids[i], eh.ids[j]);
        return true;
    });
    return found;
}

/// g with every vertex moved by m (ids, widths and edges kept).
[[nodiscard]] inline skeleton moved_copy(const skeleton& g, const rigid_motion2& m) {
    skeleton out = g;
    for (vertex_id v = 0; v < out.num_vertices(); ++v) out.set_position(v, m(g.position(v)));
    return out;
}

// ---- connectivity ---------------------------------------------------------------------------

/// Pieces of one skeleton: components of its live edges outside the cut; isolated vertices have no
/// piece. Pieces are numbered in order of their smallest vertex id.
struct skeleton_pieces {
    std::vector<std::uint32_t> of_vertex;  ///< piece per vertex, none = no usable edge
    std::vector<double> length;            ///< total edge length per piece (mm)
    [[nodiscard]] std::size_t count() const noexcept { return length.size(); }
};

[[nodiscard]] inline skeleton_pieces pieces_of(const skeleton& g, const edge_mask* cut) {
    union_find uf(g.num_vertices());
    for (edge_id e = 0; e < g.edge_slots(); ++e)
        if (usable(g, e, cut)) uf.unite(g.endpoints(e).first, g.endpoints(e).second);
    skeleton_pieces p;
    p.of_vertex.assign(g.num_vertices(), none);
    std::vector<std::uint8_t> has_edge(g.num_vertices(), 0);
    for (edge_id e = 0; e < g.edge_slots(); ++e)
        if (usable(g, e, cut)) has_edge[g.endpoints(e).first] = has_edge[g.endpoints(e).second] = 1;
    for (vertex_id v = 0; v < g.num_vertices(); ++v) {
        if (!has_edge[v]) continue;
        const vertex_id root = uf.find(v);  // the smallest id of the set: labelled first
        if (root == v) p.of_vertex[v] = static_cast<std::uint32_t>(p.length.size()), p.length.push_back(0.0);
        else p.of_vertex[v] = p.of_vertex[root];
    }
    for (edge_id e = 0; e < g.edge_slots(); ++e)
        if (usable(g, e, cut)) p.length[p.of_vertex[g.endpoints(e).first]] += g.length(e);
    return p;
}

/// The touch graph of the pattern at the level of skeleton pieces (see the file comment): every
/// touching edge pair of two different instances is kept, so that the components of (vertices
/// joined along live edges and across touching pairs) can be recounted for any tentative cut.
class pattern_contacts {
public:
    /// Finds the touching edge pairs of the instances (candidates from their grown boxes). With
    /// frames, the edges of instances a < b are compared in a's frame, b's moved there by its pose.
    explicit pattern_contacts(const std::vector<skeleton>& instances, const instance_frames* frames = nullptr)
        : instances_(&instances), frames_(frames), first_vertex_(instances.size() + 1, 0) {
        for (std::size_t k = 0; k < instances.size(); ++k) first_vertex_[k + 1] = first_vertex_[k] + instances[k].num_vertices();
        if (frames_) {
            for (std::uint32_t a = 0; a < instances.size(); ++a) {
                neighbours_.push_back(frames_->neighbours(a));
                std::sort(neighbours_.back().begin(), neighbours_.back().end());
            }
            for (std::uint32_t a = 0; a < instances.size(); ++a)
                for (const std::uint32_t b : neighbours_[a])
                    if (b > a && b < instances.size()) add_touches_in_frame(a, b);
            std::sort(touches_.begin(), touches_.end());
            components_ = count_components(none, nullptr);
            return;
        }
        edge_boxes all;
        std::vector<std::uint32_t> owner;
        for (std::uint32_t k = 0; k < instances.size(); ++k) {
            const edge_boxes b = boxes_of(instances[k], nullptr, true);
            all.ids.insert(all.ids.end(), b.ids.begin(), b.ids.end());
            all.boxes.insert(all.boxes.end(), b.boxes.begin(), b.boxes.end());
            owner.insert(owner.end(), b.ids.size(), k);
        }
        for_each_overlapping_box(all.boxes, all.boxes, [&](std::size_t i, std::size_t j) {
            if (owner[i] < owner[j] && edges_touch(instances[owner[i]], all.ids[i], instances[owner[j]], all.ids[j]))
                touches_.push_back({owner[i], all.ids[i], owner[j], all.ids[j]});
            return false;
        });
        std::sort(touches_.begin(), touches_.end());
        components_ = count_components(none, nullptr);
    }

    /// Re-finds the touching pairs of instance x after its edges were split (new vertices, new
    /// edges): its old pairs are dropped and its live edges are tested against every other instance.
    void refresh(std::uint32_t x) {
        const auto& inst = *instances_;
        std::erase_if(touches_, [x](const touch& t) { return t.a == x || t.b == x; });
        if (frames_) {  // the pairs (a, b), a < b, of the constructor that involve x
            for (std::uint32_t a = 0; a < x; ++a)
                if (std::binary_search(neighbours_[a].begin(), neighbours_[a].end(), x)) add_touches_in_frame(a, x);
            for (const std::uint32_t b : neighbours_[x])
                if (b > x && b < inst.size()) add_touches_in_frame(x, b);
        } else {
            refresh_planar(x);
        }
        std::sort(touches_.begin(), touches_.end());
        for (std::size_t k = 0; k < inst.size(); ++k) first_vertex_[k + 1] = first_vertex_[k] + inst[k].num_vertices();
        components_ = count_components(none, nullptr);
    }

    /// True iff cutting the masked edges of instance x leaves the pattern with no more components.
    [[nodiscard]] bool keeps_components(std::uint32_t x, const edge_mask& cut) const { return count_components(x, &cut) <= components_; }
    /// Records an applied cut (the edges are already removed).
    void commit() { components_ = count_components(none, nullptr); }

private:
    void refresh_planar(std::uint32_t x) {
        const auto& inst = *instances_;
        const edge_boxes mine = boxes_of(inst[x], nullptr, true);
        for (std::uint32_t k = 0; k < inst.size(); ++k) {
            if (k == x) continue;
            const edge_boxes other = boxes_of(inst[k], nullptr, true);
            for_each_overlapping_box(mine.boxes, other.boxes, [&](std::size_t i, std::size_t j) {
                if (edges_touch(inst[x], mine.ids[i], inst[k], other.ids[j]))
                    touches_.push_back(x < k ? touch{x, mine.ids[i], k, other.ids[j]} : touch{k, other.ids[j], x, mine.ids[i]});
                return false;
            });
        }
    }

    /// The touching edge pairs of instances a < b, compared in a's frame.
    void add_touches_in_frame(std::uint32_t a, std::uint32_t b) {
        const auto& inst = *instances_;
        const std::optional<rigid_motion2> pose = frames_->pose(a, b);
        if (!pose) return;
        const skeleton moved = moved_copy(inst[b], *pose);
        const edge_boxes ea = boxes_of(inst[a], nullptr, true), eb = boxes_of(moved, nullptr, true);
        for_each_overlapping_box(ea.boxes, eb.boxes, [&](std::size_t i, std::size_t j) {
            if (edges_touch(inst[a], ea.ids[i], moved, eb.ids[j])) touches_.push_back({a, ea.ids[i], b, eb.ids[j]});
            return false;
        });
    }

    struct touch {
        std::uint32_t a;
        edge_id edge_a;
        std::uint32_t b;  // a < b
        edge_id edge_b;
        friend bool operator<(const touch& l, const touch& r) noexcept {
            return std::tie(l.a, l.edge_a, l.b, l.edge_b) < std::tie(r.a, r.edge_a, r.b, r.edge_b);
        }
    };
    /// Components of the pattern's live edges, with instance x's masked edges left out.
    [[nodiscard]] std::size_t count_components(std::uint32_t x, const edge_mask* cut) const {
        const auto& inst = *instances_;
        union_find uf(first_vertex_.back());
        std::vector<std::uint8_t> used(first_vertex_.back(), 0);
        for (std::uint32_t k = 0; k < inst.size(); ++k)
            for (edge_id e = 0; e < inst[k].edge_slots(); ++e)
                if (usable(inst[k], e, k == x ? cut : nullptr)) {
                    const auto [u, v] = inst[k].endpoints(e);
                    uf.unite(first_vertex_[k] + u, first_vertex_[k] + v);
                    used[first_vertex_[k] + u] = used[first_vertex_[k] + v] = 1;
                }
        for (const touch& t : touches_)
            if (usable(inst[t.a], t.edge_a, t.a == x ? cut : nullptr) && usable(inst[t.b], t.edge_b, t.b == x ? cut : nullptr))
                uf.unite(first_vertex_[t.a] + inst[t.a].endpoints(t.edge_a).first, first_vertex_[t.b] + inst[t.b].endpoints(t.edge_b).first);
        std::size_t n = 0;
        for (std::uint32_t v = 0; v < used.size(); ++v) n += used[v] && uf.find(v) == v;
        return n;
    }

    const std::vector<skeleton>* instances_;
    const instance_frames* frames_ = nullptr;
    std::vector<std::vector<std::uint32_t>> neighbours_;  // with frames: per instance, sorted
    std::vector<std::uint32_t> first_vertex_;  // global id of each instance's vertex 0, and the total
    std::vector<touch> touches_;
    std::size_t components_ = 0;
};

/// Applies the cut of the masked edges of instance x if it is allowed (file comment): with
/// detach_below > 0, pieces that the cut detaches and that are shorter than detach_below (mm) join
/// the cut, the longest detached piece staying. Returns whether the cut was applied.
inline bool try_cut(std::vector<skeleton>& instances, std::uint32_t x, edge_mask cut, double detach_below, pattern_contacts& contacts) {
    skeleton& g = instances[x];
    const std::size_t pieces_before = pieces_of(g, nullptr).count();
    skeleton_pieces after = pieces_of(g, &cut);
    if (after.count() > pieces_before && detach_below > 0.0) {
        std::vector<std::uint32_t> at_cut;  // pieces touching an end of a cut edge
        for (edge_id e = 0; e < g.edge_slots(); ++e) {
            if (!cut[e] || !g.edge_alive(e)) continue;
            for (const vertex_id v : {g.endpoints(e).first, g.endpoints(e).second})
                if (after.of_vertex[v] != none) at_cut.push_back(after.of_vertex[v]);
        }
        std::sort(at_cut.begin(), at_cut.end());
        at_cut.erase(std::unique(at_cut.begin(), at_cut.end()), at_cut.end());
        if (at_cut.size() > 1) {
            std::uint32_t keep = at_cut[0];
            for (const std::uint32_t p : at_cut)
                if (after.length[p] > after.length[keep]) keep = p;
            std::vector<std::uint8_t> detach(after.count(), 0);
            for (const std::uint32_t p : at_cut) detach[p] = p != keep && after.length[p] < detach_below;
            for (edge_id e = 0; e < g.edge_slots(); ++e)
                if (usable(g, e, &cut) && detach[after.of_vertex[g.endpoints(e).first]]) cut[e] = 1;
            after = pieces_of(g, &cut);
        }
    }
    if (after.count() == 0 || !contacts.keeps_components(x, cut)) return false;
    for (edge_id e = 0; e < g.edge_slots(); ++e)
        if (cut[e] && g.edge_alive(e)) g.remove_edge(e);
    contacts.commit();
    return true;
}

// ---- phase 1: crossings ---------------------------------------------------------------------

/// One edge-edge crossing of P and Q: the edges, the parameters along them, the point.
struct crossing_hit {
    edge_id edge_p, edge_q;
    double t_p, t_q;
    vec2 point;
};

/// Every crossing of a live edge of P with a live edge of Q, in increasing (edge_q, edge_p).
[[nodiscard]] inline std::vector<crossing_hit> find_crossing_hits(const skeleton& P, const skeleton& Q) {
    const edge_boxes ep = boxes_of(P, nullptr, false), eq = boxes_of(Q, nullptr, false);
    std::vector<crossing_hit> hits;
    for_each_overlapping_box(ep.boxes, eq.boxes, [&](std::size_t i, std::size_t j) {
        const auto [a, b] = P.endpoints(ep.ids[i]);
        const auto [c, d] = Q.endpoints(eq.ids[j]);
        const vec2 pa = P.position(a), pb = P.position(b);
        if (const auto x = segment_crossing(pa, pb, Q.position(c), Q.position(d)))
            hits.push_back({ep.ids[i], eq.ids[j], x->t, x->s, pa + x->t * (pb - pa)});
        return false;
    });
    std::sort(hits.begin(), hits.end(), [](const crossing_hit& x, const crossing_hit& y) {
        return x.edge_q != y.edge_q ? x.edge_q < y.edge_q : x.edge_p < y.edge_p;
    });
    return hits;
}

/// A point where edge `edge` of a skeleton is to be split (parameter t from its first endpoint).
struct split_point {
    edge_id edge;
    double t;
    vec2 point;
    std::size_t hit;
};

/// Splits the edges of g at the given points and returns the vertex at each hit (indexed by hit).
/// Points within rounding of an end point (1e-9 relative to the coordinates) or of the previous
/// point on the same edge reuse that vertex; new vertices sit at the given point with the width
/// interpolated along the edge.
[[nodiscard]] inline std::vector<vertex_id> split_edges_at(skeleton& g, std::vector<split_point> at, std::size_t hits) {
    std::sort(at.begin(), at.end(), [](const split_point& x, const split_point& y) {
        return x.edge != y.edge ? x.edge < y.edge : x.t != y.t ? x.t < y.t : x.hit < y.hit;
    });
    std::vector<vertex_id> vertex_of(hits, graph::no_vertex);
    for (std::size_t k = 0; k < at.size();) {
        const edge_id e = at[k].edge;
        const auto [u, v] = g.endpoints(e);
        const vec2 pu = g.position(u), pv = g.position(v);
        const double wu = g.width(u), wv = g.width(v), len = g.length(e);
        const double snap = 1e-9 * (1.0 + std::max({std::abs(pu.x), std::abs(pu.y), std::abs(pv.x), std::abs(pv.y)}));
        std::vector<vertex_id> chain{u};
        double last_t = 0.0;
        for (; k < at.size() && at[k].edge == e; ++k) {
            const double t = at[k].t;
            vertex_id x;
            if (t * len <= snap) x = u;
            else if ((1.0 - t) * len <= snap) x = v;
            else if (chain.size() > 1 && (t - last_t) * len <= snap) x = chain.back();
            else x = g.add_vertex(at[k].point, wu + t * (wv - wu)), chain.push_back(x), last_t = t;
            vertex_of[at[k].hit] = x;
        }
        if (chain.size() == 1) continue;
        chain.push_back(v);
        g.remove_edge(e);
        for (std::size_t i = 0; i + 1 < chain.size(); ++i) g.add_edge(chain[i], chain[i + 1]);
    }
    return vertex_of;
}

/// A crossing site t_i: the vertices of G(P) and G(Q) there (usually one each).
struct crossing_site {
    std::vector<vertex_id> at_p, at_q;
    double width = 0.0;  ///< larger strip width of P and Q at the site (mm)
};

/// The sites of one pair and, per vertex of P and of Q, its site (none if it is not at one).
struct pair_crossings {
    std::vector<crossing_site> sites;
    std::vector<std::uint32_t> site_of_p, site_of_q;
};

/// Phase 1: splits P and Q at their crossings and groups the crossing vertices into sites.
[[nodiscard]] inline pair_crossings split_at_crossings(skeleton& P, skeleton& Q) {
    const std::vector<crossing_hit> hits = find_crossing_hits(P, Q);
    pair_crossings x;
    if (hits.empty()) return x;
    std::vector<split_point> on_p, on_q;
    for (std::size_t k = 0; k < hits.size(); ++k) {
        on_p.push_back({hits[k].edge_p, hits[k].t_p, hits[k].point, k});
        on_q.push_back({hits[k].edge_q, hits[k].t_q, hits[k].point, k});
    }
    const std::vector<vertex_id> vp = split_edges_at(P, std::move(on_p), hits.size()), vq = split_edges_at(Q, std::move(on_q), hits.size());
    std::vector<std::pair<vertex_id, vertex_id>> records;
    for (std::size_t k = 0; k < hits.size(); ++k) records.emplace_back(vp[k], vq[k]);
    std::sort(records.begin(), records.end());
    records.erase(std::unique(records.begin(), records.end()), records.end());
    // records sharing a vertex of P or of Q are one site
    union_find same(records.size());
    std::vector<std::uint32_t> first_p(P.num_vertices(), none), first_q(Q.num_vertices(), none);
    for (std::uint32_t r = 0; r < records.size(); ++r) {
        for (auto* first : {&first_p[records[r].first], &first_q[records[r].second]}) {
            if (*first == none) *first = r;
            else same.unite(*first, r);
        }
    }
    x.site_of_p.assign(P.num_vertices(), none);
    x.site_of_q.assign(Q.num_vertices(), none);
    std::vector<std::uint32_t> site_of_record(records.size());
    for (std::uint32_t r = 0; r < records.size(); ++r) {
        const std::uint32_t root = same.find(r);  // smallest record of the set: seen first
        if (root == r) site_of_record[r] = static_cast<std::uint32_t>(x.sites.size()), x.sites.emplace_back();
        else site_of_record[r] = site_of_record[root];
        const std::uint32_t s = site_of_record[r];
        crossing_site& site = x.sites[s];
        const auto [p, q] = records[r];
        if (x.site_of_p[p] == none) x.site_of_p[p] = s, site.at_p.push_back(p);
        if (x.site_of_q[q] == none) x.site_of_q[q] = s, site.at_q.push_back(q);
        site.width = std::max({site.width, P.width(p), Q.width(q)});
    }
    return x;
}

// ---- phase 2: clusters of close crossings ---------------------------------------------------

/// Geodesic distances along a skeleton from one vertex to the vertices closer than a radius:
/// graph/shortest_paths.hpp's bounded_search over the skeleton's incidence lists.
class bounded_search {
public:
    explicit bounded_search(const skeleton& g) : g_(&g), search_(g.num_vertices()) {}

    /// Calls found(v) for every vertex v whose geodesic distance from `source` is < radius (mm).
    template <class Found>
    void run(vertex_id source, double radius, Found&& found) {
        search_.run(source, radius, [this](vertex_id v, auto&& visit) {
            for (const edge_id e : g_->incident(v)) visit(g_->other(e, v), g_->length(e));
        }, std::forward<Found>(found));
    }

private:
    const skeleton* g_;
    graph::bounded_search search_;
};

/// Phase 2: cluster label (smallest site of the cluster) and cluster size per site; sites i, j
/// are close when closer than `radius` (mm) along both skeletons.
struct site_clusters {
    std::vector<std::uint32_t> of_site;
    std::vector<std::uint32_t> size;  ///< per site: size of its cluster
};

[[nodiscard]] inline site_clusters cluster_close_crossings(const skeleton& P, const skeleton& Q, const pair_crossings& x, double radius) {
    const std::size_t m = x.sites.size();
    union_find close(m);
    if (m > 1 && radius > 0.0) {
        bounded_search along_p(P), along_q(Q);
        std::vector<std::uint32_t> near_on_p(m, none);  // = i when site j is within radius of i along P
        for (std::uint32_t i = 0; i < m; ++i) {
            along_p.run(x.sites[i].at_p[0], radius, [&](vertex_id v) {
                if (x.site_of_p[v] != none) near_on_p[x.site_of_p[v]] = i;
            });
            along_q.run(x.sites[i].at_q[0], radius, [&](vertex_id v) {
                const std::uint32_t j = x.site_of_q[v];
                if (j != none && j != i && near_on_p[j] == i) close.unite(i, j);
            });
        }
    }
    site_clusters c;
    c.of_site.resize(m);
    c.size.assign(m, 0);
    for (std::uint32_t i = 0; i < m; ++i) c.of_site[i] = close.find(i), ++c.size[c.of_site[i]];
    for (std::uint32_t i = 0; i < m; ++i) c.size[i] = c.size[c.of_site[i]];
    return c;
}

// ---- phase 3: case 2, conflicting branches --------------------------------------------------

/// A subgraph G_k of the decomposition at the sites: its edges, L(G_k) and the sites it touches.
struct branch_part {
    std::vector<edge_id> edges;
    double length = 0.0;               ///< L(G_k), mm
    std::vector<std::uint32_t> sites;  ///< increasing, distinct
    bool removed = false;
};

/// The subgraphs of g cut open at every site vertex, in order of their smallest edge id.
[[nodiscard]] inline std::vector<branch_part> decompose_at_sites(const skeleton& g, const std::vector<std::uint32_t>& site_of) {
    union_find joined(g.edge_slots());
    for (vertex_id v = 0; v < g.num_vertices(); ++v) {
        if (site_of[v] != none) continue;
        const auto inc = g.incident(v);
        for (std::size_t k = 1; k < inc.size(); ++k) joined.unite(inc[0], inc[k]);
    }
    std::vector<branch_part> parts;
    std::vector<std::uint32_t> part_of(g.edge_slots(), none);
    for (edge_id e = 0; e < g.edge_slots(); ++e) {
        if (!g.edge_alive(e)) continue;
        const edge_id root = joined.find(e);  // smallest edge of the set: seen first
        if (part_of[root] == none) part_of[root] = static_cast<std::uint32_t>(parts.size()), parts.emplace_back();
        part_of[e] = part_of[root];
        parts[part_of[e]].edges.push_back(e);
        parts[part_of[e]].length += g.length(e);
    }
    for (vertex_id v = 0; v < g.num_vertices(); ++v)
        if (site_of[v] != none)
            for (const edge_id e : g.incident(v)) parts[part_of[e]].sites.push_back(site_of[v]);
    for (branch_part& p : parts) {
        std::sort(p.sites.begin(), p.sites.end());
        p.sites.erase(std::unique(p.sites.begin(), p.sites.end()), p.sites.end());
    }
    return parts;
}

/// Eq. 4: I(G_k) = alpha L(G_k) + beta F(G_k), F(G_k) = min over the other parts not removed of
/// their length (0 if there is none).
[[nodiscard]] inline double importance(const std::vector<branch_part>& parts, std::size_t k, const topology_cut_options& opt) {
    double frontier = infinity;
    for (std::size_t j = 0; j < parts.size(); ++j)
        if (j != k && !parts[j].removed) frontier = std::min(frontier, parts[j].length);
    return opt.alpha * parts[k].length + opt.beta * (frontier == infinity ? 0.0 : frontier);
}

/// Per site set (>= 2 sites, one cluster), the shortest part attached to exactly that set.
[[nodiscard]] inline std::map<std::vector<std::uint32_t>, std::size_t> conflict_candidates(const std::vector<branch_part>& parts,
                                                                                          const site_clusters& clusters) {
    std::map<std::vector<std::uint32_t>, std::size_t> best;
    for (std::size_t k = 0; k < parts.size(); ++k) {
        const auto& s = parts[k].sites;
        if (s.size() < 2) continue;
        if (!std::all_of(s.begin(), s.end(), [&](std::uint32_t i) { return clusters.of_site[i] == clusters.of_site[s[0]]; })) continue;
        const auto [it, fresh] = best.try_emplace(s, k);
        if (!fresh && parts[k].length < parts[it->second].length) it->second = k;
    }
    return best;
}

/// True iff part k is the only part of its skeleton not removed.
[[nodiscard]] inline bool only_part_left(const std::vector<branch_part>& parts, std::size_t k) {
    for (std::size_t j = 0; j < parts.size(); ++j)
        if (j != k && !parts[j].removed) return false;
    return true;
}

/// Threshold of a length option: the value, or factor x width when it asks for the default.
[[nodiscard]] inline double threshold(double option, double factor, double width) { return option >= 0.0 ? option : factor * width; }

/// Phase 3 (case 2, Fig. 9b-d) for the pair (p, q).
inline void cut_conflicting_branches(std::vector<skeleton>& instances, std::uint32_t p, std::uint32_t q, const pair_crossings& x,
                                     const site_clusters& clusters, const topology_cut_options& opt, pattern_contacts& contacts,
                                     topology_cut_report& report) {
    if (std::none_of(clusters.size.begin(), clusters.size.end(), [](std::uint32_t s) { return s > 1; })) return;
    std::vector<branch_part> parts_p = decompose_at_sites(instances[p], x.site_of_p), parts_q = decompose_at_sites(instances[q], x.site_of_q);
    const auto on_p = conflict_candidates(parts_p, clusters), on_q = conflict_candidates(parts_q, clusters);
    for (const auto& [sites, kp] : on_p) {
        const auto match = on_q.find(sites);
        if (match == on_q.end()) continue;
        const std::size_t kq = match->second;
        if (parts_p[kp].removed || parts_q[kq].removed) continue;
        if (only_part_left(parts_p, kp) || only_part_left(parts_q, kq)) continue;  // a whole skeleton is no branch
        const double ip = importance(parts_p, kp, opt), iq = importance(parts_q, kq, opt);
        // the lower importance is cut; equal importance cuts the branch of the higher instance index
        const bool cut_p = ip < iq || (ip == iq && p > q);
        const std::uint32_t owner = cut_p ? p : q;
        std::vector<branch_part>& parts = cut_p ? parts_p : parts_q;
        skeleton& g = instances[owner];
        edge_mask cut(g.edge_slots(), 0);
        for (const edge_id e : parts[cut_p ? kp : kq].edges) cut[e] = 1;
        double widest = 0.0;
        for (const std::uint32_t s : sites) widest = std::max(widest, x.sites[s].width);
        const double detach_below = threshold(opt.detached_length, topology_cut_options::detached_width_factor, widest);
        if (!try_cut(instances, owner, std::move(cut), detach_below, contacts)) {
            ++report.cuts_refused_for_connectivity;
            continue;
        }
        ++report.branches_cut;
        for (branch_part& part : parts)  // the branch and any pieces it took along
            part.removed = part.removed || std::none_of(part.edges.begin(), part.edges.end(), [&](edge_id e) { return g.edge_alive(e); });
    }
}

// ---- phase 4: case 1, protrusions -----------------------------------------------------------

/// The run of edges from vertex `from` along edge `first` through valence-2 vertices that are not
/// sites; dangling = it ends at a valence-1 vertex that is not a site.
struct skeleton_run {
    std::vector<edge_id> edges;
    double length = 0.0;
    bool dangling = false;
};

[[nodiscard]] inline skeleton_run walk_run(const skeleton& g, vertex_id from, edge_id first, const std::vector<std::uint32_t>& site_of) {
    skeleton_run r;
    vertex_id at = from;
    edge_id e = first;
    for (;;) {
        r.edges.push_back(e);
        r.length += g.length(e);
        at = g.other(e, at);
        if (at == from || site_of[at] != none || g.valence(at) != 2) break;
        const auto inc = g.incident(at);
        e = inc[0] == e ? inc[1] : inc[0];
    }
    r.dangling = g.valence(at) == 1 && site_of[at] == none;
    return r;
}

/// True iff both skeletons still pass through site s (each has a vertex of valence >= 2 there):
/// the site is still a crossing, not a T joint or an end.
[[nodiscard]] inline bool still_crossing(const skeleton& P, const skeleton& Q, const crossing_site& s) {
    auto through = [](const skeleton& g, const std::vector<vertex_id>& at) {
        return std::any_of(at.begin(), at.end(), [&](vertex_id v) { return g.valence(v) >= 2; });
    };
    return through(P, s.at_p) && through(Q, s.at_q);
}

/// Phase 4 (case 1, Fig. 9a) for the pair (p, q): at every site alone in its cluster, and at every
/// site of a larger cluster that case 2 left a crossing (see the file comment).
inline void trim_protrusions(std::vector<skeleton>& instances, std::uint32_t p, std::uint32_t q, const pair_crossings& x,
                             const site_clusters& clusters, const topology_cut_options& opt, pattern_contacts& contacts,
                             topology_cut_report& report) {
    for (std::uint32_t s = 0; s < x.sites.size(); ++s) {
        if (clusters.size[s] != 1 && !still_crossing(instances[p], instances[q], x.sites[s])) continue;
        const double shorter_than = threshold(opt.protrusion_length, topology_cut_options::protrusion_width_factor, x.sites[s].width);
        if (!(shorter_than > 0.0)) continue;
        struct arm { double length; std::uint32_t owner; std::vector<edge_id> edges; };
        std::vector<arm> arms;
        for (const auto& [owner, at, site_of] : {std::tuple{p, &x.sites[s].at_p, &x.site_of_p}, std::tuple{q, &x.sites[s].at_q, &x.site_of_q}}) {
            skeleton& g = instances[owner];
            for (const vertex_id v : *at) {
                if (g.valence(v) < 2) continue;
                for (const edge_id e : g.incident(v)) {
                    const skeleton_run run = walk_run(g, v, e, *site_of);
                    if (run.dangling && run.length < shorter_than) arms.push_back({run.length, owner, run.edges});
                }
            }
        }
        std::stable_sort(arms.begin(), arms.end(), [](const arm& a, const arm& b) { return a.length < b.length; });
        for (arm& a : arms) {
            edge_mask cut(instances[a.owner].edge_slots(), 0);
            for (const edge_id c : a.edges) cut[c] = 1;
            if (try_cut(instances, a.owner, std::move(cut), 0.0, contacts)) { ++report.protrusions_trimmed; break; }
            ++report.cuts_refused_for_connectivity;
        }
    }
}

// ---- driver ---------------------------------------------------------------------------------

/// Throws invalid_input for an option out of its domain or a pair naming a missing instance or
/// the same instance twice. (Positions and widths are finite by construction: skeleton_graph
/// refuses others.)
inline void check_input(const std::vector<skeleton>& instances, std::span<const std::pair<std::uint32_t, std::uint32_t>> pairs,
                        const topology_cut_options& opt) {
    for (const auto& [value, name] : {std::pair{opt.protrusion_length, "protrusion_length"}, std::pair{opt.detached_length, "detached_length"},
                                        std::pair{opt.close_intersections, "close_intersections"}})
        if (!std::isfinite(value))
            throw invalid_input(std::string("topology_cut: ") + name + " must be finite (negative: from the widths), got " + std::to_string(value));
    for (const auto& [value, name] : {std::pair{opt.alpha, "alpha"}, std::pair{opt.beta, "beta"}})
        if (!(std::isfinite(value) && value >= 0.0))
            throw invalid_input(std::string("topology_cut: ") + name + " must be finite and >= 0, got " + std::to_string(value));
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const auto [a, b] = pairs[k];
        const std::string name = "topology_cut: connected pair " + std::to_string(k) + " (" + std::to_string(a) + ", " + std::to_string(b) + ")";
        for (const std::uint32_t i : {a, b})
            if (i >= instances.size())
                throw invalid_input(name + " names instance " + std::to_string(i) + ", out of range for " + std::to_string(instances.size()) +
                                    " instances");
        if (a == b) throw invalid_input(name + " pairs an instance with itself");
    }
}

/// Phase 1 with Q given in a frame of its own: Q is moved into P's frame by q_in_p, split there,
/// and its new vertices moved back (its old ones keep their exact coordinates).
[[nodiscard]] inline pair_crossings split_at_crossings_in_frames(skeleton& P, skeleton& Q, const rigid_motion2& q_in_p) {
    skeleton moved = moved_copy(Q, q_in_p);
    pair_crossings x = split_at_crossings(P, moved);
    if (x.sites.empty()) return x;
    const rigid_motion2 back = q_in_p.inverse();
    for (vertex_id v = 0; v < moved.num_vertices(); ++v) moved.set_position(v, v < Q.num_vertices() ? Q.position(v) : back(moved.position(v)));
    Q = std::move(moved);
    return x;
}

/// All four phases for one connected pair (p, q).
inline void cut_pair(std::vector<skeleton>& instances, std::uint32_t p, std::uint32_t q, const topology_cut_options& opt,
                     pattern_contacts& contacts, topology_cut_report& report, const instance_frames* frames = nullptr) {
    pair_crossings x;
    if (!frames) {
        x = split_at_crossings(instances[p], instances[q]);
    } else if (const std::optional<rigid_motion2> q_in_p = frames->pose(p, q)) {
        x = split_at_crossings_in_frames(instances[p], instances[q], *q_in_p);
    }
    if (x.sites.empty()) return;
    contacts.refresh(p);
    contacts.refresh(q);
    double widest = 0.0;
    for (const crossing_site& s : x.sites) widest = std::max(widest, s.width);
    const double close = threshold(opt.close_intersections, topology_cut_options::close_width_factor, widest);
    const site_clusters clusters = cluster_close_crossings(instances[p], instances[q], x, close);
    cut_conflicting_branches(instances, p, q, x, clusters, opt, contacts, report);
    trim_protrusions(instances, p, q, x, clusters, opt, contacts, report);
}

}  // namespace detail::topocut

/// Topology cut (§4.5) of the element instances, in place: for every connected pair (P, Q), in
/// the given order, splits both skeletons at their crossings, removes the less important of each
/// pair of conflicting branches between close crossings (case 2, eq. 4) and trims protrusions
/// beyond single crossings (case 1), refusing every cut that would disconnect the pattern (see
/// the file comment for the phases and for what "connected" means; an instance may end in pieces).
/// @param instances       skeletons of the element instances in world coordinates (mm); edited:
///                        edges are split (new vertices) and removed (dead slots), never moved
/// @param connected_pairs indices (P, Q) into instances, P != Q, in processing order
/// @param opt             thresholds (mm) and the weights of eq. 4
/// @return counts of the cuts made and refused
/// Throws invalid_input naming the pair for an index out of range or P == Q, and naming the
/// option for a non-finite threshold or a weight that is not finite and >= 0; nothing is changed
/// then.
inline topology_cut_report topology_cut(std::vector<graph::skeleton_graph<vec2>>& instances,
                                        std::span<const std::pair<std::uint32_t, std::uint32_t>> connected_pairs,
                                        const topology_cut_options& opt = {}) {
    detail::topocut::check_input(instances, connected_pairs, opt);
    topology_cut_report report;
    if (connected_pairs.empty()) return report;
    detail::topocut::pattern_contacts contacts(instances);
    for (const auto& [p, q] : connected_pairs) detail::topocut::cut_pair(instances, p, q, opt, contacts, report);
    return report;
}

/// The same cut for instances whose skeletons are each given in a frame of their own (the local
/// parameterizations of a surface, filigree/surface/topology_cut.hpp): the crossings of a pair
/// (P, Q) are found with Q moved into P's frame by frames.pose(P, Q) (a pair without a pose is
/// skipped), and two instances a < b touch when their strips touch in a's frame. Lengths, and so
/// the clusters, importances and protrusions, do not depend on the frame. New vertices of Q are
/// given in Q's frame.
/// @param instances       skeletons, each in its own frame (mm); edited as by topology_cut
/// @param connected_pairs indices (P, Q) into instances, P != Q, in processing order
/// @param frames          poses between frames and the neighbours of each instance; must outlive the call
/// Throws as topology_cut.
inline topology_cut_report topology_cut_in_frames(std::vector<graph::skeleton_graph<vec2>>& instances,
                                                  std::span<const std::pair<std::uint32_t, std::uint32_t>> connected_pairs,
                                                  const instance_frames& frames, const topology_cut_options& opt = {}) {
    detail::topocut::check_input(instances, connected_pairs, opt);
    if (!frames.pose || !frames.neighbours) throw invalid_input("topology_cut_in_frames: the frames need a pose and a neighbours function");
    topology_cut_report report;
    if (connected_pairs.empty()) return report;
    detail::topocut::pattern_contacts contacts(instances, &frames);
    for (const auto& [p, q] : connected_pairs) detail::topocut::cut_pair(instances, p, q, opt, contacts, report, &frames);
    return report;
}

}  // namespace fabsynth::filigree
