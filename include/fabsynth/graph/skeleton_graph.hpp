// SPDX-License-Identifier: MIT
#pragma once
/// @file skeleton_graph.hpp  Editable skeleton graphs: vertices with a position and a width, joined
/// by straight edges (filigree-synthesis.md §3.3 skeletons of elements, §4.3 the connectivity graph
/// that synthesis edits).
///
/// Usage:
///   using fabsynth::graph::skeleton_graph;
///   std::vector<fabsynth::graph::skeleton_polyline<fabsynth::vec2>> lines = ...;
///   auto s = fabsynth::graph::skeleton_from_polylines(lines, 1e-6);   // weld endpoints within 1e-6 mm
///   s.valence(v);                         // number of edges at v
///   for (auto& b : s.branches()) ...;     // vertex runs between junctions/ends (valence != 2)
///   s.total_length();                     // mm
///   auto e = s.add_edge(u, v);  s.remove_edge(e);
///
/// Storage: vertices are never removed (ids stay valid); edges get ids 0, 1, ... in creation order
/// and a removed edge keeps its id as a dead slot (edge_alive() is false), so edge masks and edge
/// payloads held by the caller stay aligned. Parallel edges are allowed, self loops are not.
/// Edge lengths are Euclidean distances between the endpoint positions (mm).
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/graph/csr_graph.hpp"

namespace fabsynth::graph {

/// A position type: glm::distance applies (glm vec2/vec3, float or double).
template <class P>
concept skeleton_point = requires(const P& a, const P& b) {
    { glm::distance(a, b) } -> std::convertible_to<double>;
};

/// Edge index of a skeleton graph.
using edge_id = std::uint32_t;
inline constexpr edge_id no_edge = 0xffffffffu;

/// A vertex of a skeleton: position (mm) and width (mm, the stroke width around it).
template <skeleton_point P>
struct skeleton_vertex {
    P position{};
    double width = 0.0;
};

/// A polyline with one width per point (or no widths: every width is 0).
template <skeleton_point P>
struct skeleton_polyline {
    std::vector<P> points;
    std::vector<double> widths;
};

/// A run of edges between two vertices of valence != 2 (or a cycle of valence-2 vertices).
struct skeleton_branch {
    std::vector<vertex_id> vertices;  ///< in walking order; closed branches repeat the first vertex at the end
    std::vector<edge_id> edges;       ///< edges[i] joins vertices[i] and vertices[i + 1]
    [[nodiscard]] bool closed() const noexcept { return vertices.size() > 1 && vertices.front() == vertices.back(); }
};

/// Editable undirected skeleton graph over positions of type P.
template <skeleton_point P>
class skeleton_graph {
public:
    using point_type = P;

    /// Adds a vertex; returns its id. Throws invalid_input for a non-finite position or a width
    /// that is not finite and >= 0.
    vertex_id add_vertex(const P& position, double width = 0.0) {
        if (!all_finite(position)) throw invalid_input("skeleton_graph: vertex " + std::to_string(vertices_.size()) + " has a non-finite position");
        if (!(std::isfinite(width) && width >= 0.0))
            throw invalid_input("skeleton_graph: vertex " + std::to_string(vertices_.size()) + " has width " + std::to_string(width) +
                                "; widths must be finite and >= 0");
        if (vertices_.size() >= max_vertices) throw invalid_input("skeleton_graph: too many vertices");
        vertices_.push_back({position, width});
        incident_.emplace_back();
        return static_cast<vertex_id>(vertices_.size() - 1);
    }
    /// Moves vertex v (edges follow). Throws invalid_input for an id out of range or a non-finite
    /// position.
    void set_position(vertex_id v, const P& position) {
        if (v >= vertices_.size()) throw invalid_input("skeleton_graph: cannot move vertex " + std::to_string(v) + ": no such vertex");
        if (!all_finite(position)) throw invalid_input("skeleton_graph: vertex " + std::to_string(v) + " moved to a non-finite position");
        vertices_[v].position = position;
    }
    /// Adds the edge u-v; returns its id. Throws invalid_input for an id out of range or u == v.
    edge_id add_edge(vertex_id u, vertex_id v) {
        for (const vertex_id x : {u, v})
            if (x >= vertices_.size())
                throw invalid_input("skeleton_graph: edge " + std::to_string(u) + "-" + std::to_string(v) + " uses vertex " + std::to_string(x) +
                                    ", out of range for " + std::to_string(vertices_.size()) + " vertices");
        if (u == v) throw invalid_input("skeleton_graph: edge " + std::to_string(u) + "-" + std::to_string(v) + " is a self loop");
        if (edges_.size() >= no_edge) throw invalid_input("skeleton_graph: too many edges");
        const auto e = static_cast<edge_id>(edges_.size());
        edges_.push_back({u, v, true});
        incident_[u].push_back(e);
        incident_[v].push_back(e);
        ++alive_;
        return e;
    }
    /// Removes edge e (its id becomes a dead slot). Throws invalid_input if e is out of range or
    /// already removed. O(valence).
    void remove_edge(edge_id e) {
        if (e >= edges_.size() || !edges_[e].alive)
            throw invalid_input("skeleton_graph: cannot remove edge " + std::to_string(e) + ": no such live edge");
        edges_[e].alive = false;
        for (const vertex_id x : {edges_[e].u, edges_[e].v}) {
            auto& inc = incident_[x];
            inc.erase(std::find(inc.begin(), inc.end(), e));
        }
        --alive_;
    }
    /// Live edge between u and v with the smallest id, or no_edge. O(valence(u)).
    [[nodiscard]] edge_id find_edge(vertex_id u, vertex_id v) const {
        edge_id best = no_edge;
        for (const edge_id e : incident_.at(u))
            if (other(e, u) == v) best = std::min(best, e);
        return best;
    }

    [[nodiscard]] std::size_t num_vertices() const noexcept { return vertices_.size(); }
    /// Live edges.
    [[nodiscard]] std::size_t num_edges() const noexcept { return alive_; }
    /// Edge ids ever created (live and dead): the size of an edge mask.
    [[nodiscard]] std::size_t edge_slots() const noexcept { return edges_.size(); }
    [[nodiscard]] bool edge_alive(edge_id e) const noexcept { return e < edges_.size() && edges_[e].alive; }

    [[nodiscard]] const skeleton_vertex<P>& vertex(vertex_id v) const { return vertices_.at(v); }
    [[nodiscard]] const P& position(vertex_id v) const { return vertices_.at(v).position; }
    [[nodiscard]] double width(vertex_id v) const { return vertices_.at(v).width; }
    /// Endpoints of edge e (live or dead), smaller creation argument first.
    [[nodiscard]] std::pair<vertex_id, vertex_id> endpoints(edge_id e) const { return {edges_.at(e).u, edges_.at(e).v}; }
    /// The endpoint of e that is not x.
    [[nodiscard]] vertex_id other(edge_id e, vertex_id x) const { return edges_[e].u == x ? edges_[e].v : edges_[e].u; }
    /// Live edges at v in creation order.
    [[nodiscard]] std::span<const edge_id> incident(vertex_id v) const { return incident_.at(v); }
    /// Number of live edges at v.
    [[nodiscard]] std::size_t valence(vertex_id v) const { return incident_.at(v).size(); }
    /// Length of edge e (mm).
    [[nodiscard]] double length(edge_id e) const {
        return static_cast<double>(glm::distance(vertices_[edges_.at(e).u].position, vertices_[edges_.at(e).v].position));
    }

    /// Total length of the live edges (mm), summed in edge id order.
    [[nodiscard]] double total_length() const {
        double s = 0.0;
        for (edge_id e = 0; e < edges_.size(); ++e)
            if (edges_[e].alive) s += length(e);
        return s;
    }
    /// Total length of the live edges e with edge_mask[e] != 0 (edge_mask: edge_slots() entries).
    [[nodiscard]] double total_length_of_edges(std::span<const std::uint8_t> edge_mask) const {
        if (edge_mask.size() != edges_.size())
            throw invalid_input("skeleton_graph: edge mask has " + std::to_string(edge_mask.size()) + " entries for " + std::to_string(edges_.size()) +
                                " edge slots");
        double s = 0.0;
        for (edge_id e = 0; e < edges_.size(); ++e)
            if (edges_[e].alive && edge_mask[e]) s += length(e);
        return s;
    }
    /// Total length of the live edges with both endpoints selected by vertex_mask (num_vertices()
    /// entries): the length of the induced subgraph.
    [[nodiscard]] double total_length_of_vertices(std::span<const std::uint8_t> vertex_mask) const {
        if (vertex_mask.size() != vertices_.size())
            throw invalid_input("skeleton_graph: vertex mask has " + std::to_string(vertex_mask.size()) + " entries for " +
                                std::to_string(vertices_.size()) + " vertices");
        double s = 0.0;
        for (edge_id e = 0; e < edges_.size(); ++e)
            if (edges_[e].alive && vertex_mask[edges_[e].u] && vertex_mask[edges_[e].v]) s += length(e);
        return s;
    }

    /// Branches: maximal runs of live edges whose interior vertices have valence 2. Open branches
    /// start at a vertex of valence != 2 (junction or end), in increasing vertex id, leaving along its
    /// edges in creation order; a run may come back to its start (a loop at a junction, closed()).
    /// Then every remaining cycle of valence-2 vertices is one closed branch, starting at its smallest
    /// vertex id and leaving along that vertex's smaller edge id. Every live edge is in exactly one
    /// branch. O(V + E).
    [[nodiscard]] std::vector<skeleton_branch> branches() const {
        std::vector<skeleton_branch> out;
        std::vector<std::uint8_t> used(edges_.size(), 0);
        auto walk = [&](vertex_id start, edge_id first) {
            skeleton_branch b;
            b.vertices.push_back(start);
            vertex_id x = start;
            edge_id e = first;
            for (;;) {
                used[e] = 1;
                b.edges.push_back(e);
                x = other(e, x);
                b.vertices.push_back(x);
                if (x == start || valence(x) != 2) break;
                const auto inc = incident(x);
                const edge_id next = inc[0] == e ? inc[1] : inc[0];
                if (used[next]) break;  // parallel pair closing back (cannot happen: valence 2, already walked both)
                e = next;
            }
            out.push_back(std::move(b));
        };
        for (vertex_id v = 0; v < vertices_.size(); ++v) {
            if (valence(v) == 2) continue;
            for (const edge_id e : incident(v))
                if (!used[e]) walk(v, e);
        }
        for (vertex_id v = 0; v < vertices_.size(); ++v) {
            if (valence(v) != 2) continue;
            const auto inc = incident(v);
            if (used[inc[0]]) continue;
            walk(v, std::min(inc[0], inc[1]));
        }
        return out;
    }

    /// The graph in CSR form (undirected, weights = edge lengths), e.g. for shortest paths or
    /// colouring. Vertex ids are kept; dead edges are left out.
    [[nodiscard]] csr_graph<> to_csr() const {
        std::vector<edge_record<>> list;
        list.reserve(alive_);
        for (edge_id e = 0; e < edges_.size(); ++e)
            if (edges_[e].alive) list.push_back({edges_[e].u, edges_[e].v, length(e)});
        return build_csr(vertices_.size(), list);
    }

private:
    struct edge_rec {
        vertex_id u, v;
        bool alive;
    };
    std::vector<skeleton_vertex<P>> vertices_;
    std::vector<edge_rec> edges_;
    std::vector<std::vector<edge_id>> incident_;
    std::size_t alive_ = 0;
};

/// Skeleton graph of polylines: consecutive points of a polyline are joined by edges; the two
/// endpoints of every polyline are welded to an existing endpoint vertex within `tolerance` (mm,
/// Euclidean), so polylines sharing an endpoint meet in one vertex (a junction when three or more
/// meet). Welding is greedy in input order: an endpoint joins the earliest-created endpoint vertex
/// within tolerance and keeps that vertex's position and width. Interior points are never welded. A
/// polyline whose last point welds to its own first point closes a loop. Consecutive repeated points
/// (distance <= tolerance) are skipped.
/// @param lines      polylines of >= 2 points each; widths empty or one per point (finite, >= 0)
/// @param tolerance  weld distance (mm), finite and >= 0
/// Throws invalid_input naming the polyline for fewer than 2 points, a width count mismatch,
/// non-finite input or a polyline that collapses to a point. Time O(L * K + points) for L lines and K
/// endpoint vertices.
template <skeleton_point P>
[[nodiscard]] skeleton_graph<P> skeleton_from_polylines(std::span<const skeleton_polyline<P>> lines, double tolerance = 0.0) {
    if (!(std::isfinite(tolerance) && tolerance >= 0.0))
        throw invalid_input("skeleton_from_polylines: tolerance " + std::to_string(tolerance) + " must be finite and >= 0");
    skeleton_graph<P> s;
    std::vector<vertex_id> ends;  // endpoint vertices, in creation order
    auto endpoint = [&](const P& p, double w) {
        for (const vertex_id v : ends)
            if (static_cast<double>(glm::distance(s.position(v), p)) <= tolerance) return v;
        const vertex_id v = s.add_vertex(p, w);
        ends.push_back(v);
        return v;
    };
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const auto& l = lines[i];
        const std::string name = "skeleton_from_polylines: polyline " + std::to_string(i);
        if (l.points.size() < 2) throw invalid_input(name + " has " + std::to_string(l.points.size()) + " points; at least 2 are needed");
        if (!l.widths.empty() && l.widths.size() != l.points.size())
            throw invalid_input(name + " has " + std::to_string(l.widths.size()) + " widths for " + std::to_string(l.points.size()) + " points");
        for (std::size_t k = 0; k < l.points.size(); ++k) {
            if (!all_finite(l.points[k])) throw invalid_input(name + ": point " + std::to_string(k) + " is not finite");
            if (!l.widths.empty() && !(std::isfinite(l.widths[k]) && l.widths[k] >= 0.0))
                throw invalid_input(name + ": width " + std::to_string(k) + " must be finite and >= 0");
        }
        auto width = [&](std::size_t k) { return l.widths.empty() ? 0.0 : l.widths[k]; };
        const std::size_t last = l.points.size() - 1;
        // Interior points that do not collapse onto their predecessor.
        const vertex_id first = endpoint(l.points[0], width(0));
        vertex_id prev = first;
        P prev_pos = s.position(first);
        for (std::size_t k = 1; k < last; ++k) {
            if (static_cast<double>(glm::distance(prev_pos, l.points[k])) <= tolerance) continue;
            const vertex_id v = s.add_vertex(l.points[k], width(k));
            s.add_edge(prev, v);
            prev = v, prev_pos = l.points[k];
        }
        const vertex_id end = endpoint(l.points[last], width(last));
        if (end == prev) {
            if (prev == first) throw invalid_input(name + " collapses to a point within the tolerance");
            continue;  // the last point repeats the previous one
        }
        s.add_edge(prev, end);
    }
    return s;
}

/// skeleton_from_polylines for a std::vector of polylines.
template <skeleton_point P>
[[nodiscard]] skeleton_graph<P> skeleton_from_polylines(const std::vector<skeleton_polyline<P>>& lines, double tolerance = 0.0) {
    return skeleton_from_polylines<P>(std::span<const skeleton_polyline<P>>(lines), tolerance);
}

}  // namespace fabsynth::graph
