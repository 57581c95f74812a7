// Tests for surface_pattern/exemplar.hpp on the bundled raster exemplars, against independent
// brute-force oracles (nearest opposite pixel by exhaustive search, 2D convolution with the
// unfolded Gaussian).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/io/image.hpp"
#include "fabsynth/surface_pattern/exemplar.hpp"

using namespace fabsynth;
using surface_pattern::exemplar;
using surface_pattern::exemplar_options;
using surface_pattern::make_exemplar;

namespace {

image8 load(const std::string& file) { return io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/" + file); }

/// A 20x16 grey mask: a disk, a bar crossing the right border (so wrap-around matters) and
/// scattered pixels; both states present.
image8 crafted_mask() {
    image8 m(20, 16, 1, 0);
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 20; ++i) {
            const double dx = i + 0.5 - 7, dy = j + 0.5 - 8;
            const bool disk = dx * dx + dy * dy < 12;
            const bool bar = (i >= 17 || i <= 1) && j >= 3 && j <= 5;
            const bool dot = hash_uniform(7, i, j) < 0.06;
            m.at(i, j) = disk || bar || dot ? 255 : 0;
        }
    return m;
}

image8 random_colour(int w, int h, int channels, std::uint64_t seed) {
    image8 c(w, h, channels);
    for (std::size_t k = 0; k < c.data.size(); ++k) c.data[k] = static_cast<std::uint8_t>(hash64(seed, k) & 255);
    return c;
}

std::vector<std::uint8_t> mask_bits(const image8& grey) {
    std::vector<std::uint8_t> m(static_cast<std::size_t>(grey.width) * static_cast<std::size_t>(grey.height));
    for (std::size_t p = 0; p < m.size(); ++p) m[p] = grey.data[p * static_cast<std::size_t>(grey.channels)] >= 128 ? 1 : 0;
    return m;
}

/// Brute force: signed distance [px] (d - 0.5, see the header) to the nearest pixel of the other
/// state, by exhaustive search; periodic = nearest copy on the torus.
std::vector<double> brute_feature(const std::vector<std::uint8_t>& m, int w, int h, bool periodic) {
    std::vector<double> f(m.size());
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::uint8_t s = m[static_cast<std::size_t>(j * w + i)];
            double best = std::numeric_limits<double>::infinity();
            for (int b = 0; b < h; ++b)
                for (int a = 0; a < w; ++a) {
                    if (m[static_cast<std::size_t>(b * w + a)] == s) continue;
                    int dx = std::abs(i - a), dy = std::abs(j - b);
                    if (periodic) dx = std::min(dx, w - dx), dy = std::min(dy, h - dy);
                    best = std::min(best, double(dx) * dx + double(dy) * dy);
                }
            f[static_cast<std::size_t>(j * w + i)] = s ? std::sqrt(best) - 0.5 : -(std::sqrt(best) - 0.5);
        }
    return f;
}

/// Checks ch1 of level 0 against the brute force, exactly.
void check_feature(const exemplar& ex, const std::vector<std::uint8_t>& m, double fpx, double weight) {
    const std::vector<double> f = brute_feature(m, ex.width(), ex.height(), ex.tileable());
    const float* l = ex.level(0);
    const auto c = static_cast<std::size_t>(ex.channels());
    std::size_t bad = 0;
    for (std::size_t p = 0; p < f.size(); ++p) {
        const auto expect = static_cast<float>(std::clamp(f[p] / fpx, -1.0, 1.0) * weight);
        if (l[p * c + 1] != expect) ++bad;
    }
    CHECK(bad == 0);
}

/// Brute-force 2D convolution of level 0 with the unfolded truncated Gaussian (every one of the
/// (2r+1)^2 offsets, wrapped modulo the size however many periods it spans, or clamped) at pixel
/// (i, j), channel c.
double brute_blur(const exemplar& ex, double sigma, int i, int j, int c) {
    const int w = ex.width(), h = ex.height(), C = ex.channels();
    const float* l0 = ex.level(0);
    auto at = [&](int x, int y) {
        if (ex.tileable()) x = ((x % w) + w) % w, y = ((y % h) + h) % h;
        else x = std::clamp(x, 0, w - 1), y = std::clamp(y, 0, h - 1);
        return double(l0[(static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) * static_cast<std::size_t>(C) +
                         static_cast<std::size_t>(c)]);
    };
    if (sigma == 0) return at(i, j);
    const int r = static_cast<int>(std::ceil(3 * sigma));
    std::vector<double> g(static_cast<std::size_t>(2 * r + 1));
    double s = 0;
    for (int t = -r; t <= r; ++t) s += g[static_cast<std::size_t>(t + r)] = std::exp(-double(t) * t / (2 * sigma * sigma));
    double acc = 0;
    for (int ty = -r; ty <= r; ++ty)
        for (int tx = -r; tx <= r; ++tx) acc += g[static_cast<std::size_t>(tx + r)] * g[static_cast<std::size_t>(ty + r)] * at(i + tx, j + ty);
    return acc / (s * s);
}

double level_value(const exemplar& ex, int k, int i, int j, int c) {
    return ex.level(k)[(static_cast<std::size_t>(j) * static_cast<std::size_t>(ex.width()) + static_cast<std::size_t>(i)) *
                           static_cast<std::size_t>(ex.channels()) + static_cast<std::size_t>(c)];
}

std::vector<double> channel_means(const exemplar& ex, int k) {
    const auto c = static_cast<std::size_t>(ex.channels());
    const std::size_t n = static_cast<std::size_t>(ex.width()) * static_cast<std::size_t>(ex.height());
    std::vector<double> m(c, 0.0);
    for (std::size_t p = 0; p < n; ++p)
        for (std::size_t ch = 0; ch < c; ++ch) m[ch] += ex.level(k)[p * c + ch];
    for (double& v : m) v /= static_cast<double>(n);
    return m;
}

}  // namespace

TEST_CASE("bundled exemplars: sizes, channels, solid fraction of the data README", "[surface_pattern][exemplar]") {
    struct entry {
        const char* mask;
        const char* colour;
        int size;
        double fraction;
    };
    const entry entries[] = {{"hooks.png", "hooks_color.png", 128, 0.184},  {"zebra.png", "zebra_color.png", 256, 0.501},
                             {"spots.png", "spots_color.png", 128, 0.211},  {"keyboard.png", "keyboard_color.png", 128, 0.454},
                             {"voronoi_cells.png", "voronoi_cells_color.png", 256, 0.166}, {"waves.png", nullptr, 128, 0.452},
                             {"giraffe.png", nullptr, 128, 0.333},          {"honeycomb.png", nullptr, 128, 0.309},
                             {"square_grid.png", nullptr, 64, 0.438}};
    for (const entry& e : entries) {
        INFO(e.mask);
        const image8 m = load(e.mask);
        const image8 c = e.colour ? load(e.colour) : image8{};
        const exemplar ex = make_exemplar(m, e.colour ? &c : nullptr, {.feature_px = 6});
        CHECK(ex.width() == e.size);
        CHECK(ex.height() == e.size);
        CHECK(ex.has_colour() == (e.colour != nullptr));
        CHECK(ex.channels() == (e.colour ? 5 : 2));
        CHECK(ex.tileable());
        CHECK(ex.feature_px() == 6);
        CHECK(ex.stack_levels() == 1);
        CHECK(ex.sigma(0) == 0);
        CHECK(std::abs(ex.solid_fraction() - e.fraction) <= 0.0005 + 1e-12);  // the README rounds to 3 digits
        // ch0 is the mask, ch2..4 the colour / 255.
        const float* l = ex.level(0);
        const auto C = static_cast<std::size_t>(ex.channels());
        std::size_t bad = 0;
        for (std::size_t p = 0; p < ex.mask().size(); ++p) {
            bad += ex.mask()[p] != (m.data[p] >= 128 ? 1 : 0);
            bad += l[p * C] != float(ex.mask()[p]);
            bad += std::abs(l[p * C + 1]) > 1.0f;
            if (e.colour)
                for (std::size_t ch = 0; ch < 3; ++ch) {
                    bad += ex.colour().data[p * 3 + ch] != c.data[p * static_cast<std::size_t>(c.channels) + ch];
                    bad += l[p * C + 2 + ch] != static_cast<float>(c.data[p * static_cast<std::size_t>(c.channels) + ch] / 255.0);
                }
        }
        CHECK(bad == 0);
    }
}

TEST_CASE("feature distance equals a brute-force nearest-pixel search (periodic and clamped)", "[surface_pattern][exemplar]") {
    SECTION("square_grid.png, periodic") {
        const image8 m = load("square_grid.png");
        for (const double fpx : {2.0, 3.5, 100.0}) {  // 100 > 64: no clamping, the full torus counts
            INFO("feature_px " << fpx);
            const exemplar ex = make_exemplar(m, nullptr, {.feature_px = fpx, .feature_weight = 1.5});
            check_feature(ex, ex.mask(), fpx, 1.5);
        }
    }
    SECTION("hooks.png, periodic") {
        const image8 m = load("hooks.png");
        for (const double fpx : {4.0, 200.0}) {
            INFO("feature_px " << fpx);
            const exemplar ex = make_exemplar(m, nullptr, {.feature_px = fpx});
            check_feature(ex, ex.mask(), fpx, 1.0);
        }
    }
    SECTION("crafted 20x16 mask, periodic and not") {
        const image8 m = crafted_mask();
        for (const bool tileable : {true, false})
            for (const double fpx : {1.0, 2.5, 7.0, 50.0}) {
                INFO("tileable " << tileable << " feature_px " << fpx);
                const exemplar ex = make_exemplar(m, nullptr, {.feature_px = fpx, .tileable = tileable, .feature_weight = 0.75});
                check_feature(ex, mask_bits(m), fpx, 0.75);
            }
        // Wrap-around matters for this mask: the periodic and clamped distances differ somewhere.
        const exemplar a = make_exemplar(m, nullptr, {.feature_px = 50}), b = make_exemplar(m, nullptr, {.feature_px = 50, .tileable = false});
        bool differ = false;
        for (std::size_t p = 0; p < a.mask().size(); ++p) differ |= a.level(0)[p * 2 + 1] != b.level(0)[p * 2 + 1];
        CHECK(differ);
    }
    SECTION("values at the boundary") {
        // A solid pixel next to an empty one is at +0.5 px, an empty one next to a solid one at -0.5 px.
        image8 m(8, 8, 1, 0);
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 4; ++i) m.at(i, j) = 255;
        const exemplar ex = make_exemplar(m, nullptr, {.feature_px = 10});
        CHECK(level_value(ex, 0, 3, 2, 1) == Approx(0.05));
        CHECK(level_value(ex, 0, 4, 2, 1) == Approx(-0.05));
        CHECK(level_value(ex, 0, 1, 2, 1) == Approx(0.15));  // 3 px from column 4, 2 px from column 7 across the border
        CHECK(level_value(ex, 0, 0, 5, 1) == Approx(0.05));  // the empty column 7 is next to column 0 on the torus
    }
}

TEST_CASE("Gaussian stack equals a brute-force 2D convolution with the unfolded Gaussian", "[surface_pattern][exemplar]") {
    SECTION("crafted 20x16 with colour, periodic and clamped, every pixel") {
        const image8 m = crafted_mask(), c = random_colour(20, 16, 3, 11);
        const double sigmas[] = {0, 0.4, 1, 2.5, 7, 15, 40};  // 2r+1 > 16 from 2.5 on; 40 > the image
        for (const bool tileable : {true, false}) {
            INFO("tileable " << tileable);
            exemplar ex = make_exemplar(m, &c, {.feature_px = 3, .tileable = tileable, .feature_weight = 2, .colour_weight = 0.5});
            ex.build_stack(sigmas);
            REQUIRE(ex.stack_levels() == 7);
            double worst = 0;
            for (int k = 0; k < ex.stack_levels(); ++k) {
                CHECK(ex.sigma(k) == sigmas[k]);
                for (int j = 0; j < 16; ++j)
                    for (int i = 0; i < 20; ++i)
                        for (int ch = 0; ch < 5; ++ch)
                            worst = std::max(worst, std::abs(level_value(ex, k, i, j, ch) - brute_blur(ex, sigmas[k], i, j, ch)));
            }
            CHECK(worst < 1e-5);
        }
    }
    SECTION("hooks.png with hooks_color.png, periodic, sampled pixels") {
        const image8 m = load("hooks.png"), c = load("hooks_color.png");
        exemplar ex = make_exemplar(m, &c, {.feature_px = 5});
        const double sigmas[] = {0, 1.5, 12, 50, 200};  // 200 > 128: the kernel spans ~9 periods
        ex.build_stack(sigmas);
        double worst = 0;
        for (int k = 1; k < ex.stack_levels(); ++k) {
            const int samples = sigmas[k] > 100 ? 12 : 40;
            for (int s = 0; s < samples; ++s) {
                const int i = static_cast<int>(hash64(3, k, s, 0) % 128), j = static_cast<int>(hash64(3, k, s, 1) % 128);
                for (int ch = 0; ch < 5; ++ch) worst = std::max(worst, std::abs(level_value(ex, k, i, j, ch) - brute_blur(ex, sigmas[k], i, j, ch)));
            }
        }
        CHECK(worst < 1e-5);
    }
}

TEST_CASE("periodic blur conserves each channel's mean and tends to it for wide kernels", "[surface_pattern][exemplar]") {
    const image8 m = load("zebra.png"), c = load("zebra_color.png");
    exemplar ex = make_exemplar(m, &c, {.feature_px = 8});
    const double sigmas[] = {0, 1, 3, 10, 40, 300, 3000};
    ex.build_stack(sigmas);
    const std::vector<double> mean0 = channel_means(ex, 0);
    for (int k = 1; k < ex.stack_levels(); ++k) {
        INFO("sigma " << sigmas[k]);
        const std::vector<double> mk = channel_means(ex, k);
        for (std::size_t ch = 0; ch < mk.size(); ++ch) CHECK(std::abs(mk[ch] - mean0[ch]) < 1e-6);
    }
    // sigma = 3000 >> 256: every value is within 1e-3 of its channel's mean (the truncated kernel
    // folded ~70 times is not exactly flat).
    const int last = ex.stack_levels() - 1;
    double worst = 0;
    for (int j = 0; j < 256; ++j)
        for (int i = 0; i < 256; ++i)
            for (int ch = 0; ch < 5; ++ch) worst = std::max(worst, std::abs(level_value(ex, last, i, j, ch) - mean0[static_cast<std::size_t>(ch)]));
    CHECK(worst < 1e-3);
    // The solid fraction is the mean of ch0.
    CHECK(mean0[0] == Approx(ex.solid_fraction()).epsilon(1e-6));
}

TEST_CASE("stack results do not depend on the thread count; equal sigmas give equal levels", "[surface_pattern][exemplar]") {
    const image8 m = load("spots.png"), c = load("spots_color.png");
    const double sigmas[] = {0, 2, 2, 9, 60, 150};
    std::vector<std::vector<float>> runs[2];
    for (const bool tileable : {true, false}) {
        for (int t = 0; t < 2; ++t) {
            set_num_threads(t == 0 ? 1 : 3);
            exemplar ex = make_exemplar(m, &c, {.feature_px = 4, .tileable = tileable});
            ex.build_stack(sigmas);
            runs[t].clear();
            for (int k = 0; k < ex.stack_levels(); ++k) runs[t].emplace_back(ex.level(k), ex.level(k) + 128 * 128 * 5);
        }
        set_num_threads(0);
        CHECK(runs[0] == runs[1]);
        CHECK(runs[0][1] == runs[0][2]);
        CHECK(runs[0][2] != runs[0][3]);
    }
}

TEST_CASE("solid_at, colour_at and sample at pixel centres return the pixels; bilinear in between", "[surface_pattern][exemplar]") {
    const image8 m = load("hooks.png"), c = load("hooks_color.png");
    exemplar ex = make_exemplar(m, &c, {.feature_px = 5});
    const double sigmas[] = {0, 2};
    ex.build_stack(sigmas);
    const int w = ex.width(), h = ex.height();
    std::size_t bad = 0;
    float v[5], v1[5], v2[5];
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const bool s = ex.mask()[static_cast<std::size_t>(j * w + i)] != 0;
            bad += ex.solid_at(i + 0.5, j + 0.5) != s;
            bad += ex.solid_at(i + 0.5 + 3 * w, j + 0.5 - 2 * h) != s;  // wrapped
            const auto rgb = ex.colour_at(i + 0.5, j + 0.5);
            for (int ch = 0; ch < 3; ++ch) bad += rgb[static_cast<std::size_t>(ch)] != c.at(i, j, ch);
            const auto rgb2 = ex.colour_at(i + 0.5 - w, j + 0.5 + 5 * h);
            bad += rgb2 != rgb;
            // Half way between pixel (i, j) and its right neighbour (wrapping at the border): the
            // state is solid iff one of them is; the colour is the rounded average.
            const int in = (i + 1) % w;
            const bool s2 = ex.mask()[static_cast<std::size_t>(j * w + in)] != 0;
            bad += ex.solid_at(i + 1.0, j + 0.5) != (s || s2);
            const auto mid = ex.colour_at(i + 1.0, j + 0.5);
            for (int ch = 0; ch < 3; ++ch)
                bad += std::abs(int(mid[static_cast<std::size_t>(ch)]) - (int(c.at(i, j, ch)) + int(c.at(in, j, ch))) / 2.0) > 0.5;
            for (int k = 0; k < 2; ++k) {
                ex.sample(k, i + 0.5, j + 0.5, v);
                for (int ch = 0; ch < 5; ++ch) bad += v[ch] != float(level_value(ex, k, i, j, ch));
                ex.sample(k, i + 1.0, j + 1.0, v1);  // centre of four pixels
                const int jn = (j + 1) % h;
                for (int ch = 0; ch < 5; ++ch) {
                    const double avg = (level_value(ex, k, i, j, ch) + level_value(ex, k, in, j, ch) + level_value(ex, k, i, jn, ch) +
                                        level_value(ex, k, in, jn, ch)) / 4;
                    bad += std::abs(v1[ch] - avg) > 1e-6;
                }
                ex.sample(k, i + 0.5 + 7 * w, j + 0.5 - 3 * h, v2);
                for (int ch = 0; ch < 5; ++ch) bad += v2[ch] != v[ch];
            }
        }
    CHECK(bad == 0);
}

TEST_CASE("colour_at without colour is the mask as grey; non-tileable look-ups clamp at the tile's edges", "[surface_pattern][exemplar]") {
    const image8 m = load("zebra.png");
    const exemplar ex = make_exemplar(m, nullptr, {.feature_px = 8});
    CHECK_FALSE(ex.has_colour());
    CHECK(ex.colour().empty());
    std::size_t bad = 0;
    for (int j = 0; j < 256; j += 3)
        for (int i = 0; i < 256; ++i) {
            const std::uint8_t g = ex.mask()[static_cast<std::size_t>(j * 256 + i)] ? 255 : 0;
            bad += ex.colour_at(i + 0.5, j + 0.5) != std::array<std::uint8_t, 3>{g, g, g};
        }
    CHECK(bad == 0);

    // Crafted colour: at x = W - 0.1 the tileable look-up blends pixel W-1 with pixel 0, the
    // non-tileable one returns pixel W-1.
    image8 mk(4, 2, 1, 0);
    mk.at(0, 0) = 255;
    image8 col(4, 2, 3, 0);
    for (int j = 0; j < 2; ++j) col.at(0, j, 0) = 200, col.at(3, j, 0) = 100;
    const exemplar t = make_exemplar(mk, &col, {.feature_px = 1});
    const exemplar n = make_exemplar(mk, &col, {.feature_px = 1, .tileable = false});
    CHECK(t.colour_at(3.9, 0.5)[0] == 140);  // 0.6 * 100 + 0.4 * 200
    CHECK(n.colour_at(3.9, 0.5)[0] == 100);
    CHECK(n.colour_at(4.1, 0.5)[0] == 200);  // wrapped into the tile: x = 0.1, clamped to pixel 0
    CHECK(n.colour_at(-0.1, 0.5)[0] == 100);  // x = 3.9
    CHECK(t.solid_at(4.25, 0.5));
    CHECK_FALSE(t.solid_at(3.25, 0.5));
}

TEST_CASE("mask formats: grey, grey+alpha, RGB, RGBA; colour RGBA drops alpha", "[surface_pattern][exemplar]") {
    const image8 grey = crafted_mask();
    const exemplar ref = make_exemplar(grey, nullptr, {.feature_px = 2});
    image8 ga(20, 16, 2), rgb(20, 16, 3), rgba(20, 16, 4);
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 20; ++i) {
            const std::uint8_t g = grey.at(i, j);
            ga.at(i, j, 0) = g, ga.at(i, j, 1) = static_cast<std::uint8_t>(i * 10);
            for (int ch = 0; ch < 3; ++ch) rgb.at(i, j, ch) = g, rgba.at(i, j, ch) = g;
            rgba.at(i, j, 3) = static_cast<std::uint8_t>(j);
        }
    for (const image8* im : {&ga, &rgb, &rgba}) {
        const exemplar ex = make_exemplar(*im, nullptr, {.feature_px = 2});
        CHECK(ex.mask() == ref.mask());
        CHECK(std::vector<float>(ex.level(0), ex.level(0) + 20 * 16 * 2) == std::vector<float>(ref.level(0), ref.level(0) + 20 * 16 * 2));
    }
    // Thresholds: grey 127 empty, 128 solid; luminance of pure red (76) empty, pure green (150) solid.
    image8 t1(2, 1, 1);
    t1.at(0, 0) = 127, t1.at(1, 0) = 128;
    CHECK(make_exemplar(t1, nullptr, {.feature_px = 1}).mask() == std::vector<std::uint8_t>{0, 1});
    image8 t3(2, 1, 3, 0);
    t3.at(0, 0, 0) = 255, t3.at(1, 0, 1) = 255;
    CHECK(make_exemplar(t3, nullptr, {.feature_px = 1}).mask() == std::vector<std::uint8_t>{0, 1});
    // RGBA colour: stored as RGB.
    const image8 c4 = random_colour(20, 16, 4, 5);
    const exemplar ex = make_exemplar(grey, &c4, {.feature_px = 2, .colour_weight = 2});
    REQUIRE(ex.colour().channels == 3);
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 20; ++i)
            for (int ch = 0; ch < 3; ++ch) {
                CHECK(ex.colour().at(i, j, ch) == c4.at(i, j, ch));
                CHECK(level_value(ex, 0, i, j, 2 + ch) == Approx(c4.at(i, j, ch) / 255.0 * 2).epsilon(1e-7));
            }
}

TEST_CASE("invalid input throws invalid_input", "[surface_pattern][exemplar]") {
    const image8 m = crafted_mask();
    const exemplar_options ok{.feature_px = 3};
    using Catch::Matchers::Contains;
    CHECK_THROWS_AS(make_exemplar(image8{}, nullptr, ok), invalid_input);
    CHECK_THROWS_AS(make_exemplar(image8(0, 5, 1), nullptr, ok), invalid_input);
    const image8 c_small = random_colour(16, 20, 3, 1);
    CHECK_THROWS_WITH(make_exemplar(m, &c_small, ok), Contains("20x16") && Contains("16x20"));
    CHECK_THROWS_AS(make_exemplar(m, &c_small, ok), invalid_input);
    const image8 c_empty;
    CHECK_THROWS_AS(make_exemplar(m, &c_empty, ok), invalid_input);
    CHECK_THROWS_WITH(make_exemplar(image8(20, 16, 1, 0), nullptr, ok), Contains("empty mask"));
    CHECK_THROWS_WITH(make_exemplar(image8(20, 16, 1, 255), nullptr, ok), Contains("full mask"));
    CHECK_THROWS_AS(make_exemplar(image8(20, 16, 1, 0), nullptr, ok), invalid_input);
    CHECK_THROWS_AS(make_exemplar(image8(20, 16, 1, 255), nullptr, ok), invalid_input);
    // Channel counts.
    image8 five = m;
    five.channels = 5;
    five.data.assign(20 * 16 * 5, 255);
    CHECK_THROWS_AS(make_exemplar(five, nullptr, ok), invalid_input);
    image8 inconsistent = m;
    inconsistent.data.pop_back();
    CHECK_THROWS_AS(make_exemplar(inconsistent, nullptr, ok), invalid_input);
    const image8 c1 = random_colour(20, 16, 1, 2), c2 = random_colour(20, 16, 2, 2);
    CHECK_THROWS_WITH(make_exemplar(m, &c1, ok), Contains("1 channels"));
    CHECK_THROWS_AS(make_exemplar(m, &c1, ok), invalid_input);
    CHECK_THROWS_AS(make_exemplar(m, &c2, ok), invalid_input);
    // Options.
    for (const double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
        CHECK_THROWS_AS(make_exemplar(m, nullptr, {.feature_px = bad}), invalid_input);
    }
    CHECK_THROWS_AS(make_exemplar(m, nullptr, exemplar_options{}), invalid_input);  // feature_px defaults to 0
    CHECK_THROWS_AS(make_exemplar(m, nullptr, {.feature_px = 3, .feature_weight = -1}), invalid_input);
    CHECK_THROWS_AS(make_exemplar(m, nullptr, {.feature_px = 3, .colour_weight = -0.5}), invalid_input);
    CHECK_THROWS_AS(make_exemplar(m, nullptr, {.feature_px = 3, .feature_weight = std::nan("")}), invalid_input);
    CHECK_NOTHROW(make_exemplar(m, nullptr, {.feature_px = 3, .feature_weight = 0, .colour_weight = 0}));
    // Sigmas.
    exemplar ex = make_exemplar(m, nullptr, ok);
    const double decreasing[] = {0, 2, 1}, negative[] = {-1}, nan[] = {0, std::nan("")},
                 inf[] = {0, std::numeric_limits<double>::infinity()}, huge[] = {2e6};
    CHECK_THROWS_AS(ex.build_stack(std::span<const double>()), invalid_input);
    CHECK_THROWS_WITH(ex.build_stack(decreasing), Contains("non-decreasing"));
    CHECK_THROWS_AS(ex.build_stack(decreasing), invalid_input);
    CHECK_THROWS_AS(ex.build_stack(negative), invalid_input);
    CHECK_THROWS_AS(ex.build_stack(nan), invalid_input);
    CHECK_THROWS_AS(ex.build_stack(inf), invalid_input);
    CHECK_THROWS_AS(ex.build_stack(huge), invalid_input);
    CHECK(ex.stack_levels() == 1);  // a failed build keeps the old stack
    CHECK_THROWS_AS(ex.level(1), invalid_input);
    CHECK_THROWS_AS(ex.level(-1), invalid_input);
    CHECK_THROWS_AS(ex.sigma(1), invalid_input);
    CHECK_THROWS_AS(ex.solid_at(std::nan(""), 1), invalid_input);
    CHECK_THROWS_AS(ex.colour_at(1, std::numeric_limits<double>::infinity()), invalid_input);
    exemplar empty;
    CHECK(empty.width() == 0);
    CHECK(empty.stack_levels() == 0);
    const double zero[] = {0};
    CHECK_THROWS_AS(empty.build_stack(zero), invalid_input);
    CHECK_THROWS_AS(empty.solid_at(0.5, 0.5), invalid_input);
}
