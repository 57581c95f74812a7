// Tests for io/image.hpp: bundled PNG exemplars, PNG (8/16 bit, pHYs) and PGM round trips.
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

TEST_CASE("16-bit PNG keeps 16 bits; 8-bit files widen exactly", "[io][png]") {
    for (int c = 1; c <= 4; ++c) {
        const image16 img = random_image<std::uint16_t>(29, 17, c, 20 + std::uint64_t(c), 65535);
        const auto p = tmp_dir() / ("rt16_" + std::to_string(c) + ".png");
        io::write_png(p, img);
        CHECK(io::read_png16(p) == img);
        const io::png_info info = io::read_png_info(p);
        CHECK(info.bit_depth == 16);
        CHECK(info.channels == c);
        CHECK(!info.pixel_mm);
        // The 8-bit reader keeps the high byte of each sample.
        image8 high(img.width, img.height, c);
        for (std::size_t i = 0; i < img.data.size(); ++i) high.data[i] = std::uint8_t(img.data[i] >> 8);
        CHECK(io::read_png(p) == high);
    }
    const image8 hooks = io::read_png(io_test::data("exemplars/hooks.png"));
    const image16 wide = io::read_png16(io_test::data("exemplars/hooks.png"));
    REQUIRE(wide.data.size() == hooks.data.size());
    bool widened = true;
    for (std::size_t i = 0; i < hooks.data.size(); ++i) widened = widened && wide.data[i] == 257u * hooks.data[i];
    CHECK(widened);
}

TEST_CASE("PNG pixel size is written as pHYs and read back", "[io][png]") {
    const image8 img = random_image<std::uint8_t>(8, 5, 1, 3, 255);
    const auto p = tmp_dir() / "phys.png";
    io::write_png(p, img, {.pixel_mm = 0.05});
    const io::png_info info = io::read_png_info(p);
    REQUIRE(info.pixel_mm);
    CHECK(*info.pixel_mm == vec2(0.05));  // 20000 pixels per metre, exact
    CHECK(info.width == 8);
    CHECK(info.height == 5);
    CHECK(io::read_png(p) == img);
    // The chunk is the standard one: "pHYs", 20000 px/m in x and y, unit 1 (metre), before IDAT.
    const std::string bytes = io_test::slurp(p);
    const auto at = bytes.find("pHYs");
    REQUIRE(at != std::string::npos);
    CHECK(at < bytes.find("IDAT"));
    CHECK(io::detail::load<std::uint32_t>(bytes.data() + at + 4, io::detail::byte_order::big) == 20000u);
    CHECK(io::detail::load<std::uint32_t>(bytes.data() + at + 8, io::detail::byte_order::big) == 20000u);
    CHECK(bytes[at + 12] == 1);
    // Whole pixels per metre: 0.03 mm is stored as 33333 px/m.
    io::write_png(p, image16(4, 4, 2, 7), {.pixel_mm = 0.03});
    CHECK(io::read_png_info(p).pixel_mm->x == 1000.0 / 33333.0);
    // No option, no chunk.
    io::write_png(p, img);
    CHECK(!io::read_png_info(p).pixel_mm);
    CHECK(io_test::slurp(p).find("pHYs") == std::string::npos);
    for (double bad : {-0.05, std::nan(""), double(INFINITY), 1e-9, 1e4}) {
        INFO(bad);
        CHECK_THROWS_AS(io::write_png(tmp_dir() / "bad_phys.png", img, {.pixel_mm = bad}), invalid_input);
        CHECK_FALSE(std::filesystem::exists(tmp_dir() / "bad_phys.png"));
    }
}

TEST_CASE("PNG reader handles low bit depths, palettes, tRNS and 16-bit RGB", "[io][png]") {
    const auto corpus = std::filesystem::path(FABSYNTH_DATA_DIR) / ".." / "fuzz" / "corpus" / "png";
    // 1-bit grey, 10x2: row 0 alternates 1 0 ..., row 1 is all ones; scaled to 0/255.
    const image8 g1 = io::read_png(corpus / "gray1.png");
    REQUIRE(g1.width == 10);
    REQUIRE(g1.channels == 1);
    for (int x = 0; x < 10; ++x) {
        CHECK(g1.at(x, 0) == (x % 2 == 0 ? 255 : 0));
        CHECK(g1.at(x, 1) == 255);
    }
    CHECK(io::read_png16(corpus / "gray1.png").at(0, 0) == 65535);
    CHECK(io::read_png_info(corpus / "gray1.png").bit_depth == 1);
    // 4-bit palette red, green, blue with tRNS alpha 255, 128 (blue: none given, opaque).
    const image8 pal = io::read_png(corpus / "palette4_trns.png");
    REQUIRE(pal.channels == 4);
    CHECK(pal.data == std::vector<std::uint8_t>{255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 255});
    const io::png_info pi = io::read_png_info(corpus / "palette4_trns.png");
    CHECK(pi.channels == 4);
    REQUIRE(pi.pixel_mm);
    CHECK(*pi.pixel_mm == vec2(0.05, 0.1));  // 20000 and 10000 px/m
    // A tRNS colour key adds alpha: 0 where the key matches, opaque elsewhere.
    CHECK(io::read_png(corpus / "gray8_key.png").data == std::vector<std::uint8_t>{7, 0, 8, 255, 255, 255});
    const image8 key = io::read_png(corpus / "rgb8_key.png");
    CHECK(key.channels == 4);
    CHECK(key.data == std::vector<std::uint8_t>{1, 2, 3, 0, 1, 2, 4, 255});
    CHECK(io::read_png16(corpus / "rgb8_key.png").at(1, 0, 3) == 65535);
    // 16-bit grey and RGB, samples as stored.
    CHECK(io::read_png16(corpus / "gray16.png").data == std::vector<std::uint16_t>{0, 1, 256, 1000, 65534, 65535});
    CHECK(io::read_png(corpus / "gray16.png").data == std::vector<std::uint8_t>{0, 0, 1, 3, 255, 255});
    const image16 rgb = io::read_png16(corpus / "rgb16.png");
    CHECK(rgb.channels == 3);
    CHECK(rgb.data == std::vector<std::uint16_t>{1, 2, 3, 40000, 50000, 65535});
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
