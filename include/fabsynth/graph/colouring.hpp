// SPDX-License-Identifier: MIT
#pragma once
/// @file colouring.hpp  Greedy graph colouring into independent sets (filigree-synthesis.md §4.5:
/// the update order of Algorithm 1 moves one independent set of elements at a time).
///
/// Usage:
///   auto c = fabsynth::graph::greedy_colouring(connectivity);                        // vertex order
///   auto d = fabsynth::graph::greedy_colouring(connectivity, fabsynth::graph::largest_degree_first{});
///   for (const auto& set : c.sets) update_in_parallel(set);     // no two vertices of a set adjacent
///
/// Greedy rule: vertices are visited in the order given by the order policy; each takes the
/// smallest colour not used by an already coloured neighbour. The result is deterministic for a
/// given graph and policy and uses at most (max degree + 1) colours. Arcs are read in both
/// directions, so a directed graph is coloured as its underlying undirected graph.
/// Time O(V + E) after the order, memory O(V + E) for directed graphs, O(V) otherwise.
#include <algorithm>
#include <concepts>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/graph/csr_graph.hpp"

namespace fabsynth::graph {

/// An order policy: called with the graph, returns a permutation of 0..n-1 (checked).
template <class O, class G>
concept colouring_order = requires(const O& o, const G& g) {
    { o(g) } -> std::convertible_to<std::vector<vertex_id>>;
};

/// Vertices in increasing id (the default).
struct vertex_order {
    template <class P>
    std::vector<vertex_id> operator()(const csr_graph<P>& g) const {
        std::vector<vertex_id> order(g.num_vertices());
        std::iota(order.begin(), order.end(), vertex_id{0});
        return order;
    }
};

/// Vertices by decreasing degree (Welsh-Powell), ties by increasing id. Often fewer colours.
struct largest_degree_first {
    template <class P>
    std::vector<vertex_id> operator()(const csr_graph<P>& g) const {
        std::vector<vertex_id> order = vertex_order{}(g);
        std::stable_sort(order.begin(), order.end(), [&](vertex_id a, vertex_id b) { return g.degree(a) > g.degree(b); });
        return order;
    }
};

/// Result of greedy_colouring.
struct colouring {
    std::vector<std::uint32_t> colour;         ///< per vertex
    std::vector<std::vector<vertex_id>> sets;  ///< vertices of each colour, increasing ids
    [[nodiscard]] std::size_t count() const noexcept { return sets.size(); }
};

/// Greedy colouring of g in the order of `order` (see the file comment). Throws invalid_input if
/// the order is not a permutation of the vertices.
template <class P, class Order = vertex_order>
    requires colouring_order<Order, csr_graph<P>>
[[nodiscard]] colouring greedy_colouring(const csr_graph<P>& g, const Order& order = {}) {
    const std::size_t n = g.num_vertices();
    const std::vector<vertex_id> seq = order(g);
    if (seq.size() != n)
        throw invalid_input("greedy_colouring: the order has " + std::to_string(seq.size()) + " vertices, the graph " + std::to_string(n));
    constexpr std::uint32_t uncoloured = 0xffffffffu;
    colouring r;
    r.colour.assign(n, uncoloured);
    // Directed graphs: add the reverse arcs so both endpoints of every arc see each other.
    std::vector<std::vector<vertex_id>> reverse;
    if (g.directed()) {
        reverse.resize(n);
        for (std::size_t v = 0; v < n; ++v)
            for (const vertex_id w : g.neighbours(static_cast<vertex_id>(v))) reverse[w].push_back(static_cast<vertex_id>(v));
    }
    std::vector<std::size_t> used_by(n + 1, static_cast<std::size_t>(-1));  // colour -> last vertex position marking it
    for (std::size_t k = 0; k < n; ++k) {
        const vertex_id v = seq[k];
        if (v >= n || r.colour[v] != uncoloured)
            throw invalid_input("greedy_colouring: the order is not a permutation (entry " + std::to_string(k) + " is " + std::to_string(v) + ")");
        auto mark = [&](vertex_id w) {
            if (r.colour[w] != uncoloured) used_by[r.colour[w]] = k;
        };
        for (const vertex_id w : g.neighbours(v)) mark(w);
        if (!reverse.empty())
            for (const vertex_id w : reverse[v]) mark(w);
        std::uint32_t c = 0;
        while (used_by[c] == k) ++c;
        r.colour[v] = c;
        if (c >= r.sets.size()) r.sets.resize(c + 1);
    }
    for (std::size_t v = 0; v < n; ++v) r.sets[r.colour[v]].push_back(static_cast<vertex_id>(v));
    return r;
}

}  // namespace fabsynth::graph
