// Tests for io/mesh_3mf.hpp (built when fabsynth::lib3mf is linked): round trips through lib3mf,
// units, and refused input.
#include <catch2/catch.hpp>

#if defined(FABSYNTH_HAS_LIB3MF)

#include "fabsynth/io/mesh.hpp"
#include "fabsynth/io/mesh_3mf.hpp"
#include "io/io_test_util.hpp"

using namespace fabsynth;
using io_test::tmp_dir;

// lib3mf 1.8.1 (Debian bookworm) leaks about 0.5 KB of libzip state on every read, also on
// success; nothing the caller can free. Suppressed for LeakSanitizer in this test binary only.
#if defined(__SANITIZE_ADDRESS__)
#define FABSYNTH_TEST_LSAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FABSYNTH_TEST_LSAN 1
#endif
#endif
#if defined(FABSYNTH_TEST_LSAN)
extern "C" const char* __lsan_default_suppressions() { return "leak:libzip.so\n"; }
#endif

namespace {
/// lib3mf 1.x prints coordinates cut to 6 decimals: each reads back within 1e-6 (plus the float
/// rounding of the parsed decimal) of the float the writer was given.
bool within_print_precision(const triangle_mesh& back, const triangle_mesh& written) {
    if (back.faces != written.faces || back.vertices.size() != written.vertices.size()) return false;
    for (std::size_t i = 0; i < back.vertices.size(); ++i)
        for (int a = 0; a < 3; ++a) {
            const double f = io_test::to_float(written.vertices[i][a]);
            if (!(std::abs(back.vertices[i][a] - f) <= 1e-6 + 1.2e-7 * std::abs(f))) return false;
        }
    return true;
}
}  // namespace

TEST_CASE("3MF round trip keeps triangles and positions to float / 6-decimal precision", "[io][3mf]") {
    const triangle_mesh spot = io::read_mesh(io_test::data("meshes/spot.stl"));
    REQUIRE(spot.num_faces() > 1000);
    const auto p = tmp_dir() / "spot.3mf";
    io::write_3mf(p, spot);
    const std::string bytes = io_test::slurp(p);
    CHECK(bytes.substr(0, 2) == "PK");  // a ZIP package
    const triangle_mesh back = io::read_3mf(p);
    CHECK(back.faces == spot.faces);
    CHECK(within_print_precision(back, spot));
    // Coordinates of a printable part (|x| <= 200 mm, with many digits).
    triangle_mesh m;
    counter_rng r(7);
    for (int i = 0; i < 300; ++i) m.vertices.emplace_back(r.uniform(-200, 200), r.uniform(-1, 1), r.uniform(0, 1e-3));
    for (std::uint32_t i = 0; i + 2 < 300; i += 3) m.faces.push_back({i, i + 1, i + 2});
    io::write_3mf(p, m, {.name = "digits"});
    CHECK(within_print_precision(io::read_3mf(p), m));
    // Reproducible: the same mesh gives the same bytes (no random UUIDs), another mesh others.
    io::write_3mf(p, spot);
    CHECK(io_test::slurp(p) == bytes);
    CHECK(io::format_3mf(spot, {.name = "other"}) != bytes);
}

TEST_CASE("3MF face colours: written per triangle, read back exactly; none reads as transparent", "[io][3mf]") {
    const triangle_mesh spot = io::read_mesh(io_test::data("meshes/spot.stl"));
    std::vector<std::array<std::uint8_t, 3>> colours(spot.num_faces());
    for (std::size_t f = 0; f < colours.size(); ++f)
        colours[f] = {static_cast<std::uint8_t>(f), static_cast<std::uint8_t>(f * 7 + 3), static_cast<std::uint8_t>(255 - f % 251)};
    const auto p = tmp_dir() / "spot_colours.3mf";
    io::write_3mf(p, spot, {.name = "coloured", .face_colours = colours});
    std::vector<std::array<std::uint8_t, 4>> rgba;
    const triangle_mesh back = io::read_3mf(p, &rgba);
    CHECK(back.faces == spot.faces);
    REQUIRE(rgba.size() == spot.num_faces());
    std::size_t wrong = 0;
    for (std::size_t f = 0; f < rgba.size(); ++f)
        wrong += rgba[f] != std::array<std::uint8_t, 4>{colours[f][0], colours[f][1], colours[f][2], 255};
    CHECK(wrong == 0);
    // the colours are part of the content: other colours, other bytes; the same, the same bytes
    CHECK(io::format_3mf(spot, {.name = "coloured", .face_colours = colours}) == io_test::slurp(p));
    colours[5][0] ^= 1;
    CHECK(io::format_3mf(spot, {.name = "coloured", .face_colours = colours}) != io_test::slurp(p));
    // a file without colours reads as {0, 0, 0, 0} per face
    io::write_3mf(p, spot);
    rgba.clear();
    (void)io::read_3mf(p, &rgba);
    CHECK(rgba.size() == spot.num_faces());
    CHECK(std::all_of(rgba.begin(), rgba.end(), [](const auto& c) { return c == std::array<std::uint8_t, 4>{0, 0, 0, 0}; }));
    // one colour per face or none
    colours.pop_back();
    CHECK_THROWS_AS(io::format_3mf(spot, {.face_colours = colours}), invalid_input);
}

TEST_CASE("3MF units: coordinates are declared in the given unit and read in mm", "[io][3mf]") {
    triangle_mesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 4}};
    m.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    const auto p = tmp_dir() / "inch.3mf";
    io::write_3mf(p, m, {.unit = io::unit_3mf::inch});
    const triangle_mesh r = io::read_3mf(p);
    REQUIRE(r.faces == m.faces);
    for (std::size_t i = 0; i < m.vertices.size(); ++i) CHECK(r.vertices[i] == m.vertices[i] * 25.4);
    io::write_3mf(p, m, {.unit = io::unit_3mf::micrometer});
    CHECK(io::read_3mf(p).vertices[3].z == Approx(0.004));
}

TEST_CASE("3MF writer and reader refuse bad input", "[io][3mf][malformed]") {
    const auto dir = tmp_dir();
    triangle_mesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    CHECK_THROWS_AS(io::write_3mf(dir / "empty.3mf", m), invalid_input);  // no faces
    m.faces = {{0, 1, 2}};
    m.vertices[2].y = std::nan("");
    CHECK_THROWS_AS(io::write_3mf(dir / "nan.3mf", m), invalid_input);
    m.vertices[2].y = 1e300;
    CHECK_THROWS_AS(io::write_3mf(dir / "big.3mf", m), invalid_input);
    m.vertices[2].y = 1;
    m.faces = {{0, 1, 1}};
    CHECK_THROWS_WITH(io::write_3mf(dir / "degenerate.3mf", m), Catch::Contains("face 0 repeats a vertex"));
    m.faces = {{0, 1, 3}};
    CHECK_THROWS_AS(io::write_3mf(dir / "index.3mf", m), invalid_input);
    for (const char* f : {"empty.3mf", "nan.3mf", "big.3mf", "degenerate.3mf", "index.3mf"}) CHECK_FALSE(std::filesystem::exists(dir / f));
    m.faces = {{0, 1, 2}};
    CHECK_THROWS_AS(io::write_3mf(dir / "no_such_dir" / "m.3mf", m), io_error);

    CHECK_THROWS_WITH(io::parse_3mf("", "bad.3mf"), Catch::StartsWith("fabsynth: bad.3mf: ") && Catch::Contains("empty"));
    io::write_3mf(dir / "ok.3mf", m);
    const std::string ok = io_test::slurp(dir / "ok.3mf");
    CHECK_THROWS_WITH(io::parse_3mf("solid x\nendsolid x\n", "stl.3mf"), Catch::StartsWith("fabsynth: stl.3mf: byte 0: ") &&
                                                                                Catch::Contains("no ZIP signature"));
    CHECK_THROWS_WITH(io::parse_3mf(ok.substr(0, ok.size() / 2), "cut.3mf"), Catch::Contains("truncated"));
    CHECK_THROWS_WITH(io::parse_3mf(ok.substr(0, ok.size() - 3), "cut.3mf"), Catch::Contains("truncated"));
    // A ZIP package without a 3D model part: lib3mf's own refusal, located by file name.
    std::string other = ok;
    for (std::size_t at = other.find("3D/3dmodel.model"); at != std::string::npos; at = other.find("3D/3dmodel.model", at + 1))
        other.replace(at, 16, "3D/xxxxxxx.model");
    CHECK_THROWS_WITH(io::parse_3mf(other, "other.3mf"), Catch::StartsWith("fabsynth: other.3mf: "));
    CHECK_THROWS_WITH(io::read_3mf(dir / "missing.3mf"), Catch::Contains("does not exist"));
}

#endif
