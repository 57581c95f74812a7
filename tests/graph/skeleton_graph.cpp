// skeleton_graph.hpp: welding, valence, branches on a hand-made Y, a loop and a loop at a
// junction, exact lengths, edits; and from_mesh.hpp's edge graph.
#include <catch2/catch.hpp>

#include <fabsynth/graph/from_mesh.hpp>
#include <fabsynth/graph/skeleton_graph.hpp>

#include <algorithm>
#include <vector>

using namespace fabsynth;
using namespace fabsynth::graph;

namespace {
using line2 = skeleton_polyline<vec2>;
}

TEST_CASE("skeleton graph of a Y: one junction, three branches, exact length", "[graph][skeleton]") {
    // Three arms from (0,0), lengths 5 (3-4-5), 10 (two segments 6-8-10 ... ) and 2.
    const std::vector<line2> arms{
        {{{0, 0}, {3, 4}}, {1.0, 0.5}},
        {{{0, 0}, {-6, 8}, {-6, 13}}, {2.0, 1.0, 0.5}},   // 10 + 5
        {{{0, 2e-7}, {0, -1}, {0, -2}}, {}},             // starts within tolerance of (0,0)
    };
    const auto s = skeleton_from_polylines(arms, 1e-6);
    CHECK(s.num_vertices() == 6);
    CHECK(s.num_edges() == 5);
    CHECK(s.valence(0) == 3);
    CHECK(s.width(0) == 1.0);  // the first occurrence's width
    CHECK(s.total_length() == 5.0 + 15.0 + 2.0);
    const auto b = s.branches();
    REQUIRE(b.size() == 3);
    CHECK(b[0].vertices == std::vector<vertex_id>{0, 1});
    CHECK(b[1].vertices == std::vector<vertex_id>{0, 2, 3});
    CHECK(b[2].vertices == std::vector<vertex_id>{0, 4, 5});
    for (const auto& br : b) CHECK_FALSE(br.closed());
    CHECK(b[1].edges.size() == 2);
    // subgraph lengths by edge mask and by vertex mask
    std::vector<std::uint8_t> emask(s.edge_slots(), 0);
    for (const edge_id e : b[1].edges) emask[e] = 1;
    CHECK(s.total_length_of_edges(emask) == 15.0);
    std::vector<std::uint8_t> vmask{1, 1, 1, 0, 0, 0};
    CHECK(s.total_length_of_vertices(vmask) == 5.0 + 10.0);
}

TEST_CASE("skeleton graph of a closed loop, a loop at a junction, and edits", "[graph][skeleton]") {
    // a square traced as one closed polyline
    const std::vector<line2> square{{{{0, 0}, {2, 0}, {2, 2}, {0, 2}, {0, 0}}, {}}};
    auto s = skeleton_from_polylines(square, 1e-9);
    CHECK(s.num_vertices() == 4);
    CHECK(s.num_edges() == 4);
    auto b = s.branches();
    REQUIRE(b.size() == 1);
    CHECK(b[0].closed());
    CHECK(b[0].vertices == std::vector<vertex_id>{0, 1, 2, 3, 0});
    CHECK(s.total_length() == 8.0);

    // a tail at vertex 2 turns it into a junction: the loop becomes a closed branch from 2 plus the tail
    const vertex_id tail = s.add_vertex({5, 6}, 0.3);
    const edge_id t = s.add_edge(2, tail);
    CHECK(s.valence(2) == 3);
    b = s.branches();
    REQUIRE(b.size() == 2);
    CHECK(b[0].vertices == std::vector<vertex_id>{2, 1, 0, 3, 2});
    CHECK(b[0].closed());
    CHECK(b[1].vertices == std::vector<vertex_id>{2, tail});
    CHECK(s.total_length() == 8.0 + 5.0);

    // removing an edge of the loop opens it: one branch from the end 0 ... to the junction
    const edge_id e01 = s.find_edge(0, 1);
    REQUIRE(e01 != no_edge);
    s.remove_edge(e01);
    CHECK_FALSE(s.edge_alive(e01));
    CHECK(s.num_edges() == 4);
    b = s.branches();
    REQUIRE(b.size() == 3);
    CHECK(b[0].vertices == std::vector<vertex_id>{0, 3, 2});
    CHECK(b[1].vertices == std::vector<vertex_id>{1, 2});
    CHECK(b[2].vertices == std::vector<vertex_id>{2, tail});
    CHECK(s.total_length() == 6.0 + 5.0);
    s.remove_edge(t);
    CHECK(s.valence(tail) == 0);
    CHECK_THROWS_AS(s.remove_edge(t), invalid_input);
    CHECK(s.to_csr().num_edges() == 3);
}

TEST_CASE("skeleton graphs in 3D and bad input", "[graph][skeleton]") {
    const std::vector<skeleton_polyline<glm::vec3>> lines{{{{0, 0, 0}, {0, 0, 2}}, {}}, {{{0, 0, 2}, {0, 3, 6}}, {}}};
    const auto s = skeleton_from_polylines(lines);
    CHECK(s.valence(1) == 2);
    CHECK(s.branches().size() == 1);
    CHECK(s.total_length() == 7.0);

    CHECK_THROWS_AS(skeleton_from_polylines(std::vector<line2>{{{{0, 0}}, {}}}), invalid_input);
    CHECK_THROWS_AS(skeleton_from_polylines(std::vector<line2>{{{{0, 0}, {1, 1}}, {1.0}}}), invalid_input);
    CHECK_THROWS_AS(skeleton_from_polylines(std::vector<line2>{{{{0, 0}, {1e-9, 0}}, {}}}, 1e-6), invalid_input);
    CHECK_THROWS_AS(skeleton_from_polylines(std::vector<line2>{{{{0, 0}, {1, 0}}, {}}}, -1.0), invalid_input);
    skeleton_graph<vec2> g;
    g.add_vertex({0, 0});
    CHECK_THROWS_AS(g.add_edge(0, 0), invalid_input);
    CHECK_THROWS_AS(g.add_edge(0, 1), invalid_input);
    CHECK_THROWS_AS(g.add_vertex({0, 0}, -1.0), invalid_input);
}

TEST_CASE("from_mesh: one edge per distinct face edge, weighted by length", "[graph][from_mesh]") {
    triangle_mesh m;
    m.vertices = {{0, 0, 0}, {3, 0, 0}, {3, 4, 0}, {0, 4, 0}, {9, 9, 9}};
    m.faces = {{0, 1, 2}, {0, 2, 3}, {1, 1, 2}};  // the last face is degenerate
    const auto g = from_mesh(m);
    CHECK(g.num_vertices() == 5);
    CHECK(g.num_edges() == 5);
    CHECK(g.weight(g.find_arc(0, 2)) == 5.0);
    CHECK(g.weight(g.find_arc(3, 2)) == 3.0);
    CHECK(g.degree(4) == 0);
    m.faces.push_back({0, 1, 7});
    CHECK_THROWS_AS(from_mesh(m), invalid_input);
}
