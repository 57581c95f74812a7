// Table of malformed inputs for every reader: each must throw the right error type, and the
// message must start with "fabsynth: FILE:LINE:" (text) or "fabsynth: FILE: byte N:" (binary).
#include <catch2/catch.hpp>

#include <functional>

#include "fabsynth/io.hpp"
#include "io/io_test_util.hpp"

using namespace fabsynth;

namespace {
enum class kind { io, input };
struct bad_case {
    std::string label;
    std::function<void()> parse;
    kind expected;
    std::string where;  // message prefix after "fabsynth: "
    std::string what;   // substring of the message
};

std::string tri_obj(const std::string& face) { return "v 0 0 0\nv 1 0 0\nv 0 1 0\n" + face; }

std::string binary_stl(int facets) {
    triangle_mesh m;
    for (int i = 0; i < facets; ++i) {
        const auto b = std::uint32_t(m.vertices.size());
        m.vertices.insert(m.vertices.end(), {{double(i), 0, 0}, {double(i) + 1, 0, 0}, {double(i), 1, 0}});
        m.faces.push_back({b, b + 1, b + 2});
    }
    return io::format_stl(m, io::encoding::binary);
}
std::string put_float(std::string s, std::size_t at, float v) {
    std::string b;
    io::detail::store(b, v, io::detail::byte_order::little);
    return s.replace(at, 4, b);
}

const std::string ply_head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
const std::string ply_verts = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";

std::string binary_ply() {
    triangle_mesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.faces = {{0, 1, 2}, {0, 2, 3}};
    return io::format_ply(m, io::encoding::binary);
}

std::string png_bytes() {
    image8 img(16, 8, 1);
    for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = std::uint8_t(i * 7);
    return io::format_png(img);
}
std::string set_be32(std::string s, std::size_t at, std::uint32_t v) {
    std::string b;
    io::detail::store(b, v, io::detail::byte_order::big);
    return s.replace(at, 4, b);
}

const std::string vtk_head = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 1\n";

std::vector<bad_case> cases() {
    auto obj = [](std::string s) { return [s] { io::parse_obj(s, "bad.obj"); }; };
    auto stl = [](std::string s) { return [s] { io::parse_stl(s, "bad.stl"); }; };
    auto ply = [](std::string s) { return [s] { io::parse_ply(s, "bad.ply"); }; };
    auto png = [](std::string s) { return [s] { io::parse_png(s, "bad.png"); }; };
    auto pgm = [](std::string s) { return [s] { io::parse_pgm(s, "bad.pgm"); }; };
    auto vtk = [](std::string s) { return [s] { io::parse_vtk_structured_points(s, "bad.vtk"); }; };
    const std::string stl_ok = binary_stl(3);
    const std::string ply_ok = binary_ply();
    const std::size_t ply_body = ply_ok.find("end_header\n") + 11;
    const std::string pngs = png_bytes();
    const std::string ascii_stl_pre = "solid t\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n";
    return {
        // OBJ
        {"obj empty", obj(""), kind::io, "bad.obj: ", "empty"},
        {"obj face beyond vertices", obj(tri_obj("f 1 2 4\n")), kind::io, "bad.obj:4: ", "exceeds the 3 vertices"},
        {"obj NaN", obj("v 0 0 0\nv 1 0 nan\n"), kind::io, "bad.obj:2: ", "not finite"},
        {"obj inf", obj("v 0 0 inf\n"), kind::io, "bad.obj:1: ", "not finite"},
        {"obj 1.2.3", obj("v 0 0 1.2.3\n"), kind::io, "bad.obj:1: ", "cannot parse"},
        {"obj hex", obj("\n\nv 0 0 0x10\n"), kind::io, "bad.obj:3: ", "cannot parse"},
        {"obj overflow", obj("v 1e999 0 0\n"), kind::io, "bad.obj:1: ", "cannot parse"},
        {"obj two coords", obj("v 0 0\n"), kind::io, "bad.obj:1: ", "2 coordinates"},
        {"obj two corners", obj(tri_obj("f 1 2\n")), kind::io, "bad.obj:4: ", "2 corners"},
        {"obj index 0", obj(tri_obj("f 0 1 2\n")), kind::io, "bad.obj:4: ", "index 0"},
        {"obj relative too far", obj(tri_obj("f -4 1 2\n")), kind::io, "bad.obj:4: ", "before the first vertex"},
        {"obj index huge", obj(tri_obj("f 1 2 99999999999999\n")), kind::io, "bad.obj:4: ", "out of range"},
        {"obj index garbage", obj(tri_obj("f 1 2 3x\n")), kind::io, "bad.obj:4: ", "cannot parse"},
        {"obj forward ref missing", obj("f 1 2 3\nv 0 0 0\n"), kind::io, "bad.obj:1: ", "exceeds the 1 vertices"},
        {"obj no faces", obj("v 0 0 0\n# nothing else\n"), kind::io, "bad.obj: ", "no faces"},
        // STL
        {"stl empty", stl(""), kind::io, "bad.stl: ", "empty"},
        {"stl short junk", stl("hello"), kind::io, "bad.stl: byte 5: ", "neither"},
        {"stl truncated binary", stl(stl_ok.substr(0, stl_ok.size() - 10)), kind::io, "bad.stl: byte 80: ", "truncated"},
        {"stl huge count", stl(set_be32(stl_ok, 80, 0xffffffffu)), kind::io, "bad.stl: byte 80: ", "facets"},
        {"stl binary NaN", stl(put_float(stl_ok, 84 + 50 + 12 + 12 + 8, std::nanf(""))), kind::io, "bad.stl: byte 166: ",
         "non-finite"},
        {"stl binary inf", stl(put_float(stl_ok, 84 + 12, INFINITY)), kind::io, "bad.stl: byte 96: ", "non-finite"},
        {"stl ascii NaN", stl(ascii_stl_pre + "  vertex 0 1 nan\n endloop\nendfacet\nendsolid\n"), kind::io, "bad.stl:6: ",
         "not finite"},
        {"stl ascii garbage", stl(ascii_stl_pre + "  vertex 0 1 abc\n endloop\nendfacet\nendsolid\n"), kind::io,
         "bad.stl:6: ", "cannot parse"},
        {"stl ascii missing endloop", stl(ascii_stl_pre + "  vertex 0 1 0\nendfacet\nendsolid\n"), kind::io, "bad.stl:7: ",
         "'endloop'"},
        {"stl ascii truncated", stl(ascii_stl_pre + "  vertex 0 1"), kind::io, "bad.stl:6: ", "end of file"},
        {"stl ascii two vertices", stl(ascii_stl_pre + " endloop\nendfacet\nendsolid\n"), kind::io, "bad.stl:6: ",
         "2 vertices"},
        {"stl ascii no facets", stl("solid x\nendsolid x\n"), kind::io, "bad.stl: ", "no facets"},
        // PLY
        {"ply empty", ply(""), kind::io, "bad.ply: ", "empty"},
        {"ply magic", ply("plyx\n"), kind::io, "bad.ply:1: ", "not a PLY"},
        {"ply format", ply("ply\nformat binary_middle_endian 1.0\n"), kind::io, "bad.ply:2: ", "unknown PLY format"},
        {"ply unknown type", ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty flt x\n"), kind::io, "bad.ply:4: ",
         "unknown property type"},
        {"ply count beyond file", ply("ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n"
                                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n"),
         kind::io, "bad.ply:3: ", "cannot hold"},
        {"ply missing z", ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n"),
         kind::io, "bad.ply:3: ", "lacks x, y or z"},
        {"ply too few vertices", ply(ply_head + "0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n3 0 2 3\n"), kind::io, "bad.ply:13: ",
         "unexpected '2'"},
        {"ply too few faces", ply(ply_head + ply_verts + "3 0 1 2\n"), kind::io, "bad.ply:15: ", "end of file"},
        {"ply data left over", ply(ply_head + ply_verts + "3 0 1 2\n3 0 2 3\n3 0 1 3\n"), kind::io, "bad.ply:16: ",
         "data left"},
        {"ply index out of range", ply(ply_head + ply_verts + "3 0 1 2\n3 0 2 4\n"), kind::io, "bad.ply:15: ",
         "indexes vertex 4"},
        {"ply negative index", ply(ply_head + ply_verts + "3 0 1 2\n3 0 -1 3\n"), kind::io, "bad.ply:15: ",
         "indexes vertex -1"},
        {"ply NaN", ply(ply_head + "0 0 0\n1 nan 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"), kind::io, "bad.ply:11: ",
         "non-finite"},
        {"ply garbage number", ply(ply_head + "0 0 0\n1 0x 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"), kind::io, "bad.ply:11: ", "cannot parse"},
        {"ply two corners", ply(ply_head + ply_verts + "2 0 1\n"), kind::io, "bad.ply:14: ", "2 corners"},
        {"ply uchar overflow", ply(ply_head + ply_verts + "300 0 1 2\n"), kind::io, "bad.ply:14: ", "out of range"},
        {"ply binary truncated", ply(ply_ok.substr(0, ply_ok.size() - 5)), kind::io,
         "bad.ply: byte " + std::to_string(ply_ok.size() - 13) + ": ", "runs past the end"},
        {"ply binary trailing", ply(ply_ok + "xyz"), kind::io, "bad.ply: byte " + std::to_string(ply_ok.size()) + ": ",
         "bytes left"},
        {"ply binary bad index", ply(set_be32(ply_ok, ply_body + 48 + 13 + 1 + 8, 0x05000000u)), kind::io,
         "bad.ply: byte " + std::to_string(ply_body + 48 + 13 + 1 + 8) + ": ", "indexes vertex 5"},
        {"ply binary NaN", ply(put_float(ply_ok, ply_body + 16, std::nanf(""))), kind::io,
         "bad.ply: byte " + std::to_string(ply_body + 16) + ": ", "non-finite"},
        {"ply binary huge count", ply("ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                                      "end_header\n" + std::string(100, '\0')),
         kind::io, "bad.ply:3: ", "cannot hold"},
        // PNG
        {"png empty", png(""), kind::io, "bad.png: ", "empty"},
        {"png not png", png("GIF89a........"), kind::io, "bad.png: byte 0: ", "not a PNG"},
        {"png truncated", png(pngs.substr(0, pngs.size() / 2)), kind::io, "bad.png: ", "corrupt"},
        {"png giant", png(set_be32(set_be32(pngs, 16, 20000), 20, 20000)), kind::input, "bad.png: ", "exceeds the limit"},
        {"png bad CRC", png(set_be32(pngs, 29, 0)), kind::io, "bad.png: ", "checksum"},
        {"png zero width", png(set_be32(pngs, 16, 0)), kind::io, "bad.png: ", "corrupt PNG header"},
        {"png only signature", png(pngs.substr(0, 8)), kind::io, "bad.png: ", "corrupt PNG header"},
        {"png garbage IDAT", png(pngs.substr(0, pngs.find("IDAT") + 8) + std::string(64, 'x')), kind::io, "bad.png: ", "corrupt"},
        // PGM
        {"pgm empty", pgm(""), kind::io, "bad.pgm: ", "empty"},
        {"pgm magic", pgm("P6\n1 1\n255\n\xff\xff\xff"), kind::io, "bad.pgm:1: ", "not a PGM"},
        {"pgm too few", pgm("P2\n2 2\n255\n0 1 2\n"), kind::io, "bad.pgm:5: ", "end of file"},
        {"pgm above maxval", pgm("P2\n2 1\n10\n0 11\n"), kind::io, "bad.pgm:4: ", "out of range"},
        {"pgm garbage", pgm("P2\n2 1\n10\n0 1.5\n"), kind::io, "bad.pgm:4: ", "cannot parse"},
        {"pgm negative width", pgm("P2\n-3 2\n255\n"), kind::io, "bad.pgm:2: ", "out of range"},
        {"pgm maxval 0", pgm("P2 2 2 0\n"), kind::io, "bad.pgm:1: ", "out of range"},
        {"pgm 16 bit to read_pgm", pgm("P5 1 1 65535\n\x01\x02"), kind::io, "bad.pgm:1: ", "read_pgm16"},
        {"pgm P5 truncated", pgm("P5 4 4 255\n" + std::string(10, 'x')), kind::io, "bad.pgm: byte 21: ", "truncated"},
        {"pgm giant", pgm("P2\n100000 100000\n255\n"), kind::input, "bad.pgm: ", "exceeds the limit"},
        // VTK
        {"vtk empty", vtk(""), kind::io, "bad.vtk: ", "empty"},
        {"vtk magic", vtk("# vtk Data\n"), kind::io, "bad.vtk:1: ", "not a legacy VTK"},
        {"vtk encoding", vtk("# vtk DataFile Version 3.0\nt\nHEX\n"), kind::io, "bad.vtk:3: ", "ASCII or BINARY"},
        {"vtk polydata", vtk("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n"), kind::io, "bad.vtk:4: ",
         "STRUCTURED_POINTS"},
        {"vtk dims 0", vtk("# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 0 1\n"), kind::io,
         "bad.vtk:5: ", "out of range"},
        {"vtk count mismatch", vtk(vtk_head + "POINT_DATA 5\n"), kind::io, "bad.vtk:6: ", "does not match"},
        {"vtk too few values", vtk(vtk_head + "POINT_DATA 4\nSCALARS a double\nLOOKUP_TABLE default\n1 2 3\n"), kind::io,
         "bad.vtk:", "end of file"},
        {"vtk NaN", vtk(vtk_head + "POINT_DATA 4\nSCALARS a double 1\n1 nan 3 4\n"), kind::io, "bad.vtk:8: ", "not finite"},
        {"vtk bad type", vtk(vtk_head + "POINT_DATA 4\nSCALARS a bit\n0 1 0 1\n"), kind::io, "bad.vtk:7: ", "unsupported data type"},
        {"vtk unknown attribute", vtk(vtk_head + "POINT_DATA 4\nTEXTURE_COORDINATES t 2 float\n"), kind::io, "bad.vtk:7: ",
         "unsupported"},
        {"vtk binary truncated",
         vtk("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 1\nPOINT_DATA 4\n"
             "SCALARS a double\nLOOKUP_TABLE default\n" + std::string(20, '\0')),
         kind::io, "bad.vtk: byte 130: ", "truncated"},
        {"vtk huge", vtk("# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 100000 100000 100\n"),
         kind::input, "bad.vtk:5: ", "exceeds the limit"},
    };
}
}  // namespace

TEST_CASE("every reader rejects malformed input with the file and location", "[io][malformed]") {
    for (const bad_case& c : cases()) {
        INFO(c.label);
        std::string msg;
        bool right_type = false;
        try {
            c.parse();
        } catch (const io_error& e) {
            msg = e.what(), right_type = c.expected == kind::io;
        } catch (const invalid_input& e) {
            msg = e.what(), right_type = c.expected == kind::input;
        } catch (const std::exception& e) {
            msg = std::string("unexpected exception type: ") + e.what();
        }
        INFO(msg);
        CHECK(right_type);
        CHECK(msg.rfind("fabsynth: " + c.where, 0) == 0);
        CHECK(msg.find(c.what) != std::string::npos);
    }
}

TEST_CASE("file-level errors name the file; failed writes leave no file behind", "[io][malformed]") {
    const auto dir = io_test::tmp_dir();
    CHECK_THROWS_WITH(io::read_mesh(dir / "missing.obj"), Catch::Contains("missing.obj") && Catch::Contains("does not exist"));
    CHECK_THROWS_AS(io::read_mesh(dir / "mesh.xyz"), invalid_input);
    CHECK_THROWS_AS(io::read_png(dir), io_error);  // a directory
    triangle_mesh bad;
    bad.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, std::nan("")}};
    bad.faces = {{0, 1, 2}};
    for (const char* f : {"nan.obj", "nan.stl", "nan.ply"}) {
        CHECK_THROWS_AS(io::write_mesh(dir / f, bad), invalid_input);
        CHECK_FALSE(std::filesystem::exists(dir / f));
    }
    bad.vertices[2].z = 0;
    bad.faces = {{0, 1, 3}};
    CHECK_THROWS_AS(io::write_mesh(dir / "idx.obj", bad), invalid_input);
    bad.faces = {{0, 1, 2}};
    CHECK_THROWS_AS(io::write_mesh(dir / "no_such_dir" / "m.obj", bad), io_error);
    bad.vertices[2].z = 1e300;  // finite but not a float
    CHECK_THROWS_AS(io::write_mesh(dir / "big.stl", bad), invalid_input);
}

TEST_CASE("atomic_write replaces the target and leaves no temporary behind", "[io][atomic]") {
    const auto dir = io_test::tmp_dir() / "atomic";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    io::atomic_write(dir / "a.txt", "first");
    io::atomic_write(dir / "a.txt", "second, longer");
    CHECK(io_test::slurp(dir / "a.txt") == "second, longer");
    CHECK_THROWS_AS(io::atomic_write(dir, "x"), io_error);  // the directory itself
    CHECK(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()) == 1);
}
