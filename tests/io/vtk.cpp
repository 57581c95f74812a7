// Tests for io/vtk.hpp: structured points round trips and the layout of mesh / unstructured output.
#include <catch2/catch.hpp>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/io/detail/text.hpp"
#include "fabsynth/io/vtk.hpp"
#include "io/io_test_util.hpp"

using namespace fabsynth;
using io_test::tmp_dir;

namespace {
io::vtk_field random_field(std::string name, int comps, std::uint64_t count, std::uint64_t seed) {
    io::vtk_field f{std::move(name), comps, {}};
    counter_rng r(seed);
    for (std::uint64_t i = 0; i < count * std::uint64_t(comps); ++i) f.values.push_back(r.normal() * std::pow(10.0, r.uniform(-8, 8)));
    return f;
}

/// Every whitespace-separated token of an ASCII file.
std::vector<std::string> tokens(const std::string& s) {
    std::vector<std::string> out;
    io::detail::token_cursor c(s, "t");
    for (auto t = c.next(); !t.empty(); t = c.next()) out.emplace_back(t);
    return out;
}
}  // namespace

TEST_CASE("VTK structured points round trip exactly (ASCII and binary, point and cell data)", "[io][vtk]") {
    for (bool cells : {false, true})
        for (auto enc : {io::encoding::ascii, io::encoding::binary}) {
            io::structured_points g;
            g.dims = {5, 4, 3};
            g.origin = {-1.25, 0.1, 1e-3};
            g.spacing = {0.5, 1.0 / 3.0, 2.0};
            g.cell_data = cells;
            const std::uint64_t n = g.value_count();
            CHECK(n == (cells ? 4u * 3u * 2u : 60u));
            g.fields = {random_field("density 100%", 1, n, 1), random_field("disp", 3, n, 2), random_field("stress", 6, n, 3),
                        random_field("rgba", 4, n, 4)};
            const auto p = tmp_dir() / "grid.vtk";
            io::write_vtk(p, g, enc);
            const io::structured_points r = io::read_vtk_structured_points(p);
            CHECK(r == g);
        }
    // Flat grids: a 2D image as a 1-cell-thick slab.
    io::structured_points flat;
    flat.dims = {4, 3, 1};
    flat.cell_data = true;
    CHECK(flat.value_count() == 6);
    flat.fields = {random_field("m", 1, 6, 9)};
    io::write_vtk(tmp_dir() / "flat.vtk", flat);
    CHECK(io::read_vtk_structured_points(tmp_dir() / "flat.vtk") == flat);
}

TEST_CASE("VTK reader accepts what VTK/ParaView write", "[io][vtk]") {
    const std::string ascii =
        "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 1\n"
        "SPACING 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 4\nSCALARS occ unsigned_char\nLOOKUP_TABLE default\n0 1 1 0\n"
        "METADATA\nINFORMATION 0\n\nFIELD FieldData 1\nv%20w 2 4 float\n1 2 3 4 5 6 7 8\n"
        "VECTORS n double\n0 0 1 0 0 1 0 0 1 0 0 1\n";
    const io::structured_points g = io::parse_vtk_structured_points(ascii, "pv.vtk");
    CHECK(g.dims == ivec3(2, 2, 1));
    REQUIRE(g.fields.size() == 3);
    CHECK(g.fields[0].values == std::vector<double>{0, 1, 1, 0});
    CHECK(g.fields[1].components == 2);
    CHECK(g.fields[1].name == "v w");  // %20 decoded as vtkDataReader does
    CHECK(g.fields[1].values.back() == 8.0);
    CHECK(g.fields[2].components == 3);

    std::string bin = "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 3 1 1\n"
                      "ORIGIN 0 0 0\nSPACING 1 1 1\nCELL_DATA 2\nSCALARS s float 1\nLOOKUP_TABLE default\n";
    io::detail::store(bin, 1.5f, io::detail::byte_order::big);
    io::detail::store(bin, -2.0f, io::detail::byte_order::big);
    bin += "\nSCALARS i short\nLOOKUP_TABLE default\n";
    io::detail::store(bin, std::int16_t(-7), io::detail::byte_order::big);
    io::detail::store(bin, std::int16_t(10), io::detail::byte_order::big);
    bin += "\n";
    const io::structured_points b = io::parse_vtk_structured_points(bin, "b.vtk");
    CHECK(b.cell_data);
    REQUIRE(b.fields.size() == 2);
    CHECK(b.fields[0].values == std::vector<double>{1.5, -2.0});
    CHECK(b.fields[1].values == std::vector<double>{-7, 10});
}

TEST_CASE("VTK mesh output has the documented layout", "[io][vtk]") {
    const triangle_mesh m = io_test::awkward_mesh(7, 30);
    const auto pf = random_field("curv", 1, m.num_vertices(), 5);
    const auto cf = random_field("normal", 3, m.num_faces(), 6);
    const auto pa = tmp_dir() / "mesh_ascii.vtk", pb = tmp_dir() / "mesh_bin.vtk";
    io::write_vtk(pa, m, {pf}, {cf}, io::encoding::ascii);
    io::write_vtk(pb, m, {pf}, {cf});
    // ASCII: parse the tokens independently and compare numbers exactly.
    const auto t = tokens(io_test::slurp(pa));
    std::size_t i = 0;
    while (i < t.size() && t[i] != "POINTS") ++i;
    REQUIRE(i + 2 < t.size());
    CHECK(std::stoul(t[i + 1]) == m.num_vertices());
    CHECK(t[i + 2] == "double");
    i += 3;
    for (const vec3& v : m.vertices)
        for (int a = 0; a < 3; ++a) CHECK(*io::detail::to_double(t[i++]) == v[a]);
    REQUIRE(t[i] == "POLYGONS");
    CHECK(std::stoul(t[i + 1]) == m.num_faces());
    CHECK(std::stoul(t[i + 2]) == 4 * m.num_faces());
    i += 3;
    for (const auto& f : m.faces) {
        CHECK(t[i++] == "3");
        for (auto v : f) CHECK(std::stoul(t[i++]) == v);
    }
    CHECK(t[i] == "CELL_DATA");
    CHECK(std::stoul(t[i + 1]) == m.num_faces());
    // Binary: big-endian doubles at known offsets.
    const std::string b = io_test::slurp(pb);
    const std::string head = "POINTS " + std::to_string(m.num_vertices()) + " double\n";
    const auto at = b.find(head);
    REQUIRE(at != std::string::npos);
    const std::size_t p0 = at + head.size();
    CHECK(io::detail::load<double>(b.data() + p0 + 8, io::detail::byte_order::big) == m.vertices[0].y);
    CHECK(b.compare(p0 + 24 * m.num_vertices(), 10, "\nPOLYGONS ") == 0);
    const std::size_t poly = b.find('\n', p0 + 24 * m.num_vertices() + 1) + 1;
    CHECK(io::detail::load<std::int32_t>(b.data() + poly, io::detail::byte_order::big) == 3);
    CHECK(io::detail::load<std::int32_t>(b.data() + poly + 4, io::detail::byte_order::big) == std::int32_t(m.faces[0][0]));
    CHECK(b.compare(poly + 16 * m.num_faces(), 11, "\nCELL_DATA ") == 0);

    CHECK_THROWS_AS(io::write_vtk(tmp_dir() / "bad.vtk", m, {random_field("x", 1, 3, 1)}), invalid_input);
    CHECK_THROWS_AS(io::write_vtk(tmp_dir() / "bad.vtk", m, {random_field("", 1, m.num_vertices(), 1)}), invalid_input);
    auto nan = pf;
    nan.values[3] = std::nan("");
    CHECK_THROWS_AS(io::write_vtk(tmp_dir() / "bad.vtk", m, {nan}), invalid_input);
    CHECK_FALSE(std::filesystem::exists(tmp_dir() / "bad.vtk"));
}

TEST_CASE("VTK unstructured grid output: header, counts, connectivity", "[io][vtk]") {
    // Two hexahedra sharing a face + one wedge on top.
    std::vector<vec3> pts;
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x) pts.emplace_back(x, y, z);
    pts.emplace_back(0, 0.5, 2);
    pts.emplace_back(1, 0.5, 2);
    const std::vector<io::vtk_cell> cells = {{12, {0, 1, 4, 3, 6, 7, 10, 9}}, {12, {1, 2, 5, 4, 7, 8, 11, 10}},
                                             {13, {6, 9, 12, 7, 10, 13}}};
    const io::vtk_field vm = random_field("von_mises", 1, 3, 3);
    const io::vtk_field u = random_field("u", 3, pts.size(), 4);
    const auto pa = tmp_dir() / "ug_ascii.vtk", pb = tmp_dir() / "ug_bin.vtk";
    io::write_vtk_unstructured(pa, pts, cells, {u}, {vm}, io::encoding::ascii);
    io::write_vtk_unstructured(pb, pts, cells, {u}, {vm});
    const auto t = tokens(io_test::slurp(pa));
    auto find = [&](const std::string& w) { return std::size_t(std::find(t.begin(), t.end(), w) - t.begin()); };
    CHECK(t[find("DATASET") + 1] == "UNSTRUCTURED_GRID");
    CHECK(t[find("POINTS") + 1] == "14");
    std::size_t c = find("CELLS");
    CHECK(t[c + 1] == "3");
    CHECK(t[c + 2] == std::to_string(9 + 9 + 7));
    c += 3;
    for (const auto& cell : cells) {
        CHECK(std::stoul(t[c++]) == cell.nodes.size());
        for (auto n : cell.nodes) CHECK(std::stoul(t[c++]) == n);
    }
    CHECK(t[c] == "CELL_TYPES");
    CHECK(t[c + 2] == "12");
    CHECK(t[c + 4] == "13");
    CHECK(t[find("CELL_DATA") + 1] == "3");
    CHECK(t[find("POINT_DATA") + 1] == "14");
    CHECK(*io::detail::to_double(t[find("von_mises") + 5]) == vm.values[0]);  // SCALARS name double 1 LOOKUP_TABLE default v0
    // Binary: size is fully determined by the counts.
    const std::string b = io_test::slurp(pb);
    const std::string cells_head = "CELLS 3 25\n";
    const auto at = b.find(cells_head);
    REQUIRE(at != std::string::npos);
    CHECK(b.compare(at + cells_head.size() + 4 * 25, 14, "\nCELL_TYPES 3\n") == 0);

    CHECK_THROWS_AS(io::write_vtk_unstructured(tmp_dir() / "bad.vtk", pts, {{12, {0, 1, 2}}}), invalid_input);
    CHECK_THROWS_AS(io::write_vtk_unstructured(tmp_dir() / "bad.vtk", pts, {{5, {0, 1, 99}}}), invalid_input);
    CHECK_THROWS_AS(io::write_vtk_unstructured(tmp_dir() / "bad.vtk", pts, {{200, {0}}}), invalid_input);
}

TEST_CASE("VTK reader refuses huge grids before allocating", "[io][vtk]") {
    const std::string huge = "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 10000 10000 10000\n"
                             "POINT_DATA 1000000000000\nSCALARS a float\n";
    CHECK_THROWS_AS(io::parse_vtk_structured_points(huge, "huge.vtk"), invalid_input);
    io::structured_points g;
    g.dims = {100000, 100000, 100};
    CHECK_THROWS_AS(io::write_vtk(tmp_dir() / "huge.vtk", g), invalid_input);
}
