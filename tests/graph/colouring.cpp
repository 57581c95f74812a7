// colouring.hpp: proper, deterministic, within max degree + 1 colours; the greedy rule checked
// against a colouring written here.
#include <catch2/catch.hpp>

#include <fabsynth/graph/colouring.hpp>

#include "graph/random_graphs.hpp"

#include <algorithm>
#include <set>
#include <vector>

using namespace fabsynth;
using namespace fabsynth::graph;

namespace {
// Greedy in a given order over the edge list (independent of the library's CSR rows).
std::vector<std::uint32_t> greedy_oracle(const test::random_graph& rg, const std::vector<vertex_id>& order) {
    std::vector<std::uint32_t> colour(rg.n, 0xffffffffu);
    for (const vertex_id v : order) {
        std::set<std::uint32_t> used;
        for (const auto& e : rg.edges) {
            if (e.source == v && colour[e.target] != 0xffffffffu) used.insert(colour[e.target]);
            if (e.target == v && colour[e.source] != 0xffffffffu) used.insert(colour[e.source]);
        }
        std::uint32_t c = 0;
        while (used.count(c)) ++c;
        colour[v] = c;
    }
    return colour;
}
}  // namespace

TEST_CASE("greedy colouring is proper, deterministic and follows the greedy rule", "[graph][colouring]") {
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
        const auto rg = test::make_random_graph(seed * 11, 90, 0.5 + 0.1 * static_cast<double>(seed % 40), true);
        const auto g = build_csr(rg.n, rg.edges);
        std::size_t max_degree = 0;
        for (vertex_id v = 0; v < rg.n; ++v) max_degree = std::max(max_degree, g.degree(v));
        for (int policy = 0; policy < 2; ++policy) {
            const colouring c = policy ? greedy_colouring(g, largest_degree_first{}) : greedy_colouring(g);
            const colouring again = policy ? greedy_colouring(g, largest_degree_first{}) : greedy_colouring(g);
            REQUIRE(c.colour == again.colour);
            for (const auto& e : rg.edges) REQUIRE(c.colour[e.source] != c.colour[e.target]);
            REQUIRE(c.count() <= max_degree + 1);
            std::size_t total = 0;
            for (std::uint32_t k = 0; k < c.count(); ++k) {
                REQUIRE(!c.sets[k].empty());
                REQUIRE(std::is_sorted(c.sets[k].begin(), c.sets[k].end()));
                for (const vertex_id v : c.sets[k]) REQUIRE(c.colour[v] == k);
                total += c.sets[k].size();
            }
            REQUIRE(total == rg.n);
            // the oracle order: ids, or degree descending with ties by id
            std::vector<vertex_id> order(rg.n);
            for (vertex_id v = 0; v < rg.n; ++v) order[v] = v;
            if (policy) {
                std::vector<std::size_t> deg(rg.n, 0);
                for (const auto& e : rg.edges) ++deg[e.source], ++deg[e.target];
                std::sort(order.begin(), order.end(), [&](vertex_id a, vertex_id b) { return deg[a] != deg[b] ? deg[a] > deg[b] : a < b; });
            }
            REQUIRE(c.colour == greedy_oracle(rg, order));
        }
        // directed input is coloured as its undirected graph
        const auto d = greedy_colouring(build_csr(rg.n, rg.edges, {.directed = true}));
        for (const auto& e : rg.edges) REQUIRE(d.colour[e.source] != d.colour[e.target]);
    }
}

TEST_CASE("greedy colouring rejects an order that is not a permutation", "[graph][colouring]") {
    const auto g = build_csr(3, std::vector<edge_record<>>{{0, 1, 1.0}});
    auto bad = [](const csr_graph<>&) { return std::vector<vertex_id>{0, 0, 1}; };
    CHECK_THROWS_AS(greedy_colouring(g, bad), invalid_input);
    auto short_order = [](const csr_graph<>&) { return std::vector<vertex_id>{0}; };
    CHECK_THROWS_AS(greedy_colouring(g, short_order), invalid_input);
}
