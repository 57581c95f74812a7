// Tests for io/mesh_obj.hpp, io/mesh_stl.hpp, io/mesh_ply.hpp and io/mesh.hpp: exact round trips
// and the bundled meshes against the counts in data/README.md.
#include <catch2/catch.hpp>

#include <set>

#include "fabsynth/io/mesh.hpp"
#include "io/io_test_util.hpp"

using namespace fabsynth;
using io_test::awkward_mesh;
using io_test::tmp_dir;

TEST_CASE("OBJ round trip is bit-exact for doubles", "[io][obj]") {
    const triangle_mesh m = awkward_mesh(1);
    const auto p = tmp_dir() / "rt.obj";
    io::write_obj(p, m);
    const triangle_mesh r = io::read_obj(p);
    CHECK(io_test::bit_equal(r, m));
    // Unreferenced vertices survive (indices must match the file).
    triangle_mesh u = m;
    u.vertices.emplace_back(7.0, 8.0, 9.0);
    io::write_mesh(tmp_dir() / "rt_unref.OBJ", u);
    CHECK(io_test::bit_equal(io::read_mesh(tmp_dir() / "rt_unref.OBJ"), u));
}

TEST_CASE("STL round trips: ASCII exact, binary after float rounding, welded", "[io][stl]") {
    const triangle_mesh m = awkward_mesh(2);
    const auto pa = tmp_dir() / "rt_ascii.stl", pb = tmp_dir() / "rt_bin.stl";
    io::write_stl(pa, m, io::encoding::ascii);
    io::write_stl(pb, m);
    CHECK(io_test::bit_equal(io::read_stl(pa), io_test::welded_by_map(m)));
    CHECK(io_test::bit_equal(io::read_stl(pb), io_test::welded_by_map(io_test::float_rounded(m))));
    CHECK(std::filesystem::file_size(pb) == 84 + 50 * m.faces.size());
    // awkward_mesh references every vertex in order, so welding gives back the same mesh.
    CHECK(io_test::bit_equal(io::read_stl(pa), m));

    SECTION("binary file whose header starts with 'solid' is still read as binary") {
        std::string bytes = io_test::slurp(pb);
        bytes.replace(0, 5, "solid");
        CHECK(io_test::bit_equal(io::parse_stl(bytes, "solid_header.stl"), io::read_stl(pb)));
    }
    SECTION("welding merges -0 and +0 and shared corners") {
        triangle_mesh soup;
        soup.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        soup.faces = {{0, 1, 2}, {3, 4, 5}};
        io::write_stl(tmp_dir() / "soup.stl", soup, io::encoding::ascii);
        const triangle_mesh r = io::read_stl(tmp_dir() / "soup.stl");
        CHECK(r.num_vertices() == 4);
        CHECK(r.faces == std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}});
    }
}

TEST_CASE("PLY round trips: ASCII exact, binary after float rounding", "[io][ply]") {
    triangle_mesh m = awkward_mesh(3);
    m.vertices.emplace_back(5.0, 6.0, 7.0);  // unreferenced vertex is kept by PLY
    const auto pa = tmp_dir() / "rt_ascii.ply", pb = tmp_dir() / "rt_bin.ply";
    io::write_ply(pa, m, io::encoding::ascii);
    io::write_ply(pb, m);
    CHECK(io_test::bit_equal(io::read_ply(pa), m));
    CHECK(io_test::bit_equal(io::read_ply(pb), io_test::float_rounded(m)));
    // header + 12 bytes per vertex + 13 per face
    const auto header = io_test::slurp(pb).find("end_header\n") + 11;
    CHECK(std::filesystem::file_size(pb) == header + 12 * m.num_vertices() + 13 * m.num_faces());
    io::write_mesh(tmp_dir() / "rt_dispatch.Ply", m);
    CHECK(io_test::bit_equal(io::read_mesh(tmp_dir() / "rt_dispatch.Ply"), io_test::float_rounded(m)));
}

TEST_CASE("PLY reads big-endian binary, extra properties, quads and other elements", "[io][ply]") {
    // Hand-built big-endian file: vertices with an extra uchar property, one quad, an edge element.
    std::string b = "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\nproperty uchar red\n"
                    "property float y\nproperty short z\nelement face 1\nproperty uchar flags\n"
                    "property list uint short vertex_indices\nelement edge 1\nproperty list uchar int vertex\nend_header\n";
    auto be = [&](auto v) { io::detail::store(b, v, io::detail::byte_order::big); };
    const double xs[] = {0.1, 1.5, 1.5, 0.1};
    const float ys[] = {0.f, 0.f, 2.25f, 2.25f};
    for (int i = 0; i < 4; ++i) be(xs[i]), be(std::uint8_t{200}), be(ys[i]), be(std::int16_t(-3));
    be(std::uint8_t{1}), be(std::uint32_t{4});
    for (std::int16_t i : {0, 1, 2, 3}) be(i);
    be(std::uint8_t{2}), be(std::int32_t{0}), be(std::int32_t{2});
    const triangle_mesh m = io::parse_ply(b, "be.ply");
    REQUIRE(m.num_vertices() == 4);
    CHECK(m.vertices[1] == vec3(1.5, 0.0, -3.0));
    CHECK(m.vertices[2] == vec3(1.5, 2.25, -3.0));
    CHECK(m.faces == std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}});
}

TEST_CASE("OBJ: slashes, negative indices, polygons, forward references", "[io][obj]") {
    const std::string text =
        "# comment\nmtllib x.mtl\nv 0 0 0\nv 1 0 0 1.0\nvt 0 0\nvn 0 0 1\nv 1 1 0 0.5 0.5 0.5\n"
        "f 1/1/1 2/1/1 -1/1/1 # trailing comment\no part\nv 0 1 0\nf -4//1 -2//1 4 5\nv 0.5 0.5 1e-3\ng g\n";
    const triangle_mesh m = io::parse_obj(text, "mixed.obj");
    REQUIRE(m.num_vertices() == 5);
    CHECK(m.vertices[4] == vec3(0.5, 0.5, 1e-3));
    CHECK(m.faces == std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}});
}

TEST_CASE("text readers accept CRLF line ends and a UTF-8 BOM (OBJ)", "[io][obj][ply][stl]") {
    const triangle_mesh a = io::parse_obj("\xEF\xBB\xBFv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n", "crlf.obj");
    CHECK(a.num_vertices() == 3);
    CHECK(a.num_faces() == 1);
    const triangle_mesh b = io::parse_ply("ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
                                          "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\n"
                                          "end_header\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n",
                                          "crlf.ply");
    CHECK(b == a);
    const triangle_mesh c = io::parse_stl("solid x\r\nfacet normal 0 0 1\r\nouter loop\r\nvertex 0 0 0\r\nvertex 1 0 0\r\n"
                                          "vertex 0 1 0\r\nendloop\r\nendfacet\r\nendsolid x\r\n",
                                          "crlf.stl");
    CHECK(c == a);
}

TEST_CASE("PLY element without properties and a huge count costs nothing", "[io][ply]") {
    const triangle_mesh m = io::parse_ply("ply\nformat ascii 1.0\nelement junk 9223372036854775807\nelement vertex 3\n"
                                          "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                                          "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                                          "junk.ply");
    CHECK(m.num_faces() == 1);
}

namespace {
struct bundled {
    const char* file;
    std::size_t v, f;
};
}  // namespace

TEST_CASE("bundled meshes match the counts in data/README.md", "[io][data]") {
    // data/README.md: V / F per file; STL vertex counts are after welding.
    const bundled table[] = {
        {"meshes/bunny.obj", 35947, 69451},        {"meshes/bunny_lowres.obj", 3485, 6966},
        {"meshes/bunny_lowres.ply", 3485, 6966},   {"meshes/bunny_normals.ply", 8670, 17336},
        {"meshes/kitten.obj", 33612, 67224},       {"meshes/kitten_lowres.obj", 2500, 5000},
        {"meshes/kitten_lowres_ascii.ply", 2500, 5000}, {"meshes/spot.obj", 2930, 5856},
        {"meshes/spot.stl", 2930, 5856},           {"meshes/fandisk.obj", 6475, 12946},
        {"meshes/fertility.obj", 4494, 9000},      {"meshes/three_holes.obj", 3596, 7200},
        {"meshes/cube.obj", 8, 12},                {"meshes/cube_ascii.stl", 8, 12},
        {"meshes/cube_subdiv.obj", 1538, 3072},    {"meshes/torus.obj", 2048, 4096},
        {"meshes/icosphere.obj", 2562, 5120}};
    for (const bundled& b : table) {
        INFO(b.file);
        const triangle_mesh m = io::read_mesh(io_test::data(b.file));
        CHECK(m.num_vertices() == b.v);
        CHECK(m.num_faces() == b.f);
        CHECK_NOTHROW(validate(m));
        // Every bundled mesh except the open full-resolution bunny is closed and outward-oriented.
        if (std::string(b.file) != "meshes/bunny.obj") CHECK(signed_volume(m) > 0);
    }
}

TEST_CASE("bundled meshes agree across formats", "[io][data]") {
    SECTION("bunny.obj has 1113 unreferenced vertices") {
        const triangle_mesh m = io::read_mesh(io_test::data("meshes/bunny.obj"));
        std::set<std::uint32_t> used;
        for (const auto& f : m.faces) used.insert(f.begin(), f.end());
        CHECK(m.num_vertices() - used.size() == 1113);
    }
    SECTION("bunny_lowres: binary PLY == OBJ rounded to float") {
        const triangle_mesh obj = io::read_obj(io_test::data("meshes/bunny_lowres.obj"));
        const triangle_mesh ply = io::read_ply(io_test::data("meshes/bunny_lowres.ply"));
        CHECK(io_test::bit_equal(ply, io_test::float_rounded(obj)));
    }
    SECTION("kitten_lowres: ASCII PLY has the OBJ's faces and (numerically) the same vertices") {
        const triangle_mesh obj = io::read_obj(io_test::data("meshes/kitten_lowres.obj"));
        const triangle_mesh ply = io::read_ply(io_test::data("meshes/kitten_lowres_ascii.ply"));
        REQUIRE(ply.num_vertices() == obj.num_vertices());
        CHECK(ply.faces == obj.faces);
        double err = 0;
        for (std::size_t i = 0; i < obj.num_vertices(); ++i) err = std::max(err, glm::length(ply.vertices[i] - obj.vertices[i]));
        CHECK(err < 1e-4);
    }
    SECTION("spot.stl has the same surface as spot.obj") {
        const triangle_mesh obj = io::read_obj(io_test::data("meshes/spot.obj"));
        const triangle_mesh stl = io::read_stl(io_test::data("meshes/spot.stl"));
        CHECK(signed_volume(stl) == Approx(signed_volume(obj)).epsilon(1e-6));
        CHECK(surface_area(stl) == Approx(surface_area(obj)).epsilon(1e-6));
        CHECK(stl.vertices.size() == obj.vertices.size());
    }
    SECTION("cube_ascii.stl has the corners of cube.obj") {
        const triangle_mesh obj = io::read_obj(io_test::data("meshes/cube.obj"));
        const triangle_mesh stl = io::read_stl(io_test::data("meshes/cube_ascii.stl"));
        auto key = [](const vec3& v) { return std::array<double, 3>{v.x, v.y, v.z}; };
        std::set<std::array<double, 3>> a, b;
        for (const auto& v : obj.vertices) a.insert(key(v));
        for (const auto& v : stl.vertices) b.insert(key(v));
        CHECK(a == b);
        CHECK(signed_volume(stl) == Approx(1.0));
    }
}
