#pragma once
/// @file plot.hpp  The foam_fit preview figure (pure drawing, kept with the tool), drawn into a fabsynth::image8 (RGB) with a built-in 5x7
/// pixel font, so no plotting package is needed. Two panels:
///  - left (like the paper's Figure 5): E/Es against rho, one colour per tau; dots are the samples,
///    lines the fitted polynomial P(rho, tau) over the sampled densities of that tau;
///  - right (like Figure 8a): E/Es against the relative volume w, the samples, the fitted
///    Gibson-Ashby curve C w^n over its fit range (black) and the paper's C = 0.85, n = 1.95 (grey).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <fabsynth/core/image.hpp>
#include <fabsynth/foam/elasticity_study.hpp>
#include <fabsynth/foam/fit.hpp>

namespace foam_fit_plot {

using fabsynth::image8;
namespace foam = fabsynth::foam;

namespace plot_detail {

using rgb = std::array<std::uint8_t, 3>;

// 5x7 glyphs, one string of 7 rows x 5 columns per character ('#' = ink); drawn for this tool.
struct glyph {
    char c;
    const char* rows;
};
inline constexpr glyph font[] = {
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

struct canvas {
    image8 img;
    canvas(int w, int h) : img(w, h, 3, 255) {}
    void put(int x, int y, rgb c) {
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
        for (int k = 0; k < 3; ++k) img.at(x, y, k) = c[static_cast<std::size_t>(k)];
    }
    void rect(int x0, int y0, int x1, int y1, rgb c) {
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) put(x, y, c);
    }
    void line(double x0, double y0, double x1, double y1, rgb c, int width = 1, int dash = 0) {
        const int steps = std::max(1, static_cast<int>(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0)))));
        for (int i = 0; i <= steps; ++i) {
            if (dash > 0 && (i / dash) % 2 == 1) continue;
            const double t = double(i) / steps;
            const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0))), y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
            rect(x - (width - 1) / 2, y - (width - 1) / 2, x + width / 2, y + width / 2, c);
        }
    }
    /// Text with its top-left corner at (x, y), `scale` pixels per font pixel; returns the width.
    int text(int x, int y, const std::string& s, rgb c = {0, 0, 0}, int scale = 2, bool vertical = false) {
        int pos = 0;
        for (char ch : s) {
            const char u = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
            const glyph* g = nullptr;
            for (const glyph& f : font)
                if (f.c == u) g = &f;
            if (g)
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

[[nodiscard]] inline int text_width(const std::string& s, int scale = 2) { return static_cast<int>(s.size()) * 6 * scale; }

[[nodiscard]] inline std::string tick_label(double v, double step) {
    char buf[32];
    const int digits = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
    std::snprintf(buf, sizeof buf, "%.*f", digits, std::abs(v) < 1e-12 * step ? 0.0 : v);
    return buf;
}

[[nodiscard]] inline double nice_step(double range) {
    const double raw = range / 5.0, p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

// One panel: data range [x0, x1] x [y0, y1] mapped into the pixel box.
struct panel {
    canvas& cv;
    int px0, py0, px1, py1;  // plot area (pixels), y down
    double x0, x1, y0, y1;
    [[nodiscard]] double X(double x) const { return px0 + (x - x0) / (x1 - x0) * (px1 - px0); }
    [[nodiscard]] double Y(double y) const { return py1 - (y - y0) / (y1 - y0) * (py1 - py0); }
    void axes(const std::string& xlabel, const std::string& ylabel, const std::string& title) {
        const rgb black{0, 0, 0}, grid{225, 225, 225};
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
    void dot(double x, double y, rgb c) {
        if (x < x0 || x > x1 || y < y0 || y > y1) return;
        const int cx = static_cast<int>(std::lround(X(x))), cy = static_cast<int>(std::lround(Y(y)));
        cv.rect(cx - 3, cy - 3, cx + 3, cy + 3, {0, 0, 0});
        cv.rect(cx - 2, cy - 2, cx + 2, cy + 2, c);
    }
    void ring(double x, double y, rgb c) {
        if (x < x0 || x > x1 || y < y0 || y > y1) return;
        const int cx = static_cast<int>(std::lround(X(x))), cy = static_cast<int>(std::lround(Y(y)));
        for (int d = -3; d <= 3; ++d) {
            cv.put(cx + d, cy - 3, c), cv.put(cx + d, cy + 3, c), cv.put(cx - 3, cy + d, c), cv.put(cx + 3, cy + d, c);
        }
    }
    template <class F>
    void curve(double a, double b, F f, rgb c, int width = 2, int dash = 0) {
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

inline rgb colour(std::size_t i) {
    static constexpr rgb pal[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44}, {214, 39, 40}, {148, 103, 189},
                                  {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
    return pal[i % std::size(pal)];
}

}  // namespace plot_detail

/// Draws the figure for a finished run (see the file comment).
[[nodiscard]] inline image8 draw_plot(const foam::elasticity_fit_config& c, const foam::elasticity_fit_report& r) {
    using namespace plot_detail;
    canvas cv(1640, 700);
    std::vector<double> taus;
    double rmax = 0, emax = 0, wmax = 0;
    for (const auto& s : r.samples) {
        if (std::find(taus.begin(), taus.end(), s.s.radius) == taus.end()) taus.push_back(s.s.radius);
        emax = std::max(emax, s.s.E), wmax = std::max(wmax, s.s.volume_fraction);
    }
    std::sort(taus.begin(), taus.end());
    {
        std::vector<foam::elasticity_sample> raw;
        for (const auto& s : r.samples) raw.push_back(s.s);
        for (const auto& e : foam::fit_points(raw)) rmax = std::max(rmax, e.density);
    }
    auto tau_index = [&](double t) { return static_cast<std::size_t>(std::find(taus.begin(), taus.end(), t) - taus.begin()); };
    const double ytop = emax * 1.08 > 0 ? emax * 1.08 : 1.0;

    panel left{cv, 110, 70, 700, 560, 0.0, rmax * 1.05 > 0 ? rmax * 1.05 : 1.0, 0.0, ytop};
    left.axes("RHO (SEEDS/MM^3)", "E/ES", "YOUNG'S MODULUS VS DENSITY, PER BEAM RADIUS");
    std::vector<foam::elasticity_sample> raw;
    for (const auto& s : r.samples) raw.push_back(s.s);
    const std::vector<foam::elasticity_sample> pts = foam::fit_points(raw);
    if (!r.P.coeffs.empty())
        for (double t : taus) {  // the fit over the densities its points cover at this radius
            double lo = 1e300, hi = 0;
            for (const auto& e : pts)
                if (e.radius == t) lo = std::min(lo, e.density), hi = std::max(hi, e.density);
            left.curve(lo, hi, [&](double rho) { return r.P(rho, t); }, colour(tau_index(t)));
        }
    for (const auto& e : pts) left.ring(e.density, e.E, colour(tau_index(e.radius)));
    for (const auto& s : r.samples) left.dot(s.s.density, s.s.E, colour(tau_index(s.s.radius)));
    int ly = 84;
    for (std::size_t i = 0; i < taus.size(); ++i, ly += 22) {
        char buf[48];
        std::snprintf(buf, sizeof buf, "TAU = %.3g MM", taus[i]);
        cv.rect(left.px1 + 14, ly + 2, left.px1 + 26, ly + 12, colour(i));
        cv.text(left.px1 + 32, ly, buf);
    }
    char note[96];
    std::snprintf(note, sizeof note, "FILLED: SAMPLES; HOLLOW: SCALE EQUIVALENTS; LINES: DEGREE-4 FIT (MAX DEV %.1f%%)", 100 * r.max_deviation);
    cv.text(left.px0 - 60, left.py1 + 60, note);

    panel right{cv, 1020, 70, 1610, 560, 0.0, std::max(0.1, std::min(1.0, wmax * 1.08)), 0.0, ytop};
    right.axes("RELATIVE VOLUME W", "E/ES", "YOUNG'S MODULUS VS RELATIVE VOLUME");
    right.curve(c.omega_lo, c.omega_hi, [](double w) { return 0.85 * std::pow(w, 1.95); }, {150, 150, 150}, 2, 6);
    if (r.gibson_ashby_ok) right.curve(c.omega_lo, c.omega_hi, [&](double w) { return r.gibson_ashby(w); }, {0, 0, 0}, 2);
    for (const auto& s : r.samples) right.dot(s.s.volume_fraction, s.s.E, colour(tau_index(s.s.radius)));
    char ga[96];
    if (r.gibson_ashby_ok) {
        std::snprintf(ga, sizeof ga, "FIT C W^N: C = %.3f, N = %.3f", r.gibson_ashby.C, r.gibson_ashby.n);
        right.cv.line(right.px0 + 14, 92, right.px0 + 44, 92, {0, 0, 0}, 2);
        cv.text(right.px0 + 52, 85, ga);
    }
    right.cv.line(right.px0 + 14, 114, right.px0 + 44, 114, {150, 150, 150}, 2, 6);
    cv.text(right.px0 + 52, 107, "PAPER: C = 0.85, N = 1.95");
    std::snprintf(ga, sizeof ga, "CURVES ON %.2g < W < %.2g (GIBSON-ASHBY RANGE)", c.omega_lo, c.omega_hi);
    cv.text(right.px0 + 10, right.py1 + 60, ga);
    return cv.img;
}

}  // namespace foam_fit_plot
