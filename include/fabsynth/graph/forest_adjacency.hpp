// SPDX-License-Identifier: MIT
#pragma once
/// @file forest_adjacency.hpp  Which trees of a shortest-path forest touch, and through which edge
/// (structurally-sound-patterns.md Algorithm 5, steps 2 and 4).
///
/// Usage:
///   auto solid = fabsynth::graph::forest_adjacency(g, forest, solid_mask);          // step 2
///   auto grown = fabsynth::graph::extend_forest(g, forest);
///   auto empty = fabsynth::graph::forest_adjacency(g, grown, {}, {.skip = solid});   // step 4
///   for (const auto& t : empty) use(t.tree_u, t.tree_v, t.path);   // path: root_u ... a b ... root_v
///
/// Two trees u < v (tree labels, i.e. indices into forest.sources) are adjacent if some arc a -> b
/// of the graph has both endpoints inside the mask, reached, with label[a] = u and label[b] = v (or
/// the other way round; the record always puts the tree-u endpoint first). Each adjacent pair gives
/// one record. Its edge is the one minimising distance[a] + w + distance[b] (summed in that order,
/// a in tree u); ties go to the smaller a, then the smaller b, then the lighter parallel arc.
/// Records are sorted by (tree_u, tree_v). Time O(V + E + P log P) for P candidate arcs between
/// trees, plus the lengths of the recorded paths; memory O(P).
#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/graph/csr_graph.hpp"
#include "fabsynth/graph/shortest_paths.hpp"

namespace fabsynth::graph {

/// One pair of adjacent trees and the edge chosen to connect them.
struct tree_adjacency {
    vertex_id tree_u = no_vertex;  ///< smaller tree label
    vertex_id tree_v = no_vertex;  ///< larger tree label
    vertex_id a = no_vertex;       ///< endpoint of the edge in tree u
    vertex_id b = no_vertex;       ///< endpoint of the edge in tree v
    double weight = 0.0;           ///< weight of the edge a-b
    double length = 0.0;           ///< distance[a] + weight + distance[b]
    std::vector<vertex_id> path;   ///< sources[u] ... a b ... sources[v] (empty unless record_paths)
};

/// Options of forest_adjacency.
struct forest_adjacency_options {
    /// Pairs already connected (e.g. the solid edges of step 2); only their tree labels are read,
    /// in either order.
    std::span<const tree_adjacency> skip = {};
    bool record_paths = true;  ///< fill tree_adjacency::path
};

/// Adjacent tree pairs of `f` in g restricted to `mask` (empty = all vertices). See the file comment.
/// Throws invalid_input if f does not belong to g or the mask size is wrong.
template <class P>
[[nodiscard]] std::vector<tree_adjacency> forest_adjacency(const csr_graph<P>& g, const shortest_path_forest& f, vertex_mask mask = {},
                                                           forest_adjacency_options opt = {}) {
    const std::size_t n = g.num_vertices();
    detail::check_mask(mask, n, "forest_adjacency");
    if (f.label.size() != n || f.distance.size() != n || f.parent.size() != n)
        throw invalid_input("forest_adjacency: the forest has " + std::to_string(f.label.size()) + " vertices but the graph has " +
                            std::to_string(n));
    auto pair_key = [](vertex_id u, vertex_id v) { return (std::uint64_t{std::min(u, v)} << 32) | std::max(u, v); };
    std::vector<std::uint64_t> skip;
    skip.reserve(opt.skip.size());
    for (const auto& s : opt.skip) skip.push_back(pair_key(s.tree_u, s.tree_v));
    std::sort(skip.begin(), skip.end());

    struct candidate {
        std::uint64_t key;
        double length;
        vertex_id a, b;
        double weight;
    };
    std::vector<candidate> cand;
    for (std::size_t x = 0; x < n; ++x) {
        const vertex_id lx = f.label[x];
        if (lx == no_vertex || !detail::in_mask(mask, x)) continue;
        for (arc_id e = g.edge_begin(static_cast<vertex_id>(x)); e < g.edge_end(static_cast<vertex_id>(x)); ++e) {
            const vertex_id y = g.target(e), ly = f.label[y];
            if (ly == no_vertex || ly == lx || !detail::in_mask(mask, y)) continue;
            const std::uint64_t key = pair_key(lx, ly);
            if (std::binary_search(skip.begin(), skip.end(), key)) continue;
            const vertex_id a = lx < ly ? static_cast<vertex_id>(x) : y, b = lx < ly ? y : static_cast<vertex_id>(x);
            const double w = g.weight(e);
            cand.push_back({key, f.distance[a] + w + f.distance[b], a, b, w});
        }
    }
    std::sort(cand.begin(), cand.end(), [](const candidate& p, const candidate& q) {
        if (p.key != q.key) return p.key < q.key;
        if (p.length != q.length) return p.length < q.length;
        if (p.a != q.a) return p.a < q.a;
        if (p.b != q.b) return p.b < q.b;
        return p.weight < q.weight;
    });
    std::vector<tree_adjacency> out;
    for (std::size_t i = 0; i < cand.size(); ++i) {
        if (i > 0 && cand[i].key == cand[i - 1].key) continue;
        const candidate& c = cand[i];
        tree_adjacency t;
        t.tree_u = static_cast<vertex_id>(c.key >> 32);
        t.tree_v = static_cast<vertex_id>(c.key & 0xffffffffu);
        t.a = c.a, t.b = c.b, t.weight = c.weight, t.length = c.length;
        if (opt.record_paths) {
            t.path = path_to_root(f, c.a);
            std::reverse(t.path.begin(), t.path.end());
            for (vertex_id x = c.b; x != no_vertex; x = f.parent[x]) t.path.push_back(x);
        }
        out.push_back(std::move(t));
    }
    return out;
}

}  // namespace fabsynth::graph
