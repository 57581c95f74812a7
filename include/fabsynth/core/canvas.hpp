// SPDX-License-Identifier: MIT
#pragma once
/// @file canvas.hpp  Drawing on an RGB raster for figures: pixels, rectangles, thick and dashed
/// lines, text in a built-in 5x7 pixel font (digits, upper-case letters, common punctuation) and
/// a plot panel with axes, ticks and labels. It exists so a tool or an embedder can draw a
/// diagnostic figure (foam/fit_plot.hpp's elasticity fit) into a PNG without a plotting package;
/// it is not a vector graphics library (no anti-aliasing, integer pixel coordinates after rounding).
///
/// Usage:
///     fabsynth::canvas cv(640, 480);                        // white, 3 channels
///     fabsynth::plot_panel p{cv, 80, 40, 600, 420, 0.0, 1.0, 0.0, 10.0};
///     p.axes("X (MM)", "Y", "TITLE");
///     p.curve(0.0, 1.0, [](double x) { return 10 * x * x; }, fabsynth::plot_colour(0));
///     fabsynth::io::write_png("fig.png", cv.img);
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <string>

#include <fabsynth/core/image.hpp>

namespace fabsynth {

/// An 8-bit RGB colour.
using rgb8 = std::array<std::uint8_t, 3>;

namespace detail {
// One 5x7 glyph: 7 rows of 5 columns, row-major, '#' = ink. Drawn for this library (no font
// package is needed for a figure's labels); lower-case letters are drawn as upper-case.
struct glyph {
    char c;
    const char* rows;
};
inline constexpr glyph font_5x7[] = {
    {'0', " ### #   ##  ### # ###  ##   # ### "}, {'1', "  #   ##    #    #    #    #   ### "},
    {'2', " ### #   #    #   #   #   #   #####"}, {'3', "#####   #   #     #     ##   # ### "},
    {'4', "   #   ##  # # #  # #####   #    # "}, {'5', "######    ####     #    ##   # ### "},
    {'6', "  ##  #   #    #### #   ##   # ### "}, {'7', "#####    #   #   #   #    #    #   "},
    {'8', " ### #   ##   # ### #   ##   # ### "}, {'9', " ### #   ##   # ####    #   #  ##  "},
    {'A', " ### #   ##   #######   ##   ##   #"}, {'B', "#### #   ##   ##### #   ##   ##### "},
    {'C', " ### #   ##    #    #    #   # ### "}, {'D', "#### #   ##   ##   ##   ##   ##### "},
    {'E', "######    #    #### #    #    #####"}, {'F', "######    #    #### #    #    #    "},
    {'G', " ### #   ##    # ####   ##   # ####"}, {'H', "#   ##   ##   #######   ##   ##   #"},
    {'I', " ###   #    #    #    #    #   ### "}, {'J', "  ###   #    #    #    # #  #  ##  "},
    {'K', "#   ##  # # #  ##   # #  #  # #   #"}, {'L', "#    #    #    #    #    #    #####"},
    {'M', "#   ### ### # ##   ##   ##   ##   #"}, {'N', "#   ###  ## # ##  ###   ##   ##   #"},
    {'O', " ### #   ##   ##   ##   ##   # ### "}, {'P', "#### #   ##   ##### #    #    #    "},
    {'Q', " ### #   ##   ##   ## # ##  #  ## #"}, {'R', "#### #   ##   ##### # #  #  # #   #"},
    {'S', " #####    #     ###     #    ##### "}, {'T', "#####  #    #    #    #    #    #  "},
    {'U', "#   ##   ##   ##   ##   ##   # ### "}, {'V', "#   ##   ##   ##   ##   # # #   #  "},
    {'W', "#   ##   ##   ## # ## # ### ###   #"}, {'X', "#   ##   # # #   #   # # #   ##   #"},
    {'Y', "#   ##   # # #   #    #    #    #  "}, {'Z', "#####    #   #   #   #   #    #####"},
    {'.', "                         ##   ##   "}, {'-', "                ###                "},
    {'+', "       #    #  #####  #    #       "}, {'=', "          #####     #####          "},
    {'/', "    #    #   #   #   #   #    #    "}, {'(', "   #   #   #    #    #     #     # "},
    {')', " #     #     #    #    #   #   #   "}, {':', "      ##   ##        ##   ##       "},
    {',', "                    ##   ##   #    "}, {'^', "  #   # # #   #                    "},
    {'\'', "  #    #   #                       "}, {'<', "   #   #   #   #     #     #     # "},
    {';', "      ##   ##        ##   ##   #   "}, {'%', "##   ##  #   #   #   #   #  ##   ##"}, {' ', "                                   "},
};

[[nodiscard]] inline const glyph* find_glyph(char ch) {
    const char u = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    const glyph* g = nullptr;
    for (const glyph& f : font_5x7)
        if (f.c == u) g = &f;
    return g;
}
}  // namespace detail

/// An RGB image8 to draw on; pixel (0, 0) is the top-left corner, x right, y down. Drawing outside
/// the image is clipped.
struct canvas {
    image8 img;
    /// A width x height canvas (pixels, each > 0) filled with `background`.
    canvas(int width, int height, rgb8 background = {255, 255, 255}) : img(width, height, 3, 255) {
        if (background != rgb8{255, 255, 255}) rect(0, 0, width - 1, height - 1, background);
    }
    void put(int x, int y, rgb8 c) {
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
        for (int k = 0; k < 3; ++k) img.at(x, y, k) = c[static_cast<std::size_t>(k)];
    }
    /// The filled rectangle [x0, x1] x [y0, y1] (inclusive pixel bounds).
    void rect(int x0, int y0, int x1, int y1, rgb8 c) {
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) put(x, y, c);
    }
    /// A line from (x0, y0) to (x1, y1) in pixels, `width` pixels thick; `dash` > 0 leaves out
    /// every other run of `dash` steps (one step per pixel along the longer axis).
    void line(double x0, double y0, double x1, double y1, rgb8 c, int width = 1, int dash = 0) {
        const int steps = std::max(1, static_cast<int>(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0)))));
        for (int i = 0; i <= steps; ++i) {
            if (dash > 0 && (i / dash) % 2 == 1) continue;
            const double t = double(i) / steps;
            const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0))), y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
            rect(x - (width - 1) / 2, y - (width - 1) / 2, x + width / 2, y + width / 2, c);
        }
    }
    /// Text with its top-left corner at (x, y), `scale` pixels per font pixel (a character is
    /// 6 * scale pixels wide, 7 * scale high); `vertical` writes bottom to top with (x, y) the
    /// bottom-left corner. Characters without a glyph leave a blank. Returns the advance in pixels.
    int text(int x, int y, const std::string& s, rgb8 c = {0, 0, 0}, int scale = 2, bool vertical = false) {
        int pos = 0;
        for (char ch : s) {
            if (const detail::glyph* g = detail::find_glyph(ch))
                for (int r = 0; r < 7; ++r)
                    for (int col = 0; col < 5; ++col)
                        if (g->rows[r * 5 + col] == '#') {
                            const int px = vertical ? x + r * scale : x + pos + col * scale;
                            const int py = vertical ? y - pos - col * scale : y + r * scale;
                            rect(px, vertical ? py - scale + 1 : py, px + scale - 1, vertical ? py : py + scale - 1, c);
                        }
            pos += 6 * scale;
        }
        return pos;
    }
};

/// The advance of `s` written at `scale` (pixels).
[[nodiscard]] inline int text_width(const std::string& s, int scale = 2) { return static_cast<int>(s.size()) * 6 * scale; }

/// A tick step of 1, 2 or 5 times a power of ten giving about five ticks over `range` (> 0).
[[nodiscard]] inline double nice_step(double range) {
    const double raw = range / 5.0, p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

/// `v` with as many decimals as the tick `step` needs (0 printed as 0, never -0).
[[nodiscard]] inline std::string tick_label(double v, double step) {
    char buf[32];
    const int digits = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
    std::snprintf(buf, sizeof buf, "%.*f", digits, std::abs(v) < 1e-12 * step ? 0.0 : v);
    return buf;
}

/// The i-th colour of a ten-colour categorical palette (cycles).
[[nodiscard]] inline rgb8 plot_colour(std::size_t i) {
    static constexpr rgb8 pal[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44}, {214, 39, 40}, {148, 103, 189},
                                   {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
    return pal[i % std::size(pal)];
}

/// A plot: the data rectangle [x0, x1] x [y0, y1] (x0 < x1, y0 < y1) mapped onto the pixel box
/// [px0, px1] x [py0, py1] of `cv` (y up in data, down in pixels). Marks outside the data range
/// are not drawn.
struct plot_panel {
    canvas& cv;
    int px0, py0, px1, py1;
    double x0, x1, y0, y1;
    [[nodiscard]] double X(double x) const { return px0 + (x - x0) / (x1 - x0) * (px1 - px0); }
    [[nodiscard]] double Y(double y) const { return py1 - (y - y0) / (y1 - y0) * (py1 - py0); }
    /// Frame, grey grid at nice_step ticks, tick labels, the axis labels (y written vertically,
    /// 78 px left of the box) and the title (26 px above it).
    void axes(const std::string& xlabel, const std::string& ylabel, const std::string& title) {
        const rgb8 black{0, 0, 0}, grid{225, 225, 225};
        const double sx = nice_step(x1 - x0), sy = nice_step(y1 - y0);
        for (double v = std::ceil(x0 / sx) * sx; v <= x1 + 1e-9 * sx; v += sx) {
            cv.line(X(v), py0, X(v), py1, grid);
            cv.line(X(v), py1, X(v), py1 + 6, black);
            const std::string s = tick_label(v, sx);
            cv.text(static_cast<int>(X(v)) - text_width(s) / 2, py1 + 10, s);
        }
        for (double v = std::ceil(y0 / sy) * sy; v <= y1 + 1e-9 * sy; v += sy) {
            cv.line(px0, Y(v), px1, Y(v), grid);
            cv.line(px0 - 6, Y(v), px0, Y(v), black);
            const std::string s = tick_label(v, sy);
            cv.text(px0 - 10 - text_width(s), static_cast<int>(Y(v)) - 7, s);
        }
        cv.line(px0, py0, px0, py1, black, 2), cv.line(px0, py1, px1, py1, black, 2);
        cv.line(px1, py0, px1, py1, black), cv.line(px0, py0, px1, py0, black);
        cv.text((px0 + px1) / 2 - text_width(xlabel) / 2, py1 + 34, xlabel);
        cv.text(px0 - 78, (py0 + py1) / 2 + text_width(ylabel) / 2, ylabel, black, 2, true);
        cv.text((px0 + px1) / 2 - text_width(title) / 2, py0 - 26, title);
    }
    /// A filled 5x5 square mark with a black border at (x, y).
    void dot(double x, double y, rgb8 c) {
        if (x < x0 || x > x1 || y < y0 || y > y1) return;
        const int cx = static_cast<int>(std::lround(X(x))), cy = static_cast<int>(std::lround(Y(y)));
        cv.rect(cx - 3, cy - 3, cx + 3, cy + 3, {0, 0, 0});
        cv.rect(cx - 2, cy - 2, cx + 2, cy + 2, c);
    }
    /// A hollow 7x7 square mark at (x, y).
    void ring(double x, double y, rgb8 c) {
        if (x < x0 || x > x1 || y < y0 || y > y1) return;
        const int cx = static_cast<int>(std::lround(X(x))), cy = static_cast<int>(std::lround(Y(y)));
        for (int d = -3; d <= 3; ++d) {
            cv.put(cx + d, cy - 3, c), cv.put(cx + d, cy + 3, c), cv.put(cx - 3, cy + d, c), cv.put(cx + 3, cy + d, c);
        }
    }
    /// The graph of f on [a, b] (400 segments); pieces where f is not finite or leaves [y0, y1]
    /// are left out.
    template <class F>
    void curve(double a, double b, F f, rgb8 c, int width = 2, int dash = 0) {
        constexpr int n = 400;
        double lx = 0, ly = 0;
        bool have = false;
        for (int i = 0; i <= n; ++i) {
            const double x = a + (b - a) * i / n, y = f(x);
            const bool in = std::isfinite(y) && y >= y0 && y <= y1;
            if (in && have) cv.line(lx, ly, X(x), Y(y), c, width, dash);
            have = in, lx = X(x), ly = Y(y);
        }
    }
};

}  // namespace fabsynth
