// Dijkstra forests, their extension and geodesics against a brute-force Bellman-Ford with the
// documented tie rule (tests/graph/random_graphs.hpp).
#include <catch2/catch.hpp>

#include <fabsynth/graph/shortest_paths.hpp>

#include "graph/random_graphs.hpp"

#include <limits>
#include <string>
#include <vector>

using namespace fabsynth;
using namespace fabsynth::graph;

namespace {

std::vector<vertex_id> pick_sources(std::uint64_t seed, std::size_t n, const std::vector<std::uint8_t>& mask, std::size_t want) {
    std::vector<vertex_id> s;
    counter_rng rng(seed, 0x51);
    for (std::size_t tries = 0; tries < 4 * want && s.size() < want; ++tries) {
        const auto v = static_cast<vertex_id>(rng.uniform_int(n));
        if ((mask.empty() || mask[v]) && std::find(s.begin(), s.end(), v) == s.end()) s.push_back(v);
    }
    return s;
}

test::oracle_forest oracle_from_sources(std::size_t n, const std::vector<vertex_id>& sources, std::vector<std::uint8_t>& fixed) {
    test::oracle_forest f{std::vector<vertex_id>(n, no_vertex), std::vector<vertex_id>(n, no_vertex),
                          std::vector<double>(n, std::numeric_limits<double>::infinity())};
    fixed.assign(n, 0);
    for (std::size_t t = 0; t < sources.size(); ++t) f.label[sources[t]] = static_cast<vertex_id>(t), f.distance[sources[t]] = 0, fixed[sources[t]] = 1;
    return f;
}

void require_equal(const shortest_path_forest& got, const test::oracle_forest& want) {
    REQUIRE(got.distance == want.distance);  // exact, including +inf
    REQUIRE(got.label == want.label);
    REQUIRE(got.parent == want.parent);
}

}  // namespace

TEST_CASE("dijkstra_forest equals Bellman-Ford with the tie rule on random graphs", "[graph][shortest_paths]") {
    for (std::uint64_t seed = 1; seed <= 120; ++seed) {
        const bool integer_weights = seed % 2 == 0;
        const auto rg = test::make_random_graph(seed, 60, 1.0 + static_cast<double>(seed % 4), integer_weights);
        const auto g = build_csr(rg.n, rg.edges);
        const auto mask = seed % 3 == 0 ? std::vector<std::uint8_t>{} : test::random_mask(seed, rg.n, 0.75);
        const auto sources = pick_sources(seed, rg.n, mask, 1 + seed % 6);
        std::vector<std::uint8_t> fixed;
        const auto want = test::bellman_ford_forest(rg, mask, oracle_from_sources(rg.n, sources, fixed), fixed);
        const auto got = dijkstra_forest(g, sources, mask);
        REQUIRE(got.sources == sources);
        require_equal(got, want);
        // paths to the roots walk graph edges and sum to the distance
        for (vertex_id v = 0; v < rg.n; ++v) {
            const auto path = path_to_root(got, v);
            if (!got.reached(v)) {
                REQUIRE(path.empty());
                continue;
            }
            REQUIRE(path.front() == v);
            REQUIRE(path.back() == sources[got.label[v]]);
            REQUIRE(got.root(v) == path.back());
            double d = 0;
            for (std::size_t k = path.size() - 1; k > 0; --k) {
                const arc_id e = g.find_arc(path[k], path[k - 1]);  // the lightest parallel arc comes first
                REQUIRE(e < g.num_arcs());
                d += g.weight(e);
            }
            REQUIRE(d == Approx(got.distance[v]).epsilon(1e-12));
        }
    }
}

TEST_CASE("extend_forest equals Bellman-Ford with the first forest frozen", "[graph][shortest_paths]") {
    for (std::uint64_t seed = 1; seed <= 120; ++seed) {
        const auto rg = test::make_random_graph(seed * 7, 50, 2.0, seed % 2 == 0);
        const auto g = build_csr(rg.n, rg.edges);
        const auto small = test::random_mask(seed, rg.n, 0.5);
        std::vector<std::uint8_t> large = test::random_mask(seed + 1000, rg.n, 0.6);
        for (std::size_t v = 0; v < rg.n; ++v) large[v] |= small[v];
        const bool everything = seed % 4 == 0;
        const auto sources = pick_sources(seed, rg.n, small, 1 + seed % 5);
        const auto first = dijkstra_forest(g, sources, small);
        const auto grown = extend_forest(g, first, everything ? vertex_mask{} : vertex_mask(large));

        test::oracle_forest init{first.label, first.parent, first.distance};
        std::vector<std::uint8_t> frozen(rg.n);
        for (std::size_t v = 0; v < rg.n; ++v) frozen[v] = first.reached(static_cast<vertex_id>(v)) ? 1 : 0;
        const auto want = test::bellman_ford_forest(rg, everything ? std::vector<std::uint8_t>{} : large, init, frozen);
        require_equal(grown, want);
        for (vertex_id v = 0; v < rg.n; ++v)  // the trees keep their vertices
            if (first.reached(v)) REQUIRE(grown.label[v] == first.label[v]);
    }
}

TEST_CASE("geodesic equals the single-source oracle, +inf when disconnected", "[graph][shortest_paths]") {
    int disconnected = 0;
    for (std::uint64_t seed = 1; seed <= 80; ++seed) {
        const auto rg = test::make_random_graph(seed * 13, 40, 1.3, seed % 2 == 1);
        const auto g = build_csr(rg.n, rg.edges);
        const auto mask = test::random_mask(seed, rg.n, 0.8);
        const auto ends = pick_sources(seed, rg.n, mask, 2);
        if (ends.size() < 2) continue;
        std::vector<std::uint8_t> fixed;
        const auto want = test::bellman_ford_forest(rg, mask, oracle_from_sources(rg.n, {ends[0]}, fixed), fixed);
        const auto geo = geodesic(g, ends[0], ends[1], mask);
        REQUIRE(geo.length == want.distance[ends[1]]);
        if (!geo.connected()) {
            ++disconnected;
            REQUIRE(geo.length == std::numeric_limits<double>::infinity());
            continue;
        }
        REQUIRE(geo.vertices.front() == ends[0]);
        REQUIRE(geo.vertices.back() == ends[1]);
        for (std::size_t k = 1; k < geo.vertices.size(); ++k) {
            REQUIRE(mask[geo.vertices[k]]);
            REQUIRE(want.parent[geo.vertices[k]] == geo.vertices[k - 1]);
        }
    }
    CHECK(disconnected > 0);
}

TEST_CASE("shortest paths reject bad sources and masks", "[graph][shortest_paths]") {
    const std::vector<edge_record<>> edges{{0, 1, 1.0}, {1, 2, 1.0}};
    const auto g = build_csr(3, edges);
    const std::vector<std::uint8_t> mask{1, 0, 1}, short_mask{1, 1};
    auto throws_with = [](auto&& f, const std::string& what) {
        try {
            f();
        } catch (const invalid_input& e) {
            const std::string msg = e.what();
            CHECK(msg.rfind("fabsynth:", 0) == 0);
            CHECK(msg.find(what) != std::string::npos);
            return;
        }
        FAIL("no invalid_input thrown, expected: " << what);
    };
    throws_with([&] { (void)dijkstra_forest(g, std::vector<vertex_id>{5}, {}); }, "out of range");
    throws_with([&] { (void)dijkstra_forest(g, std::vector<vertex_id>{1}, mask); }, "outside the mask");
    throws_with([&] { (void)dijkstra_forest(g, std::vector<vertex_id>{0, 0}, {}); }, "both source");
    throws_with([&] { (void)dijkstra_forest(g, std::vector<vertex_id>{0}, short_mask); }, "mask has 2 entries");
    const auto f = dijkstra_forest(g, std::vector<vertex_id>{0}, {});
    throws_with([&] { (void)extend_forest(g, f, mask); }, "outside the larger mask");
    throws_with([&] { (void)geodesic(g, 0, 1, mask); }, "outside the mask");
    // a mask that cuts the path: unreached / +inf, not an error
    CHECK(dijkstra_forest(g, std::vector<vertex_id>{0}, mask).distance[2] == std::numeric_limits<double>::infinity());
    CHECK(geodesic(g, 0, 2, mask).length == std::numeric_limits<double>::infinity());
    CHECK(geodesic(g, 0, 2).length == 2.0);
    CHECK(geodesic(g, 1, 1).vertices == std::vector<vertex_id>{1});
}

TEST_CASE("bounded_search finds exactly the vertices closer than the radius, in order, run after run", "[graph][shortest_paths]") {
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        const auto rg = test::make_random_graph(seed, 60, 1.0 + static_cast<double>(seed % 4), seed % 2 == 0);
        const auto g = build_csr(rg.n, rg.edges);
        bounded_search near(rg.n);  // one object for every run: the reset of the last run's vertices is under test
        for (vertex_id source = 0; source < rg.n; source += 7) {
            std::vector<std::uint8_t> fixed;
            const auto want = test::bellman_ford_forest(rg, {}, oracle_from_sources(rg.n, {source}, fixed), fixed);
            const double radius = 0.5 + static_cast<double>(seed % 5);
            std::vector<vertex_id> found;
            near.run(g, source, radius, [&](vertex_id v) { found.push_back(v); });
            std::vector<std::uint8_t> seen(rg.n, 0);
            for (std::size_t k = 0; k < found.size(); ++k) {
                REQUIRE(!seen[found[k]]);  // each vertex once
                seen[found[k]] = 1;
                if (k) REQUIRE(want.distance[found[k - 1]] <= want.distance[found[k]]);  // by distance
            }
            for (vertex_id v = 0; v < rg.n; ++v) REQUIRE(static_cast<bool>(seen[v]) == (want.distance[v] < radius));
        }
    }
    bounded_search near(3);
    CHECK_THROWS_AS(near.run(7, 1.0, [](vertex_id, auto&&) {}, [](vertex_id) {}), invalid_input);
}
