#pragma once
// Random test graphs and brute-force oracles for tests/graph (no library algorithm is used here:
// only the edge_record type to hand edges to build_csr).
#include <fabsynth/core/rng.hpp>
#include <fabsynth/graph/csr_graph.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace fabsynth::test {

struct random_graph {
    std::size_t n = 0;
    std::vector<graph::edge_record<>> edges;  // undirected
};

/// n in [2, max_n], about density * n edges, no self loops (parallel edges possible). Weights are
/// small integers (many ties) when `integer_weights`, else uniform in [0.1, 2).
inline random_graph make_random_graph(std::uint64_t seed, std::size_t max_n, double density, bool integer_weights) {
    counter_rng rng(seed, 0x9a);
    random_graph g;
    g.n = 2 + static_cast<std::size_t>(rng.uniform_int(max_n - 1));
    const auto m = static_cast<std::size_t>(density * static_cast<double>(g.n));
    for (std::size_t k = 0; k < m; ++k) {
        const auto a = static_cast<graph::vertex_id>(rng.uniform_int(g.n));
        const auto b = static_cast<graph::vertex_id>(rng.uniform_int(g.n));
        if (a == b) continue;
        const double w = integer_weights ? static_cast<double>(1 + rng.uniform_int(3)) : 0.1 + 1.9 * rng.uniform();
        g.edges.push_back({a, b, w});
    }
    return g;
}

inline std::vector<std::uint8_t> random_mask(std::uint64_t seed, std::size_t n, double keep) {
    std::vector<std::uint8_t> m(n);
    for (std::size_t i = 0; i < n; ++i) m[i] = hash_uniform(seed, 0x3b, i) < keep ? 1 : 0;
    return m;
}

/// Brute-force forest: Bellman-Ford to a fixed point for the distances, then labels and parents by
/// the documented tie rule (smallest label among tight neighbours, then smallest neighbour id),
/// visiting vertices by increasing distance. `fixed` vertices (sources or a previous forest) keep
/// the given label/parent/distance.
struct oracle_forest {
    std::vector<graph::vertex_id> label, parent;
    std::vector<double> distance;
};

inline oracle_forest bellman_ford_forest(const random_graph& g, const std::vector<std::uint8_t>& mask, oracle_forest init,
                                         const std::vector<std::uint8_t>& fixed) {
    const auto inf = std::numeric_limits<double>::infinity();
    auto in = [&](std::size_t v) { return mask.empty() || mask[v]; };
    oracle_forest f = std::move(init);
    for (bool changed = true; changed;) {
        changed = false;
        for (const auto& e : g.edges)
            for (int dir = 0; dir < 2; ++dir) {
                const std::size_t u = dir ? e.target : e.source, v = dir ? e.source : e.target;
                if (!in(u) || !in(v) || fixed[v] || f.distance[u] == inf) continue;
                if (f.distance[u] + e.weight < f.distance[v]) f.distance[v] = f.distance[u] + e.weight, changed = true;
            }
    }
    std::vector<std::size_t> order;
    for (std::size_t v = 0; v < g.n; ++v)
        if (!fixed[v] && f.distance[v] < inf) order.push_back(v);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return f.distance[a] < f.distance[b]; });
    for (const std::size_t v : order) {
        graph::vertex_id best_label = graph::no_vertex, best_parent = graph::no_vertex;
        for (const auto& e : g.edges)
            for (int dir = 0; dir < 2; ++dir) {
                const std::size_t u = dir ? e.target : e.source, w = dir ? e.source : e.target;
                if (w != v || !in(u) || f.distance[u] == inf || f.distance[u] + e.weight != f.distance[v]) continue;
                const graph::vertex_id lu = f.label[u];
                if (lu < best_label || (lu == best_label && u < best_parent)) best_label = lu, best_parent = static_cast<graph::vertex_id>(u);
            }
        f.label[v] = best_label, f.parent[v] = best_parent;
    }
    return f;
}

}  // namespace fabsynth::test
