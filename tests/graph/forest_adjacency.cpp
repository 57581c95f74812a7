// forest_adjacency.hpp against a brute force over every edge of the input list.
#include <catch2/catch.hpp>

#include <fabsynth/graph/forest_adjacency.hpp>

#include "graph/random_graphs.hpp"

#include <map>
#include <tuple>
#include <vector>

using namespace fabsynth;
using namespace fabsynth::graph;

namespace {
struct best {
    double length;
    vertex_id a, b;
    double weight;
};
// Brute force: every edge of the list, both orientations, keep the (length, a, b, weight) minimum.
std::map<std::pair<vertex_id, vertex_id>, best> brute_adjacency(const test::random_graph& rg, const shortest_path_forest& f,
                                                                const std::vector<std::uint8_t>& mask,
                                                                const std::vector<std::pair<vertex_id, vertex_id>>& skip) {
    std::map<std::pair<vertex_id, vertex_id>, best> out;
    for (const auto& e : rg.edges) {
        vertex_id a = e.source, b = e.target;
        if ((!mask.empty() && (!mask[a] || !mask[b])) || f.label[a] == no_vertex || f.label[b] == no_vertex || f.label[a] == f.label[b]) continue;
        if (f.label[a] > f.label[b]) std::swap(a, b);
        const std::pair<vertex_id, vertex_id> key{f.label[a], f.label[b]};
        if (std::find(skip.begin(), skip.end(), key) != skip.end()) continue;
        const best c{f.distance[a] + e.weight + f.distance[b], a, b, e.weight};
        auto it = out.find(key);
        if (it == out.end() || std::tie(c.length, c.a, c.b, c.weight) < std::tie(it->second.length, it->second.a, it->second.b, it->second.weight))
            out[key] = c;
    }
    return out;
}
}  // namespace

TEST_CASE("forest_adjacency equals a brute force over all edges, with paths root to root", "[graph][forest_adjacency]") {
    std::size_t records = 0;
    for (std::uint64_t seed = 1; seed <= 100; ++seed) {
        const auto rg = test::make_random_graph(seed * 31, 70, 2.5, seed % 2 == 0);
        const auto g = build_csr(rg.n, rg.edges);
        const auto mask = test::random_mask(seed, rg.n, 0.8);
        std::vector<vertex_id> sources;
        for (vertex_id v = 0; v < rg.n && sources.size() < 2 + seed % 7; v += 3)
            if (mask[v]) sources.push_back(v);
        const auto f = dijkstra_forest(g, sources, mask);
        const auto want = brute_adjacency(rg, f, mask, {});
        const auto got = forest_adjacency(g, f, mask);
        REQUIRE(got.size() == want.size());
        auto it = want.begin();
        for (const auto& t : got) {
            REQUIRE(std::pair(t.tree_u, t.tree_v) == it->first);
            REQUIRE(t.length == it->second.length);
            REQUIRE(t.a == it->second.a);
            REQUIRE(t.b == it->second.b);
            REQUIRE(t.weight == it->second.weight);
            // path: source_u ... a b ... source_v along parents
            REQUIRE(t.path.front() == sources[t.tree_u]);
            REQUIRE(t.path.back() == sources[t.tree_v]);
            const auto ia = std::find(t.path.begin(), t.path.end(), t.a);
            REQUIRE(ia + 1 < t.path.end());
            REQUIRE(*(ia + 1) == t.b);
            for (auto p = t.path.begin() + 1; p <= ia; ++p) REQUIRE(f.parent[*p] == *(p - 1));
            for (auto p = ia + 1; p + 1 < t.path.end(); ++p) REQUIRE(f.parent[*p] == *(p + 1));
            ++it, ++records;
        }
        // step 4: extend through everything, skipping the pairs found so far
        const auto grown = extend_forest(g, f);
        std::vector<std::pair<vertex_id, vertex_id>> skip;
        for (const auto& t : got) skip.emplace_back(t.tree_u, t.tree_v);
        const auto want2 = brute_adjacency(rg, grown, {}, skip);
        const auto got2 = forest_adjacency(g, grown, {}, {.skip = got, .record_paths = false});
        REQUIRE(got2.size() == want2.size());
        auto it2 = want2.begin();
        for (const auto& t : got2) {
            REQUIRE(std::pair(t.tree_u, t.tree_v) == it2->first);
            REQUIRE(std::tie(t.length, t.a, t.b) == std::tie(it2->second.length, it2->second.a, it2->second.b));
            REQUIRE(t.path.empty());
            ++it2;
        }
    }
    CHECK(records > 100);
}
