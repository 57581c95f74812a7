// from_voxels.hpp on a voxelized sphere shell: edges and weights against a brute force over all
// voxel pairs (centre distance <= threshold), and the three input forms agree.
#include <catch2/catch.hpp>

#include <fabsynth/graph/from_voxels.hpp>

#include <cmath>
#include <map>
#include <string>
#include <vector>

using namespace fabsynth;
using namespace fabsynth::graph;

namespace {
// Voxels whose centre lies within [r - h, r + h] of the grid centre.
std::vector<ivec3> sphere_shell(const grid_geometry& g, double r, double h) {
    std::vector<ivec3> out;
    const vec3 c = g.origin + 0.5 * g.spacing * vec3(g.dims);
    for (int k = g.dims.z - 1; k >= 0; --k)  // deliberately not in index order
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i) {
                const double d = glm::distance(g.center({i, j, k}), c);
                if (d >= r - h && d <= r + h) out.push_back({i, j, k});
            }
    return out;
}

template <class C>
void compare_with_pairs(const grid_geometry& g, const std::vector<ivec3>& shell, double threshold) {
    const auto vg = from_voxels<C>(g, shell);
    REQUIRE(vg.size() == shell.size());
    // brute force over all pairs, with vertex ids from sorting the linear indices here
    std::map<std::uint64_t, vertex_id> id;
    for (const ivec3& p : shell) id[g.index(p)] = 0;
    vertex_id next = 0;
    for (auto& kv : id) kv.second = next++;
    std::size_t pairs = 0;
    for (std::size_t a = 0; a < shell.size(); ++a)
        for (std::size_t b = 0; b < shell.size(); ++b) {
            if (a == b) continue;
            const double d = glm::distance(g.center(shell[a]), g.center(shell[b]));
            if (d > threshold) continue;
            ++pairs;
            const vertex_id u = id[g.index(shell[a])], v = id[g.index(shell[b])];
            const arc_id e = vg.graph.find_arc(u, v);
            REQUIRE(e < vg.graph.num_arcs());
            REQUIRE(vg.graph.weight(e) == d);  // exact: centres are exact binary fractions here
        }
    REQUIRE(vg.graph.num_arcs() == pairs);
    for (vertex_id v = 0; v < vg.size(); ++v) {
        REQUIRE(vg.vertex_of(vg.voxels[v]) == v);
        REQUIRE(vg.indices[v] == g.index(vg.voxels[v]));
        if (v > 0) REQUIRE(vg.indices[v - 1] < vg.indices[v]);
    }
}
}  // namespace

TEST_CASE("from_voxels on a sphere shell equals the brute force over all voxel pairs", "[graph][from_voxels]") {
    const grid_geometry g{{22, 21, 20}, vec3(-3.0, 1.0, 0.5), vec3(0.5)};
    const auto shell = sphere_shell(g, 4.2, 0.5);
    REQUIRE(shell.size() > 500);
    const double h = 0.5, eps = 1e-9;
    compare_with_pairs<connectivity::c26>(g, shell, std::sqrt(3.0) * h + eps);
    compare_with_pairs<connectivity::c18>(g, shell, std::sqrt(2.0) * h + eps);
    compare_with_pairs<connectivity::c6>(g, shell, h + eps);
}

TEST_CASE("from_voxels: anisotropic spacing, grid borders and the three input forms", "[graph][from_voxels]") {
    const grid_geometry g{{5, 4, 3}, vec3(0.0), vec3(0.5, 0.25, 2.0)};
    std::vector<ivec3> all;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 5; ++i)
                if ((i + 2 * j + k) % 3 != 0) all.push_back({i, j, k});
    const auto from_list = from_voxels<connectivity::c26>(g, all);
    sparse_voxel_grid<float> sparse(g, 0.0f);
    voxel_grid<float> dense(g, 0.0f);
    for (const ivec3& p : all) sparse.set(p, 1.0f), dense.set(p, 1.0f);
    const auto from_sparse = from_voxels(sparse);
    const auto from_dense = from_voxels(dense, [](float v) { return v > 0.5f; });
    for (const auto* other : {&from_sparse, &from_dense}) {
        REQUIRE(other->indices == from_list.indices);
        REQUIRE(std::vector<arc_id>(other->graph.offsets().begin(), other->graph.offsets().end()) ==
                std::vector<arc_id>(from_list.graph.offsets().begin(), from_list.graph.offsets().end()));
        REQUIRE(std::vector<vertex_id>(other->graph.targets().begin(), other->graph.targets().end()) ==
                std::vector<vertex_id>(from_list.graph.targets().begin(), from_list.graph.targets().end()));
    }
    // every arc: a 26-neighbour, weight = anisotropic centre distance
    for (vertex_id v = 0; v < from_list.size(); ++v)
        for (arc_id e = from_list.graph.edge_begin(v); e < from_list.graph.edge_end(v); ++e) {
            const ivec3 d = from_list.voxels[from_list.graph.target(e)] - from_list.voxels[v];
            REQUIRE(std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)}) == 1);
            const vec3 dm = vec3(d) * g.spacing;
            REQUIRE(from_list.graph.weight(e) == std::sqrt(dm.x * dm.x + dm.y * dm.y + dm.z * dm.z));
        }
    // a dense grid with the default predicate: every voxel, interior vertex of a 3x3x3 block has 26 arcs
    const auto full = from_voxels(voxel_grid<std::uint8_t>({3, 3, 3}, vec3(0), 1.0));
    CHECK(full.size() == 27);
    CHECK(full.graph.degree(full.vertex_of({1, 1, 1})) == 26);
    CHECK(full.graph.degree(full.vertex_of({0, 0, 0})) == 7);
    CHECK(full.vertex_of({3, 0, 0}) == no_vertex);
}

TEST_CASE("from_voxels rejects voxels outside the grid and repeated voxels", "[graph][from_voxels]") {
    const grid_geometry g{{4, 4, 4}, vec3(0), vec3(1)};
    try {
        (void)from_voxels(g, std::vector<ivec3>{{0, 0, 0}, {4, 0, 0}});
        FAIL("no throw");
    } catch (const invalid_input& e) {
        CHECK(std::string(e.what()).rfind("fabsynth: from_voxels: voxel 1 (4, 0, 0) is outside", 0) == 0);
    }
    try {
        (void)from_voxels(g, std::vector<ivec3>{{1, 2, 3}, {0, 0, 0}, {1, 2, 3}});
        FAIL("no throw");
    } catch (const invalid_input& e) {
        CHECK(std::string(e.what()).find("(1, 2, 3) is listed more than once") != std::string::npos);
    }
}
