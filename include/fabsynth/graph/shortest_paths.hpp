// SPDX-License-Identifier: MIT
#pragma once
/// @file shortest_paths.hpp  Multi-source shortest-path forests (Dijkstra), their extension to a
/// larger vertex set, paths to the roots, geodesic distances with early exit, and repeated
/// searches bounded by a radius (bounded_search).
///
/// Usage (structurally-sound-patterns.md Algorithm 5, steps 1 and 3):
///   auto forest = fabsynth::graph::dijkstra_forest(g_surface, samples, solid_mask);   // in G_solid
///   auto grown  = fabsynth::graph::extend_forest(g_surface, forest);                  // in G_surface
///   auto path   = fabsynth::graph::path_to_root(grown, v);       // v, parent(v), ..., its source
///   auto geo    = fabsynth::graph::geodesic(g_surface, a, b, solid_mask);   // §5.2.2; +inf if apart
///
/// Forest: tree t is grown from sources[t]; per vertex v, label[v] = t (the index of its source in
/// the sources list), parent[v] (no_vertex for sources), distance[v] (graph units, mm for voxel and
/// mesh graphs). Unreached vertices (outside the mask or in a part without a source) have label and
/// parent no_vertex and distance +inf.
///
/// Tie-breaking (deterministic; never depends on heap order or threads): vertices are settled in
/// increasing (distance, label, vertex id). A vertex v that is not a source takes the
/// lexicographically smallest (distance(u) + w(u, v), label[u], u) over its neighbours u settled
/// before it. With strictly positive weights every neighbour on a shortest path is settled first,
/// so: distance = the shortest distance to any source (floating-point sums along the path, in path
/// order), label = the smallest label among the tight neighbours (distance(u) + w == distance(v)),
/// parent = the smallest tight neighbour id with that label. Zero-weight edges are allowed; the rule
/// then only sees neighbours settled earlier, which keeps parents acyclic. Sources keep label t,
/// distance 0 and no parent even when another source is at distance 0 from them.
///
/// Complexity: O((V + E) log V) time with a binary heap, O(V) memory. Undirected graphs follow both
/// arcs; directed graphs follow arcs forwards.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <queue>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/graph/csr_graph.hpp"

namespace fabsynth::graph {

/// Shortest-path forest over the vertices of one graph (see the file comment).
struct shortest_path_forest {
    std::vector<vertex_id> sources;  ///< source vertex of each tree; the tree label is the index
    std::vector<vertex_id> label;    ///< per vertex: tree label, no_vertex = unreached
    std::vector<vertex_id> parent;   ///< per vertex: parent in its tree, no_vertex for sources/unreached
    std::vector<double> distance;    ///< per vertex: distance to its source, +inf = unreached

    [[nodiscard]] std::size_t num_vertices() const noexcept { return label.size(); }
    [[nodiscard]] std::size_t num_trees() const noexcept { return sources.size(); }
    [[nodiscard]] bool reached(vertex_id v) const noexcept { return label[v] != no_vertex; }
    /// Source vertex of the tree holding v (no_vertex if unreached).
    [[nodiscard]] vertex_id root(vertex_id v) const noexcept { return reached(v) ? sources[label[v]] : no_vertex; }
};

namespace detail {

struct heap_entry {
    double distance;
    vertex_id label;
    vertex_id vertex;
    /// Ordering for a min-heap on (distance, label, vertex).
    friend bool operator>(const heap_entry& a, const heap_entry& b) noexcept {
        if (a.distance != b.distance) return a.distance > b.distance;
        if (a.label != b.label) return a.label > b.label;
        return a.vertex > b.vertex;
    }
};
using min_heap = std::priority_queue<heap_entry, std::vector<heap_entry>, std::greater<heap_entry>>;

/// Grows f through `mask` from every reached vertex. Reached vertices on entry are frozen (their
/// label, parent and distance stay). Stops early once `stop` is settled (no_vertex: never).
template <class P>
void grow_forest(const csr_graph<P>& g, shortest_path_forest& f, vertex_mask mask, vertex_id stop = no_vertex) {
    const std::size_t n = g.num_vertices();
    std::vector<std::uint8_t> state(n, 0);  // 0 free, 1 frozen (never relaxed into), 2 settled
    min_heap heap;
    for (std::size_t v = 0; v < n; ++v)
        if (f.label[v] != no_vertex) state[v] = 1, heap.push({f.distance[v], f.label[v], static_cast<vertex_id>(v)});
    std::vector<std::uint8_t> settled(n, 0);
    while (!heap.empty()) {
        const heap_entry top = heap.top();
        heap.pop();
        const vertex_id u = top.vertex;
        if (settled[u] || top.distance != f.distance[u] || top.label != f.label[u]) continue;  // stale entry
        settled[u] = 1;
        if (u == stop) return;
        for (arc_id e = g.edge_begin(u); e < g.edge_end(u); ++e) {
            const vertex_id w = g.target(e);
            if (state[w] == 1 || settled[w] || !in_mask(mask, w)) continue;
            const double d = top.distance + g.weight(e);
            const bool better = d < f.distance[w] ||
                                (d == f.distance[w] && (top.label < f.label[w] || (top.label == f.label[w] && u < f.parent[w])));
            if (!better) continue;
            const bool key_changed = d != f.distance[w] || top.label != f.label[w];
            f.distance[w] = d, f.label[w] = top.label, f.parent[w] = u;
            if (key_changed) heap.push({d, top.label, w});
        }
    }
}

}  // namespace detail

/// Multi-source shortest-path forest restricted to a vertex mask (Algorithm 5 step 1).
/// @param g        graph (weights finite, >= 0)
/// @param sources  #S distinct vertex ids, each < n and inside the mask; tree t grows from sources[t]
/// @param mask     empty (all vertices) or n entries; only selected vertices are visited
/// Throws invalid_input for a bad mask size, a source out of range, outside the mask or repeated.
template <class P>
[[nodiscard]] shortest_path_forest dijkstra_forest(const csr_graph<P>& g, std::span<const vertex_id> sources, vertex_mask mask = {}) {
    const std::size_t n = g.num_vertices();
    detail::check_mask(mask, n, "dijkstra_forest");
    shortest_path_forest f;
    f.sources.assign(sources.begin(), sources.end());
    f.label.assign(n, no_vertex);
    f.parent.assign(n, no_vertex);
    f.distance.assign(n, std::numeric_limits<double>::infinity());
    for (std::size_t t = 0; t < sources.size(); ++t) {
        const vertex_id s = sources[t];
        if (s >= n)
            throw invalid_input("dijkstra_forest: source " + std::to_string(t) + " is vertex " + std::to_string(s) + ", out of range for " +
                                std::to_string(n) + " vertices");
        if (!detail::in_mask(mask, s))
            throw invalid_input("dijkstra_forest: source " + std::to_string(t) + " (vertex " + std::to_string(s) + ") is outside the mask");
        if (f.label[s] != no_vertex)
            throw invalid_input("dijkstra_forest: vertex " + std::to_string(s) + " is both source " + std::to_string(f.label[s]) + " and source " +
                                std::to_string(t));
        f.label[s] = static_cast<vertex_id>(t);
        f.distance[s] = 0.0;
    }
    detail::grow_forest(g, f, mask);
    return f;
}

/// Overload for a std::vector of sources.
template <class P>
[[nodiscard]] shortest_path_forest dijkstra_forest(const csr_graph<P>& g, const std::vector<vertex_id>& sources, vertex_mask mask = {}) {
    return dijkstra_forest(g, std::span<const vertex_id>(sources), mask);
}

/// Extends a forest computed on a smaller mask through `larger` (Algorithm 5 step 3): every vertex
/// reached by `f` keeps its label, parent and distance; the trees grow further through the free
/// vertices of `larger`, each free vertex taking the tie rule of the file comment with the frozen
/// vertices' distances. Every vertex reached by f must be in `larger` (empty = all vertices).
/// Throws invalid_input if f does not belong to g or the mask does not contain f.
template <class P>
[[nodiscard]] shortest_path_forest extend_forest(const csr_graph<P>& g, shortest_path_forest f, vertex_mask larger = {}) {
    const std::size_t n = g.num_vertices();
    detail::check_mask(larger, n, "extend_forest");
    if (f.label.size() != n || f.parent.size() != n || f.distance.size() != n)
        throw invalid_input("extend_forest: the forest has " + std::to_string(f.label.size()) + " vertices but the graph has " + std::to_string(n));
    for (std::size_t v = 0; v < n; ++v)
        if (f.label[v] != no_vertex && !detail::in_mask(larger, v))
            throw invalid_input("extend_forest: vertex " + std::to_string(v) + " is in the forest but outside the larger mask");
    detail::grow_forest(g, f, larger);
    return f;
}

/// Path from v to the source of its tree: v, parent(v), ..., source. Empty if v is unreached.
/// O(path length).
[[nodiscard]] inline std::vector<vertex_id> path_to_root(const shortest_path_forest& f, vertex_id v) {
    std::vector<vertex_id> path;
    if (v >= f.num_vertices() || !f.reached(v)) return path;
    for (vertex_id x = v; x != no_vertex; x = f.parent[x]) {
        path.push_back(x);
        FABSYNTH_ASSERT(path.size() <= f.num_vertices());
    }
    return path;
}

/// A shortest path between two vertices.
struct geodesic_path {
    double length = std::numeric_limits<double>::infinity();  ///< +inf if disconnected
    std::vector<vertex_id> vertices;                          ///< from a to b; empty if disconnected
    [[nodiscard]] bool connected() const noexcept { return !vertices.empty(); }
};

/// Geodesic distance and path from a to b inside a mask (§5.2.2: geodesic length in G_solid).
/// Dijkstra from a with the tie rule above (a single tree), stopping as soon as b is settled.
/// Returns length +inf and no vertices if b cannot be reached inside the mask. Throws invalid_input
/// if a or b is out of range or outside the mask. O((V + E) log V) worst case, O(V) memory.
template <class P>
[[nodiscard]] geodesic_path geodesic(const csr_graph<P>& g, vertex_id a, vertex_id b, vertex_mask mask = {}) {
    const std::size_t n = g.num_vertices();
    detail::check_mask(mask, n, "geodesic");
    for (vertex_id v : {a, b}) {
        if (v >= n) throw invalid_input("geodesic: vertex " + std::to_string(v) + " is out of range for " + std::to_string(n) + " vertices");
        if (!detail::in_mask(mask, v)) throw invalid_input("geodesic: vertex " + std::to_string(v) + " is outside the mask");
    }
    shortest_path_forest f;
    f.sources = {a};
    f.label.assign(n, no_vertex);
    f.parent.assign(n, no_vertex);
    f.distance.assign(n, std::numeric_limits<double>::infinity());
    f.label[a] = 0, f.distance[a] = 0.0;
    detail::grow_forest(g, f, mask, b);
    geodesic_path r;
    if (!f.reached(b)) return r;
    r.length = f.distance[b];
    r.vertices = path_to_root(f, b);
    std::reverse(r.vertices.begin(), r.vertices.end());
    return r;
}

/// Geodesic distances from one vertex to the vertices closer than a radius (Dijkstra stopped at
/// the radius), run many times over one graph: the distance array is reset only where the last
/// run wrote, so a run costs O(k log k) for the k vertices it reaches, not O(V).
/// The graph is any adjacency given by a callable: neighbours(v, visit) calls visit(w, length)
/// for every neighbour w of v (length finite, >= 0), so graphs other than csr_graph (the filigree
/// skeletons) use it as they are. Vertices are reported in increasing distance (ties by the heap:
/// deterministic for one input).
///   graph::bounded_search near(n);
///   near.run(source, 2.5, [&](vertex_id v, auto&& visit) { for (...) visit(w, len); }, [&](vertex_id v) { ... });
class bounded_search {
public:
    explicit bounded_search(std::size_t vertices) : distance_(vertices, std::numeric_limits<double>::infinity()) {}

    /// Calls found(v) for every vertex v whose geodesic distance from `source` is < radius.
    template <class Neighbours, class Found>
    void run(vertex_id source, double radius, Neighbours&& neighbours, Found&& found) {
        constexpr double infinity = std::numeric_limits<double>::infinity();
        if (source >= distance_.size())
            throw invalid_input("bounded_search: vertex " + std::to_string(source) + " is out of range for " + std::to_string(distance_.size()) +
                                " vertices");
        for (const vertex_id v : touched_) distance_[v] = infinity;
        touched_.clear();
        using entry = std::pair<double, vertex_id>;
        std::priority_queue<entry, std::vector<entry>, std::greater<entry>> heap;
        distance_[source] = 0.0;
        touched_.push_back(source);
        heap.push({0.0, source});
        while (!heap.empty()) {
            // not a structured binding: clang 14 cannot capture one in the lambda below
            const double d = heap.top().first;
            const vertex_id v = heap.top().second;
            heap.pop();
            if (d > distance_[v]) continue;
            found(v);
            neighbours(v, [&](vertex_id w, double length) {
                const double dw = d + length;
                if (!(dw < radius) || !(dw < distance_[w])) return;
                if (distance_[w] == infinity) touched_.push_back(w);
                distance_[w] = dw;
                heap.push({dw, w});
            });
        }
    }

    /// The same over a csr_graph (its weights are the lengths).
    template <class P, class Found>
    void run(const csr_graph<P>& g, vertex_id source, double radius, Found&& found) {
        run(source, radius, [&](vertex_id v, auto&& visit) {
            for (arc_id e = g.edge_begin(v); e < g.edge_end(v); ++e) visit(g.target(e), g.weight(e));
        }, std::forward<Found>(found));
    }

private:
    std::vector<double> distance_;
    std::vector<vertex_id> touched_;
};

}  // namespace fabsynth::graph
