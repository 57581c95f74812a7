// Tests for io/image.hpp: bundled PNG exemplars, PNG and PGM round trips.
#include <catch2/catch.hpp>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/io/image.hpp"
#include "io/io_test_util.hpp"

using namespace fabsynth;
using io_test::tmp_dir;

namespace {
template <class T>
image<T> random_image(int w, int h, int c, std::uint64_t seed, unsigned maxval) {
    image<T> img(w, h, c);
    counter_rng r(seed);
    for (T& v : img.data) v = static_cast<T>(r.uniform_int(maxval + 1ULL));
    return img;
}
struct exemplar {
    const char* file;
    int size;
    double solid;  // solid fraction from data/README.md (3 decimals)
};
}  // namespace

TEST_CASE("PNG masks decode to the documented sizes, values and solid fractions", "[io][png][data]") {
    const exemplar masks[] = {{"voronoi_cells", 256, 0.166}, {"waves", 128, 0.452}, {"hooks", 128, 0.184},
                              {"spots", 128, 0.211},         {"keyboard", 128, 0.454}, {"zebra", 256, 0.501},
                              {"giraffe", 128, 0.333},       {"honeycomb", 128, 0.309}, {"square_grid", 64, 0.438}};
    for (const exemplar& e : masks) {
        INFO(e.file);
        const image8 img = io::read_png(io_test::data("exemplars") / (std::string(e.file) + ".png"));
        CHECK(img.width == e.size);
        CHECK(img.height == e.size);
        CHECK(img.channels == 1);
        std::size_t solid = 0, other = 0;
        for (auto v : img.data) solid += v == 255, other += v != 0 && v != 255;
        CHECK(other == 0);
        CHECK(double(solid) / double(img.data.size()) == Approx(e.solid).margin(0.0006));
    }
    // square_grid: an 8-px lattice of 2-px lines covers 1 - (6/8)^2 of the plane exactly.
    const image8 grid = io::read_png(io_test::data("exemplars/square_grid.png"));
    std::size_t solid = 0;
    for (auto v : grid.data) solid += v == 255;
    CHECK(solid * 64 == grid.data.size() * 28);
    for (const char* c : {"voronoi_cells_color", "hooks_color", "spots_color", "keyboard_color", "zebra_color"}) {
        INFO(c);
        const image8 img = io::read_png(io_test::data("exemplars") / (std::string(c) + ".png"));
        CHECK(img.channels == 3);
        CHECK(img.width == (std::string(c).starts_with("voronoi") || std::string(c).starts_with("zebra") ? 256 : 128));
    }
}

TEST_CASE("PNG round trip is exact for 1..4 channels", "[io][png]") {
    for (int c = 1; c <= 4; ++c) {
        const image8 img = random_image<std::uint8_t>(37, 23, c, 10 + std::uint64_t(c), 255);
        const auto p = tmp_dir() / ("rt" + std::to_string(c) + ".png");
        io::write_png(p, img);
        CHECK(io::read_png(p) == img);
    }
    CHECK_THROWS_AS(io::write_png(tmp_dir() / "empty.png", image8{}), invalid_input);
    image8 broken(4, 4, 1);
    broken.data.pop_back();
    CHECK_THROWS_AS(io::write_png(tmp_dir() / "broken.png", broken), invalid_input);
}

TEST_CASE("PGM round trips (P2/P5, 8 and 16 bit) are exact", "[io][pgm]") {
    const image8 a = random_image<std::uint8_t>(31, 17, 1, 5, 255);
    const image16 b = random_image<std::uint16_t>(13, 29, 1, 6, 65535);
    for (auto enc : {io::encoding::ascii, io::encoding::binary}) {
        const auto pa = tmp_dir() / "rt8.pgm", pb = tmp_dir() / "rt16.pgm";
        io::write_pgm(pa, a, enc);
        io::write_pgm(pb, b, enc);
        CHECK(io::read_pgm(pa) == a);
        CHECK(io::read_pgm16(pb) == b);
        image16 a16(a.width, a.height, 1);
        for (std::size_t i = 0; i < a.data.size(); ++i) a16.data[i] = a.data[i];
        CHECK(io::read_pgm16(pa) == a16);
        CHECK_THROWS_AS(io::read_pgm(pb), io_error);  // maxval 65535 does not fit 8 bits
    }
}

TEST_CASE("PGM reader handles comments, maxval and the P5 separator", "[io][pgm]") {
    const image8 a = io::parse_pgm("P2\n# a comment\n3 2 # trailing\n# another\n7\n0 1 2\n3 4 7\n", "c.pgm");
    CHECK(a.width == 3);
    CHECK(a.height == 2);
    CHECK(a.data == std::vector<std::uint8_t>{0, 1, 2, 3, 4, 7});
    std::string p5 = "P5 2 2 255\n";
    p5 += std::string("\x0a\x20\xff\x00", 4);  // raster bytes that look like whitespace/newline
    CHECK(io::parse_pgm(p5, "b.pgm").data == std::vector<std::uint8_t>{10, 32, 255, 0});
    std::string p16 = "P5 1 2 1000\n";
    p16 += std::string("\x03\xe8\x00\x01", 4);  // big-endian 1000, 1
    CHECK(io::parse_pgm16(p16, "c.pgm").data == std::vector<std::uint16_t>{1000, 1});
    // A mask survives PNG -> PGM -> PNG unchanged.
    const image8 m = io::read_png(io_test::data("exemplars/hooks.png"));
    io::write_pgm(tmp_dir() / "hooks.pgm", m);
    CHECK(io::read_pgm(tmp_dir() / "hooks.pgm") == m);
}
