// graph/components.hpp against a BFS written here, and against voxel/components.hpp on voxel sets.
#include <catch2/catch.hpp>

#include <fabsynth/graph/components.hpp>
#include <fabsynth/graph/from_voxels.hpp>
#include <fabsynth/voxel/components.hpp>

#include "graph/random_graphs.hpp"

#include <deque>
#include <vector>

using namespace fabsynth;
using namespace fabsynth::graph;

TEST_CASE("connected_components equals a BFS over the edge list", "[graph][components]") {
    for (std::uint64_t seed = 1; seed <= 100; ++seed) {
        const auto rg = test::make_random_graph(seed * 5, 80, 0.4 + 0.02 * static_cast<double>(seed % 50), true);
        const auto g = build_csr(rg.n, rg.edges);
        const auto mask = seed % 3 == 0 ? std::vector<std::uint8_t>{} : test::random_mask(seed, rg.n, 0.7);
        auto in = [&](std::size_t v) { return mask.empty() || mask[v]; };
        std::vector<std::vector<std::size_t>> adj(rg.n);
        for (const auto& e : rg.edges) adj[e.source].push_back(e.target), adj[e.target].push_back(e.source);
        std::vector<vertex_id> label(rg.n, no_vertex);
        std::vector<std::size_t> sizes;
        for (std::size_t s = 0; s < rg.n; ++s) {
            if (!in(s) || label[s] != no_vertex) continue;
            const auto l = static_cast<vertex_id>(sizes.size());
            sizes.push_back(0);
            std::deque<std::size_t> q{s};
            label[s] = l;
            while (!q.empty()) {
                const std::size_t v = q.front();
                q.pop_front();
                ++sizes.back();
                for (const std::size_t w : adj[v])
                    if (in(w) && label[w] == no_vertex) label[w] = l, q.push_back(w);
            }
        }
        const auto cc = connected_components(g, mask);
        REQUIRE(cc.count == sizes.size());
        REQUIRE(cc.label == label);
        REQUIRE(cc.sizes == sizes);
    }
}

TEST_CASE("components of voxel graphs equal voxel/components.hpp labelling", "[graph][components]") {
    for (std::uint64_t seed = 1; seed <= 12; ++seed) {
        sparse_voxel_grid<std::uint8_t> s({11, 9, 7}, vec3(0), 0.5);
        for (std::uint64_t i = 0; i < 11 * 9 * 7; ++i)
            if (hash_uniform(seed, i) < 0.1 + 0.03 * static_cast<double>(seed)) s.set(s.coord(i), 1);
        auto check = [&](auto conn) {
            using C = decltype(conn);
            const auto vg = from_voxels<C>(s);
            const auto cc = connected_components(vg.graph);
            const auto want = label_components<C>(s, [](std::uint8_t v) { return v != 0; });
            REQUIRE(cc.count == static_cast<std::size_t>(want.count));
            for (vertex_id v = 0; v < vg.size(); ++v) REQUIRE(static_cast<std::int32_t>(cc.label[v]) == want.labels.get(vg.voxels[v]));
        };
        check(connectivity::c6{});
        check(connectivity::c18{});
        check(connectivity::c26{});
    }
}
