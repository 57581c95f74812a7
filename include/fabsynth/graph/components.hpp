// SPDX-License-Identifier: MIT
#pragma once
/// @file components.hpp  Connected components of a graph restricted to a vertex mask.
///
/// Usage:
///   auto cc = fabsynth::graph::connected_components(g, solid_mask);
///   cc.count; cc.label[v]; cc.sizes[c];     // label no_vertex = outside the mask
///
/// Components are numbered 0, 1, ... in the order of their smallest vertex id (deterministic).
/// Two selected vertices are connected if a path of arcs between selected vertices joins them,
/// ignoring arc direction (weak components for directed graphs). Time O(V + E alpha(V)), memory O(V).
#include <cstdint>
#include <vector>

#include "fabsynth/core/union_find.hpp"
#include "fabsynth/graph/csr_graph.hpp"

namespace fabsynth::graph {

/// Result of connected_components.
struct graph_components {
    std::vector<vertex_id> label;    ///< per vertex: component, no_vertex = not selected
    std::size_t count = 0;           ///< number of components
    std::vector<std::size_t> sizes;  ///< vertices per component
};

/// Connected components of the vertices selected by mask (empty = all). Throws invalid_input for a
/// mask of the wrong size.
template <class P>
[[nodiscard]] graph_components connected_components(const csr_graph<P>& g, vertex_mask mask = {}) {
    const std::size_t n = g.num_vertices();
    detail::check_mask(mask, n, "connected_components");
    union_find uf(n);
    for (std::size_t v = 0; v < n; ++v) {
        if (!detail::in_mask(mask, v)) continue;
        for (const vertex_id w : g.neighbours(static_cast<vertex_id>(v)))
            if (detail::in_mask(mask, w)) uf.unite(static_cast<vertex_id>(v), w);
    }
    graph_components r;
    r.label.assign(n, no_vertex);
    for (std::size_t v = 0; v < n; ++v) {
        if (!detail::in_mask(mask, v)) continue;
        const vertex_id root = uf.find(static_cast<vertex_id>(v));  // smallest id of the set: labelled first
        if (root == v) r.label[v] = static_cast<vertex_id>(r.count++), r.sizes.push_back(0);
        else r.label[v] = r.label[root];
        ++r.sizes[r.label[v]];
    }
    return r;
}

}  // namespace fabsynth::graph
