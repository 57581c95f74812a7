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

namespace {
/// A field of `type` with values that type holds exactly (extremes included).
io::vtk_field typed_field(std::string name, int comps, std::uint64_t count, io::vtk_type type, std::uint64_t seed) {
    io::vtk_field f{std::move(name), comps, {}, type};
    counter_rng r(seed);
    for (std::uint64_t i = 0; i < count * std::uint64_t(comps); ++i) {
        switch (type) {
            case io::vtk_type::uint8: f.values.push_back(double(r.uniform_int(256))); break;
            case io::vtk_type::uint16: f.values.push_back(double(r.uniform_int(65536))); break;
            case io::vtk_type::int32: f.values.push_back(double(std::int64_t(r.uniform_int(1ULL << 32)) - (1LL << 31))); break;
            case io::vtk_type::float32: f.values.push_back(io_test::to_float(r.normal() * std::pow(10.0, r.uniform(-30, 30)))); break;
            case io::vtk_type::float64: f.values.push_back(r.normal() * std::pow(10.0, r.uniform(-100, 100))); break;
        }
    }
    if (type == io::vtk_type::uint8) f.values[0] = 0, f.values[1] = 255;
    if (type == io::vtk_type::int32) f.values[0] = -2147483648.0, f.values[1] = 2147483647.0;
    return f;
}
constexpr io::vtk_type all_types[] = {io::vtk_type::uint8, io::vtk_type::uint16, io::vtk_type::int32, io::vtk_type::float32,
                                      io::vtk_type::float64};
}  // namespace

TEST_CASE("VTK fields keep their type: each round-trips exactly in both encodings", "[io][vtk]") {
    for (bool cells : {false, true})
        for (auto enc : {io::encoding::ascii, io::encoding::binary}) {
            io::structured_points g;
            g.dims = {4, 3, 5};
            g.cell_data = cells;
            const std::uint64_t n = g.value_count();
            int k = 0;
            for (io::vtk_type t : all_types) {
                const auto name = [&](char c) {  // (not "s" + to_string(k): GCC 12 -Wrestrict false positive)
                    std::string s(1, c);
                    return s.append(std::to_string(k));
                };
                g.fields.push_back(typed_field(name('s'), 1, n, t, 40 + std::uint64_t(k)));
                g.fields.push_back(typed_field(name('v'), 3, n, t, 50 + std::uint64_t(k)));
                g.fields.push_back(typed_field(name('t'), 6, n, t, 60 + std::uint64_t(k)));  // a FIELD array
                ++k;
            }
            const auto p = tmp_dir() / "typed.vtk";
            io::write_vtk(p, g, enc);
            const io::structured_points r = io::read_vtk_structured_points(p);
            CHECK(r == g);
            const std::string text = io_test::slurp(p);
            for (const char* name : {"unsigned_char", "unsigned_short", " int", " float", " double"})
                CHECK(text.find(name) != std::string::npos);
        }
}

TEST_CASE("VTK file size follows the field type", "[io][vtk]") {
    io::structured_points g;
    g.dims = {65, 65, 65};  // 64^3 cells
    g.cell_data = true;
    const std::uint64_t n = g.value_count();
    std::uintmax_t size[5] = {};
    for (int k = 0; k < 5; ++k) {
        g.fields = {typed_field("solid", 1, n, all_types[k], 3)};
        for (double& v : g.fields[0].values) v = std::fmod(std::abs(v), 2.0) < 1 ? 0.0 : 1.0;  // a 0/1 mask in any type
        const auto p = tmp_dir() / ("size" + std::to_string(k) + ".vtk");
        io::write_vtk(p, g);
        size[k] = std::filesystem::file_size(p);
        INFO(io::vtk_type_name(all_types[k]));
        CHECK(size[k] > n);
    }
    const double dbl = double(size[4]);
    CHECK(double(size[0]) / dbl == Approx(1.0 / 8).epsilon(0.01));  // unsigned_char
    CHECK(double(size[1]) / dbl == Approx(2.0 / 8).epsilon(0.01));  // unsigned_short
    CHECK(double(size[2]) / dbl == Approx(4.0 / 8).epsilon(0.01));  // int
    CHECK(double(size[3]) / dbl == Approx(4.0 / 8).epsilon(0.01));  // float
}

TEST_CASE("VTK writers refuse values their type cannot hold; mesh and unstructured writers take types", "[io][vtk]") {
    io::structured_points g;
    g.dims = {2, 2, 1};
    auto bad = [&](io::vtk_type t, double v, const char* what) {
        io::vtk_field f{"f", 1, {0, 1, 2, v}, t};
        g.fields = {f};
        INFO(io::vtk_type_name(t) << " " << v);
        CHECK_THROWS_WITH(io::write_vtk(tmp_dir() / "bad_typed.vtk", g), Catch::Contains(what) && Catch::Contains("value 3"));
        CHECK_FALSE(std::filesystem::exists(tmp_dir() / "bad_typed.vtk"));
    };
    bad(io::vtk_type::uint8, 256, "whole number");
    bad(io::vtk_type::uint8, -1, "whole number");
    bad(io::vtk_type::uint8, 0.5, "whole number");
    bad(io::vtk_type::uint16, 65536, "whole number");
    bad(io::vtk_type::int32, 2147483648.0, "whole number");
    bad(io::vtk_type::float32, 1e39, "does not fit a float");
    // float32 rounds to the nearest float.
    g.fields = {{"f", 1, {0.1, 1.0 / 3.0, -1e-30, 7}, io::vtk_type::float32}};
    io::write_vtk(tmp_dir() / "f32.vtk", g, io::encoding::ascii);
    CHECK(io::read_vtk_structured_points(tmp_dir() / "f32.vtk").fields[0].values ==
          std::vector<double>{io_test::to_float(0.1), io_test::to_float(1.0 / 3.0), io_test::to_float(-1e-30), 7.0});
    // ASCII readers check integer types too.
    const std::string head = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 1 1\nPOINT_DATA 2\n";
    CHECK_THROWS_WITH(io::parse_vtk_structured_points(head + "SCALARS m unsigned_char\n0 300\n", "u8.vtk"),
                      Catch::StartsWith("fabsynth: u8.vtk:8: ") && Catch::Contains("whole number"));
    CHECK_THROWS_AS(io::parse_vtk_structured_points(head + "SCALARS m int\n0 1.5\n", "i.vtk"), io_error);

    // Mesh (POLYDATA) and unstructured writers store each field in its type.
    const triangle_mesh m = io_test::awkward_mesh(7, 30);
    io::vtk_field label{"label", 1, std::vector<double>(m.num_faces(), 3.0), io::vtk_type::uint8};
    io::vtk_field normal = typed_field("n", 3, m.num_vertices(), io::vtk_type::float32, 9);
    io::write_vtk(tmp_dir() / "mesh_typed.vtk", m, {normal}, {label}, io::encoding::ascii);
    const auto t = tokens(io_test::slurp(tmp_dir() / "mesh_typed.vtk"));
    const auto at = std::size_t(std::find(t.begin(), t.end(), "label") - t.begin());
    REQUIRE(at + 5 < t.size());
    CHECK(t[at + 1] == "unsigned_char");
    CHECK(t[at + 5] == "3");
    const auto nf = std::size_t(std::find(t.begin(), t.end(), "n") - t.begin());
    CHECK(t[nf + 1] == "float");
    io::write_vtk(tmp_dir() / "mesh_typed_bin.vtk", m, {}, {label});
    io::write_vtk(tmp_dir() / "mesh_double_bin.vtk", m, {}, {{"label", 1, label.values}});
    CHECK(std::filesystem::file_size(tmp_dir() / "mesh_double_bin.vtk") - std::filesystem::file_size(tmp_dir() / "mesh_typed_bin.vtk") ==
          7 * m.num_faces() - 7);  // 7 bytes less per value, but "unsigned_char" is 7 letters longer than "double"
    const std::vector<vec3> pts = {{0, 0, 0}, {1, 0, 0}};
    io::write_vtk_unstructured(tmp_dir() / "ug_typed.vtk", pts, {{io::vtk_cell_type::line, {0, 1}}}, {},
                               {{"id", 1, {-5}, io::vtk_type::int32}}, io::encoding::ascii);
    const auto u = tokens(io_test::slurp(tmp_dir() / "ug_typed.vtk"));
    const auto id = std::size_t(std::find(u.begin(), u.end(), "id") - u.begin());
    REQUIRE(id + 5 < u.size());
    CHECK(u[id + 1] == "int");
    CHECK(u[id + 5] == "-5");
    CHECK_THROWS_AS(io::write_vtk_unstructured(tmp_dir() / "ug_bad.vtk", pts, {{io::vtk_cell_type::line, {0, 1}}}, {},
                                               {{"id", 1, {300}, io::vtk_type::uint8}}),
                    invalid_input);
}
