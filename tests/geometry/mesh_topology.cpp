#include <catch2/catch.hpp>

#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/io/mesh.hpp>

#include <string>

using namespace fabsynth;

namespace {
triangle_mesh data_mesh(const char* name) { return io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/" + name); }
}  // namespace

TEST_CASE("mesh topology of the bundled meshes matches data/README.md", "[geometry][topology]") {
    struct expect {
        const char* file;
        long long genus;
    };
    // closed, edge-manifold, single component meshes with their published genus
    for (const expect& e : {expect{"kitten_lowres.obj", 1}, expect{"fertility.obj", 4}, expect{"three_holes.obj", 3},
                            expect{"bunny_lowres.obj", 0}, expect{"torus.obj", 1}, expect{"icosphere.obj", 0},
                            expect{"cube.obj", 0}, expect{"cube_subdiv.obj", 0}}) {
        INFO(e.file);
        const auto t = analyze_topology(data_mesh(e.file));
        CHECK(t.is_watertight());
        CHECK(t.components == 1);
        CHECK(t.genus == e.genus);
        CHECK(t.euler == 2 - 2 * e.genus);
    }
    // the full bunny is open: 5 holes, 223 boundary edges, 1 component, unreferenced vertices ignored
    const triangle_mesh bunny = data_mesh("bunny.obj");
    const auto t = analyze_topology(bunny);
    CHECK(t.boundary_edges == 223);
    CHECK(t.boundary_loops == 5);
    CHECK(t.components == 1);
    CHECK(t.vertices == 35947 - 1113);
    CHECK(t.is_edge_manifold());
    CHECK_FALSE(t.is_watertight());
    CHECK(count_boundary_edges(bunny) == 223);
    CHECK(t.genus == 0);
}

TEST_CASE("mesh topology: hand-made cases", "[geometry][topology]") {
    triangle_mesh tri{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}};
    auto t = analyze_topology(tri);
    CHECK(t.boundary_edges == 3);
    CHECK(t.boundary_loops == 1);
    CHECK(t.euler == 1);
    CHECK(t.genus == 0);
    CHECK_FALSE(is_watertight(tri));

    // tetrahedron: closed, genus 0; flipping one face breaks the orientation
    triangle_mesh tet{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
    CHECK(is_watertight(tet));
    CHECK(signed_volume(tet) > 0);
    auto flipped = tet;
    std::swap(flipped.faces[3][0], flipped.faces[3][1]);
    t = analyze_topology(flipped);
    CHECK(t.is_closed());
    CHECK(t.inconsistent_edges == 3);
    CHECK_FALSE(t.is_watertight());

    // three triangles on one edge: non-manifold
    triangle_mesh fan{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}};
    t = analyze_topology(fan);
    CHECK(t.nonmanifold_edges == 1);
    CHECK_FALSE(is_edge_manifold(fan));

    // two disjoint tetrahedra: two components, labelled in face order
    triangle_mesh two = tet;
    for (auto v : tet.vertices) two.vertices.push_back(v + vec3(5, 0, 0));
    for (auto f : tet.faces) two.faces.push_back({f[0] + 4, f[1] + 4, f[2] + 4});
    std::size_t count = 0;
    const auto comp = face_components(two, &count);
    CHECK(count == 2);
    CHECK(comp == std::vector<std::uint32_t>{0, 0, 0, 0, 1, 1, 1, 1});
    t = analyze_topology(two);
    CHECK(t.euler == 4);
    CHECK(t.genus == 0);

    // degenerate face and bad indices
    triangle_mesh degenerate = tet;
    degenerate.faces.push_back({0, 0, 1});
    CHECK(analyze_topology(degenerate).degenerate_faces == 1);
    CHECK_FALSE(is_watertight(degenerate));
    triangle_mesh bad = tet;
    bad.faces[0][2] = 17;
    CHECK_THROWS_AS(analyze_topology(bad), invalid_input);
    CHECK_FALSE(is_watertight(triangle_mesh{}));
}
