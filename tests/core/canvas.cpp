// core/canvas.hpp: the drawing primitives behind the figures (foam/fit_plot.hpp): where marks land,
// what is clipped, the text's extent in both directions, the tick steps.
#include <catch2/catch.hpp>

#include <cmath>

#include "fabsynth/core/canvas.hpp"

using namespace fabsynth;

namespace {
bool is(const image8& img, int x, int y, rgb8 c) { return img.at(x, y, 0) == c[0] && img.at(x, y, 1) == c[1] && img.at(x, y, 2) == c[2]; }

// The ink's bounding box (non-white pixels): {x0, y0, x1, y1}, or x0 > x1 when there is none.
std::array<int, 4> ink_box(const image8& img) {
    std::array<int, 4> b{img.width, img.height, -1, -1};
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (!is(img, x, y, {255, 255, 255})) b = {std::min(b[0], x), std::min(b[1], y), std::max(b[2], x), std::max(b[3], y)};
    return b;
}
}  // namespace

TEST_CASE("canvas: lines reach both ends, widths and dashes, clipping", "[core][canvas]") {
    const rgb8 red{200, 0, 0};
    canvas cv(40, 30);
    cv.line(3, 4, 33, 4, red);
    CHECK(is(cv.img, 3, 4, red));
    CHECK(is(cv.img, 33, 4, red));
    CHECK(is(cv.img, 2, 4, {255, 255, 255}));
    CHECK(ink_box(cv.img) == std::array<int, 4>{3, 4, 33, 4});

    canvas thick(40, 30);
    thick.line(5, 10, 5, 20, red, 3);  // 3 px wide: x = 4..6
    CHECK(ink_box(thick.img) == std::array<int, 4>{4, 9, 6, 21});

    canvas dashed(40, 30);
    dashed.line(0, 0, 39, 0, red, 1, 5);  // runs of 5 on, 5 off
    int inked = 0;
    for (int x = 0; x < 40; ++x) inked += is(dashed.img, x, 0, red);
    CHECK(inked == 20);
    CHECK(is(dashed.img, 4, 0, red));
    CHECK_FALSE(is(dashed.img, 5, 0, red));

    canvas clip(10, 10);  // marks partly or wholly outside are cut, never written out of bounds
    clip.rect(-5, -5, 2, 2, red);
    clip.line(-20, 5, 30, 5, red, 3);
    clip.text(8, 8, "WWW");
    clip.text(-100, -100, "8");
    CHECK(ink_box(clip.img) == std::array<int, 4>{0, 0, 9, 9});
    CHECK(is(clip.img, 9, 5, red));
}

TEST_CASE("canvas: text advance, case, vertical text is the horizontal text turned", "[core][canvas]") {
    canvas h(200, 40), lower(200, 40), v(40, 200);
    const int adv = h.text(10, 10, "E/ES 0.5", {0, 0, 0}, 2);
    CHECK(adv == text_width("E/ES 0.5", 2));
    lower.text(10, 10, "e/es 0.5", {0, 0, 0}, 2);
    CHECK(lower.img.data == h.img.data);  // lower case draws as upper case
    const auto hb = ink_box(h.img);
    CHECK(hb[3] - hb[1] + 1 == 7 * 2);  // 'E' spans the 7 rows
    CHECK(hb[0] == 10);
    v.text(10, 190, "E/ES 0.5", {0, 0, 0}, 2, true);  // bottom to top from (10, 190)
    const auto vb = ink_box(v.img);
    CHECK(vb[2] - vb[0] == hb[3] - hb[1]);  // the extents swap
    CHECK(vb[3] - vb[1] == hb[2] - hb[0]);
    CHECK(vb[3] == 190);
    for (int y = 0; y < 14; ++y)  // rotating the horizontal text by 90 degrees gives the vertical one
        for (int x = hb[0]; x <= hb[2]; ++x) {
            const bool a = !is(h.img, x, 10 + y, {255, 255, 255});
            const bool b = !is(v.img, 10 + y, 190 - (x - 10), {255, 255, 255});
            REQUIRE(a == b);
        }
    canvas unknown(40, 20);
    CHECK(unknown.text(0, 0, "\x01~") == text_width("..", 2));  // no glyph: a blank of the same advance
    CHECK(ink_box(unknown.img)[0] > ink_box(unknown.img)[2]);
}

TEST_CASE("plot panel: data to pixels, marks and curves where the data are, ticks", "[core][canvas]") {
    canvas cv(300, 200);
    plot_panel p{cv, 50, 20, 250, 170, 0.0, 2.0, -1.0, 1.0};
    CHECK(p.X(0.0) == 50);
    CHECK(p.X(2.0) == 250);
    CHECK(p.Y(-1.0) == 170);
    CHECK(p.Y(1.0) == 20);
    CHECK(p.Y(0.0) == 95);
    const rgb8 c = plot_colour(2);
    p.dot(1.0, 0.5, c);  // at (150, 57.5 -> 58)
    CHECK(is(cv.img, 150, 58, c));
    CHECK(is(cv.img, 147, 58, {0, 0, 0}));  // its border
    p.dot(3.0, 0.0, c);  // outside the data range: nothing
    CHECK(is(cv.img, 250, 95, {255, 255, 255}));
    const rgb8 k{0, 0, 0};
    p.curve(0.0, 2.0, [](double x) { return std::sin(3 * x); }, k, 1);
    for (double x : {0.25, 0.8, 1.3, 1.9}) {  // the graph passes through (x, sin 3x), to the pixel
        const int px = static_cast<int>(std::lround(p.X(x)));
        bool near = false;
        for (int dy = -1; dy <= 1; ++dy) near = near || is(cv.img, px, static_cast<int>(std::lround(p.Y(std::sin(3 * x)))) + dy, k);
        CHECK(near);
    }
    CHECK(plot_colour(0) != plot_colour(1));
    CHECK(plot_colour(10) == plot_colour(0));
    // steps of 1, 2 or 5 x 10^k giving about five ticks
    CHECK(nice_step(1.0) == Approx(0.2));
    CHECK(nice_step(7.0) == Approx(2.0));
    CHECK(nice_step(0.03) == Approx(0.01));
    CHECK(nice_step(480.0) == Approx(100.0));
    CHECK(tick_label(0.4, 0.2) == "0.4");
    CHECK(tick_label(-1e-17, 0.2) == "0.0");
    CHECK(tick_label(300.0, 100.0) == "300");
}
