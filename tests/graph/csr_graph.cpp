// csr_graph.hpp: layout, neighbour order, payloads and input validation.
#include <catch2/catch.hpp>

#include <fabsynth/graph/csr_graph.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace fabsynth;
using namespace fabsynth::graph;

namespace {
void check_throws(const std::vector<edge_record<>>& edges, std::size_t n, const std::string& what) {
    try {
        (void)build_csr(n, edges);
    } catch (const invalid_input& e) {
        const std::string msg = e.what();
        CHECK(msg.rfind("fabsynth:", 0) == 0);
        CHECK(msg.find(what) != std::string::npos);
        return;
    }
    FAIL("no invalid_input for " << what);
}
}  // namespace

TEST_CASE("build_csr stores both directions with rows sorted by target", "[graph][csr]") {
    const std::vector<edge_record<>> edges{{2, 0, 1.5}, {0, 1, 1.0}, {3, 0, 0.5}, {1, 3, 2.0}, {0, 2, 0.25}};
    const auto g = build_csr(4, edges);
    CHECK(g.num_vertices() == 4);
    CHECK(g.num_arcs() == 10);
    CHECK(g.num_edges() == 5);
    CHECK_FALSE(g.directed());
    const std::vector<vertex_id> row0(g.neighbours(0).begin(), g.neighbours(0).end());
    CHECK(row0 == std::vector<vertex_id>{1, 2, 2, 3});
    const std::vector<double> w0(g.neighbour_weights(0).begin(), g.neighbour_weights(0).end());
    CHECK(w0 == std::vector<double>{1.0, 0.25, 1.5, 0.5});  // parallel arcs: lighter first
    CHECK(g.degree(3) == 2);
    CHECK(g.weight(g.find_arc(2, 0)) == 0.25);
    CHECK(g.find_arc(1, 2) == g.num_arcs());
    CHECK(g.offsets().size() == 5);

    const auto d = build_csr(4, edges, {.directed = true});
    CHECK(d.num_arcs() == 5);
    CHECK(d.num_edges() == 5);
    CHECK(d.degree(0) == 2);
    CHECK(d.degree(1) == 1);
}

TEST_CASE("csr_graph carries a per-edge payload on both arcs", "[graph][csr]") {
    struct kind {
        int solid = 0;
    };
    const std::vector<edge_record<kind>> edges{{0, 1, 1.0, {7}}, {1, 2, 1.0, {3}}};
    const auto g = build_csr(3, edges);
    static_assert(decltype(g)::has_payload);
    CHECK(g.payload(g.find_arc(1, 0)).solid == 7);
    CHECK(g.payload(g.find_arc(0, 1)).solid == 7);
    CHECK(g.payload(g.find_arc(2, 1)).solid == 3);
    static_assert(sizeof(edge_record<>) == 16);  // no_payload takes no space
}

TEST_CASE("build_csr and from_arrays reject bad input with a named reason", "[graph][csr]") {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    check_throws({{0, 3, 1.0}}, 3, "out of range");
    check_throws({{0, 1, 1.0}, {2, 2, 1.0}}, 3, "self loop");
    check_throws({{0, 1, nan}}, 3, "weight");
    check_throws({{0, 1, -1.0}}, 3, "weights must be finite and >= 0");
    check_throws({{0, 1, inf}}, 3, "edge 0");
    CHECK_THROWS_AS(csr_graph<>::from_arrays({0, 1, 1}, {0}, {1.0}), invalid_input);          // self loop
    CHECK_THROWS_AS(csr_graph<>::from_arrays({0, 2, 2}, {1, 1}, {1.0}), invalid_input);       // weight count
    CHECK_THROWS_AS(csr_graph<>::from_arrays({0, 2, 2, 2}, {2, 1}, {1.0, 1.0}), invalid_input);  // unsorted row
    CHECK_THROWS_AS(csr_graph<>::from_arrays({0, 1}, {0, 1}, {1.0, 1.0}), invalid_input);     // offsets end
    CHECK_NOTHROW(build_csr(3, std::vector<edge_record<>>{}));
    CHECK(csr_graph<>().num_vertices() == 0);
}
