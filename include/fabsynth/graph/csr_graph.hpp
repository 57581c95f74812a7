// SPDX-License-Identifier: MIT
#pragma once
/// @file csr_graph.hpp  Compact weighted graphs in compressed sparse row (CSR) form.
///
/// Usage:
///   std::vector<fabsynth::graph::edge_record<>> edges{{0, 1, 1.0}, {1, 2, 0.5}};
///   auto g = fabsynth::graph::build_csr(3, edges);              // undirected: both directions stored
///   for (auto e = g.edge_begin(v); e < g.edge_end(v); ++e) use(g.target(e), g.weight(e));
///   g.neighbours(1); g.neighbour_weights(1);                    // spans over the row of vertex 1
///
/// A graph has vertices 0..n-1 and arcs (directed edges) stored row by row: the arcs leaving v are
/// the indices [offsets[v], offsets[v+1]) into targets / weights / payloads. An undirected edge
/// {u, v} is stored as the two arcs u->v and v->u with the same weight and payload. Within a row
/// the arcs are sorted by target (parallel arcs: by weight, then by input order), so neighbour
/// order is deterministic. Weights are doubles, finite and >= 0 (mm for the geometric adaptors).
/// The optional per-edge Payload is stored per arc (no_payload, the default, takes no memory).
///
/// Limits: fewer than 2^32 - 1 vertices; arc counts are 64-bit.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"

namespace fabsynth::graph {

/// Vertex index.
using vertex_id = std::uint32_t;
/// Arc (directed edge) index into a CSR graph's arrays.
using arc_id = std::uint64_t;
/// "No vertex": unreached, no parent, not in the graph.
inline constexpr vertex_id no_vertex = std::numeric_limits<vertex_id>::max();
/// Largest supported vertex count.
inline constexpr std::size_t max_vertices = std::numeric_limits<vertex_id>::max() - 1;

/// The empty edge payload.
struct no_payload {
    friend constexpr bool operator==(no_payload, no_payload) noexcept { return true; }
};

/// One input edge source -> target with a weight (finite, >= 0) and an optional payload.
template <class Payload = no_payload>
struct edge_record {
    vertex_id source = 0;
    vertex_id target = 0;
    double weight = 0.0;
    [[no_unique_address]] Payload payload{};
};

/// Options of build_csr.
struct csr_options {
    bool directed = false;  ///< false: each edge is stored in both directions
};

/// Immutable graph in CSR form. Construct with build_csr() (edge list) or from_arrays() (CSR
/// arrays); both validate their input.
template <class Payload = no_payload>
class csr_graph {
public:
    using payload_type = Payload;
    static constexpr bool has_payload = !std::is_same_v<Payload, no_payload>;

    csr_graph() : offsets_(1, 0) {}

    /// Graph from CSR arrays: offsets (n + 1 entries, offsets[0] = 0, non-decreasing,
    /// offsets[n] = targets.size()), targets (each < n, no self loops, sorted within each row),
    /// weights (one per arc, finite, >= 0) and payloads (one per arc, or empty when Payload is
    /// no_payload). `directed` is recorded, not checked (an undirected graph must hold both arcs).
    /// Throws invalid_input naming the first bad entry. O(arcs).
    static csr_graph from_arrays(std::vector<arc_id> offsets, std::vector<vertex_id> targets, std::vector<double> weights,
                                 bool directed = false, std::vector<Payload> payloads = {}) {
        if (offsets.empty() || offsets.front() != 0)
            throw invalid_input("csr_graph: offsets must hold n + 1 entries starting with 0");
        const std::size_t n = offsets.size() - 1;
        if (n > max_vertices) throw invalid_input("csr_graph: " + std::to_string(n) + " vertices exceed the limit of 2^32 - 2");
        if (offsets.back() != targets.size())
            throw invalid_input("csr_graph: offsets end at " + std::to_string(offsets.back()) + " but there are " +
                                std::to_string(targets.size()) + " targets");
        if (weights.size() != targets.size())
            throw invalid_input("csr_graph: " + std::to_string(weights.size()) + " weights for " + std::to_string(targets.size()) + " arcs");
        if constexpr (has_payload) {
            if (payloads.size() != targets.size())
                throw invalid_input("csr_graph: " + std::to_string(payloads.size()) + " payloads for " + std::to_string(targets.size()) + " arcs");
        }
        for (std::size_t v = 0; v < n; ++v) {
            if (offsets[v + 1] < offsets[v]) throw invalid_input("csr_graph: offsets decrease at vertex " + std::to_string(v));
            for (arc_id e = offsets[v]; e < offsets[v + 1]; ++e) {
                const vertex_id t = targets[e];
                if (t >= n)
                    throw invalid_input("csr_graph: arc " + std::to_string(e) + " of vertex " + std::to_string(v) + " targets vertex " +
                                        std::to_string(t) + ", out of range for " + std::to_string(n) + " vertices");
                if (t == v) throw invalid_input("csr_graph: self loop at vertex " + std::to_string(v));
                if (e > offsets[v] && targets[e - 1] > t)
                    throw invalid_input("csr_graph: targets of vertex " + std::to_string(v) + " are not sorted");
                check_weight(weights[e], v, t);
            }
        }
        csr_graph g;
        g.offsets_ = std::move(offsets);
        g.targets_ = std::move(targets);
        g.weights_ = std::move(weights);
        if constexpr (has_payload) g.payloads_ = std::move(payloads);
        g.directed_ = directed;
        return g;
    }

    /// Number of vertices n.
    [[nodiscard]] std::size_t num_vertices() const noexcept { return offsets_.size() - 1; }
    /// Number of stored arcs (twice the edge count of an undirected graph).
    [[nodiscard]] std::size_t num_arcs() const noexcept { return targets_.size(); }
    /// Number of edges: arcs for a directed graph, arcs / 2 for an undirected one.
    [[nodiscard]] std::size_t num_edges() const noexcept { return directed_ ? targets_.size() : targets_.size() / 2; }
    [[nodiscard]] bool directed() const noexcept { return directed_; }

    /// Out-degree of v (number of arcs leaving v).
    [[nodiscard]] std::size_t degree(vertex_id v) const noexcept { return static_cast<std::size_t>(offsets_[v + 1] - offsets_[v]); }
    /// First arc of v; the arcs of v are [edge_begin(v), edge_end(v)).
    [[nodiscard]] arc_id edge_begin(vertex_id v) const noexcept { return offsets_[v]; }
    [[nodiscard]] arc_id edge_end(vertex_id v) const noexcept { return offsets_[v + 1]; }
    [[nodiscard]] vertex_id target(arc_id e) const noexcept { return targets_[e]; }
    [[nodiscard]] double weight(arc_id e) const noexcept { return weights_[e]; }
    [[nodiscard]] const Payload& payload(arc_id e) const noexcept
        requires has_payload
    {
        return payloads_[e];
    }
    /// Targets of v, sorted increasingly.
    [[nodiscard]] std::span<const vertex_id> neighbours(vertex_id v) const noexcept {
        return {targets_.data() + offsets_[v], degree(v)};
    }
    /// Weights of the arcs of v, parallel to neighbours(v).
    [[nodiscard]] std::span<const double> neighbour_weights(vertex_id v) const noexcept {
        return {weights_.data() + offsets_[v], degree(v)};
    }
    /// First arc u -> v, or num_arcs() if there is none. O(log degree(u)).
    [[nodiscard]] arc_id find_arc(vertex_id u, vertex_id v) const noexcept {
        const auto row = neighbours(u);
        const auto it = std::lower_bound(row.begin(), row.end(), v);
        return it != row.end() && *it == v ? offsets_[u] + static_cast<arc_id>(it - row.begin()) : num_arcs();
    }

    /// Raw CSR arrays (offsets: n + 1 entries).
    [[nodiscard]] std::span<const arc_id> offsets() const noexcept { return offsets_; }
    [[nodiscard]] std::span<const vertex_id> targets() const noexcept { return targets_; }
    [[nodiscard]] std::span<const double> weights() const noexcept { return weights_; }
    [[nodiscard]] std::span<const Payload> payloads() const noexcept
        requires has_payload
    {
        return payloads_;
    }

    /// Throws invalid_input unless w is finite and >= 0 (names the edge u-v).
    static void check_weight(double w, std::size_t u, std::size_t v) {
        if (!(std::isfinite(w) && w >= 0.0))
            throw invalid_input("csr_graph: edge " + std::to_string(u) + "-" + std::to_string(v) + " has weight " + std::to_string(w) +
                                "; weights must be finite and >= 0");
    }

private:
    struct none {};
    std::vector<arc_id> offsets_;
    std::vector<vertex_id> targets_;
    std::vector<double> weights_;
    [[no_unique_address]] std::conditional_t<has_payload, std::vector<Payload>, none> payloads_;
    bool directed_ = false;
};

/// Builds a CSR graph on n vertices from an edge list.
/// @param n      number of vertices (< 2^32 - 1)
/// @param edges  #E edges; source, target < n, source != target, weight finite and >= 0
/// @param opt    directed or undirected (default: undirected, both arcs stored)
/// Parallel edges are kept (sorted by weight, then input order). Throws invalid_input naming the
/// first bad edge by its index. Time O(n + E log E), memory O(n + E).
template <class Payload = no_payload>
[[nodiscard]] csr_graph<Payload> build_csr(std::size_t n, std::span<const edge_record<Payload>> edges, csr_options opt = {}) {
    if (n > max_vertices) throw invalid_input("build_csr: " + std::to_string(n) + " vertices exceed the limit of 2^32 - 2");
    for (std::size_t i = 0; i < edges.size(); ++i) {
        const auto& e = edges[i];
        if (e.source >= n || e.target >= n)
            throw invalid_input("build_csr: edge " + std::to_string(i) + " (" + std::to_string(e.source) + " -> " + std::to_string(e.target) +
                                ") has a vertex id out of range for " + std::to_string(n) + " vertices");
        if (e.source == e.target) throw invalid_input("build_csr: edge " + std::to_string(i) + " is a self loop at vertex " + std::to_string(e.source));
        if (!(std::isfinite(e.weight) && e.weight >= 0.0))
            throw invalid_input("build_csr: edge " + std::to_string(i) + " (" + std::to_string(e.source) + " -> " + std::to_string(e.target) +
                                ") has weight " + std::to_string(e.weight) + "; weights must be finite and >= 0 (NaN, inf and negative are rejected)");
    }
    const std::size_t arcs = opt.directed ? edges.size() : 2 * edges.size();
    std::vector<arc_id> offsets(n + 1, 0);
    for (const auto& e : edges) {
        ++offsets[e.source + 1];
        if (!opt.directed) ++offsets[e.target + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    // Counting sort by source keeps input order within a row; rows are then sorted stably.
    std::vector<std::uint64_t> order(arcs);  // (edge index << 1) | reversed
    {
        std::vector<arc_id> next(offsets.begin(), offsets.end() - 1);
        for (std::size_t i = 0; i < edges.size(); ++i) {
            order[next[edges[i].source]++] = std::uint64_t{i} << 1;
            if (!opt.directed) order[next[edges[i].target]++] = (std::uint64_t{i} << 1) | 1u;
        }
    }
    auto target_of = [&](std::uint64_t o) { return (o & 1u) ? edges[o >> 1].source : edges[o >> 1].target; };
    for (std::size_t v = 0; v < n; ++v)
        std::stable_sort(order.begin() + static_cast<std::ptrdiff_t>(offsets[v]), order.begin() + static_cast<std::ptrdiff_t>(offsets[v + 1]),
                         [&](std::uint64_t a, std::uint64_t b) {
                             const vertex_id ta = target_of(a), tb = target_of(b);
                             if (ta != tb) return ta < tb;
                             return edges[a >> 1].weight < edges[b >> 1].weight;
                         });
    std::vector<vertex_id> targets(arcs);
    std::vector<double> weights(arcs);
    std::vector<Payload> payloads;
    if constexpr (csr_graph<Payload>::has_payload) payloads.resize(arcs);
    for (std::size_t k = 0; k < arcs; ++k) {
        targets[k] = target_of(order[k]);
        weights[k] = edges[order[k] >> 1].weight;
        if constexpr (csr_graph<Payload>::has_payload) payloads[k] = edges[order[k] >> 1].payload;
    }
    return csr_graph<Payload>::from_arrays(std::move(offsets), std::move(targets), std::move(weights), opt.directed, std::move(payloads));
}

/// build_csr for a std::vector of edges (deduces Payload).
template <class Payload>
[[nodiscard]] csr_graph<Payload> build_csr(std::size_t n, const std::vector<edge_record<Payload>>& edges, csr_options opt = {}) {
    return build_csr<Payload>(n, std::span<const edge_record<Payload>>(edges), opt);
}

/// A vertex mask: mask[v] != 0 selects v. An empty mask selects every vertex; otherwise it must
/// hold one entry per vertex (checked by the algorithms taking one).
using vertex_mask = std::span<const std::uint8_t>;

namespace detail {
/// Throws invalid_input unless mask is empty or has n entries.
inline void check_mask(vertex_mask mask, std::size_t n, const char* who) {
    if (!mask.empty() && mask.size() != n)
        throw invalid_input(std::string(who) + ": vertex mask has " + std::to_string(mask.size()) + " entries for " + std::to_string(n) +
                            " vertices");
}
[[nodiscard]] inline bool in_mask(vertex_mask mask, std::size_t v) noexcept { return mask.empty() || mask[v] != 0; }
}  // namespace detail

}  // namespace fabsynth::graph
