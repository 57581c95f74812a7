// SPDX-License-Identifier: MIT
#pragma once
/// @file exemplar.hpp  Raster exemplars of the surface-pattern pipeline (Lu, Lefebvre, Dumas, Wu &
/// Dick 2015, structurally-sound-patterns.md §3 "Pre-processing" and "Notations", §4.3): a binary
/// pattern map (solid = 1, empty = 0), an optional colour image, the feature-distance channel of
/// Lefebvre & Hoppe 2006 and a Gaussian stack of the channel image, one level per voxel-pyramid
/// level.
///
/// Pixel coordinates: pixel (i, j) covers [i, i+1) x [j, j+1), x to the right, y DOWN (row j of
/// the file, counted from the top); its centre is (i + 0.5, j + 0.5). Continuous look-ups
/// (solid_at, colour_at, sample) interpolate bilinearly between pixel centres, so they return the
/// pixel's own value exactly at its centre. Positions outside [0, W) x [0, H) wrap (the exemplar
/// tiles the plane, §4.1). For a tileable exemplar interpolation also wraps across the borders; for
/// a non-tileable one the position is first wrapped into the tile and interpolation then clamps at
/// the tile's edges (no blending across the seam).
///
/// Channels (C = channels(): 2 without colour, 5 with), per pixel, as floats:
///   ch0      mask value s in {0, 1} (unweighted);
///   ch1      feature distance: with d_e = Euclidean distance [px] between the pixel's centre and
///            the nearest empty pixel's centre and d_s the same to the nearest solid pixel,
///            f = (d_e - 0.5) in solid pixels (>= 0.5) and f = -(d_s - 0.5) in empty ones
///            (<= -0.5): the signed distance to the boundary, taken half way between pixel
///            centres. ch1 = clamp(f / feature_px, -1, 1) * feature_weight. Tileable exemplars
///            measure the distance on the torus (to the nearest periodic copy): the mask is padded
///            on every side with min(ceil(W/2), ceil(feature_px + 0.5)) wrapped columns (rows:
///            with H) and the exact transform of geometry/distance_transform.hpp is run on the
///            padded grid. This is exact: the nearest periodic copy lies within W/2 along x (H/2
///            along y), and a copy farther than feature_px + 0.5 is clamped to +-1 anyway.
///            Non-tileable exemplars measure inside the image only (its border is no boundary);
///   ch2..4   colour r, g, b / 255 * colour_weight (only with a colour image).
///
/// Gaussian stack: level k = the channel image convolved with the separable, sampled, truncated
/// Gaussian of standard deviation sigma_k [px]: weights g(t) = exp(-t^2 / (2 sigma_k^2)) for
/// integer offsets |t| <= r = ceil(3 sigma_k), normalised to sum 1 over [-r, r] (sigma_k = 0:
/// the unblurred image). The 2D kernel is the product of the x and y kernels. Tileable: exact
/// periodic convolution, out(i) = sum_t g(t) in((i + t) mod W); when 2r + 1 > W the kernel is
/// folded onto the period once (weights of congruent offsets summed, O(r) per level), so a pixel
/// costs at most W (resp. H) multiply-adds per channel and axis whatever sigma, and a very wide
/// kernel tends to the channel mean. Non-tileable: clamp-to-edge, out(i) = sum_t g(t)
/// in(clamp(i + t, 0, W - 1)), the weights that fall outside summed onto the edge pixels (again
/// at most W + 2 taps per pixel). The periodic blur conserves each channel's mean. Computed in
/// double, stored as float. Passes run in parallel over rows with a fixed summation order, so
/// results do not depend on the thread count.
///
/// Usage:
///   const fabsynth::image8 m = fabsynth::io::read_png("data/exemplars/hooks.png");       // drivers read files
///   const fabsynth::image8 c = fabsynth::io::read_png("data/exemplars/hooks_color.png");
///   auto ex = fabsynth::surface_pattern::make_exemplar(m, &c, {.feature_px = 6});
///   ex.channels();                       // 5: mask, feature, r, g, b
///   ex.solid_fraction();                 // 0.184
///   const double sigmas[] = {0, 1, 2, 4, 8, 16, 32, 64};
///   ex.build_stack(sigmas);              // 8 levels
///   const float* l3 = ex.level(3);       // l3[(y * ex.width() + x) * ex.channels() + c]
///   bool s = ex.solid_at(10.5, 3.5);     // the state of pixel (10, 3)
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/geometry/distance_transform.hpp"

namespace fabsynth::surface_pattern {

/// Options of make_exemplar.
struct exemplar_options {
    double feature_px = 0;        ///< r_pattern: scale of the pattern's features [exemplar px] (> 0, finite); the feature distance saturates there
    bool tileable = true;         ///< the exemplar lives on a torus (all bundled ones do); false: distances inside the
                                  ///< image only, blur clamped to the edge
    double feature_weight = 1.0;  ///< weight of the feature-distance channel ch1 (>= 0, finite)
    double colour_weight = 1.0;   ///< weight of the colour channels ch2..4 (>= 0, finite)
};

/// Largest accepted Gaussian standard deviation [px] (the one-off kernel fold costs O(3 sigma)).
inline constexpr double max_stack_sigma_px = 1e6;

namespace detail {

inline std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

inline std::string number_text(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

/// One axis of the separable Gaussian (see the file comment): the taps of each output sample.
class blur_axis {
public:
    blur_axis(int n, double sigma, bool periodic) : n_(n), periodic_(periodic) {
        if (sigma <= 0) {
            off_ = {0}, w_ = {1.0};
            periodic_ = true;  // identity: one tap of weight 1 at offset 0
            return;
        }
        const long long r = static_cast<long long>(std::ceil(3.0 * sigma));
        const double inv = 1.0 / (2.0 * sigma * sigma);
        auto e = [&](long long t) { return t == 0 ? 1.0 : std::exp(-static_cast<double>(t) * static_cast<double>(t) * inv); };
        double half = 0;  // sum_{t=0}^{r} e(t)
        for (long long t = r; t >= 0; --t) half += e(t);
        const double s = 2.0 * half - 1.0;  // sum over [-r, r] (e(0) = 1)
        r_ = r;
        if (periodic_) {
            if (2 * r + 1 <= n) {
                for (long long t = -r; t <= r; ++t) off_.push_back(static_cast<int>(t)), w_.push_back(e(t) / s);
            } else {  // fold onto the period
                std::vector<double> acc(static_cast<std::size_t>(n), 0.0);
                const long long nn = n;
                for (long long t = -r; t <= r; ++t) acc[static_cast<std::size_t>(((t % nn) + nn) % nn)] += e(t);
                for (int m = 0; m < n; ++m) off_.push_back(m), w_.push_back(acc[static_cast<std::size_t>(m)] / s);
            }
        } else {
            // g_[t] = e(t)/s for t <= min(r, n - 1); tail_[a] = sum_{t=a}^{r} e(t)/s for a = 1..n (0 beyond r).
            const long long rr = std::min<long long>(r, n - 1);
            for (long long t = 0; t <= rr; ++t) g_.push_back(e(t) / s);
            tail_.assign(static_cast<std::size_t>(n) + 2, 0.0);
            double far = 0;  // sum_{t=n+1}^{r} e(t)
            for (long long t = r; t > n; --t) far += e(t);
            double acc = far;
            for (long long a = std::min<long long>(r, n); a >= 1; --a) {
                acc += e(a);
                tail_[static_cast<std::size_t>(a)] = acc / s;
            }
        }
    }

    /// Taps (input index, weight) of output sample i, in increasing input index for the clamped
    /// kernel and increasing offset for the periodic one (a fixed order: the summation order).
    void taps(int i, std::vector<std::pair<int, double>>& out) const {
        out.clear();
        if (periodic_) {
            for (std::size_t k = 0; k < off_.size(); ++k) {
                int idx = i + off_[k];
                if (idx < 0) idx += n_;
                else if (idx >= n_) idx -= n_;
                out.emplace_back(idx, w_[k]);
            }
            return;
        }
        const long long lo = std::max<long long>(0, i - r_), hi = std::min<long long>(n_ - 1, i + r_);
        for (long long k = lo; k <= hi; ++k) out.emplace_back(static_cast<int>(k), g_[static_cast<std::size_t>(k >= i ? k - i : i - k)]);
        // Offsets that leave the image land on the edge pixels: tail(i + 1) on pixel 0, tail(n - i) on pixel n - 1.
        out.front().second += tail_[static_cast<std::size_t>(i + 1)];
        out.back().second += tail_[static_cast<std::size_t>(n_ - i)];
    }

private:
    int n_;
    bool periodic_;
    long long r_ = 0;
    std::vector<int> off_;
    std::vector<double> w_;
    std::vector<double> g_, tail_;
};

/// Blurs a w x h image of c interleaved double channels; result as floats (same layout).
inline std::vector<float> gaussian_blur(const std::vector<double>& in, int w, int h, int c, double sigma, bool periodic) {
    const std::size_t row = static_cast<std::size_t>(w) * static_cast<std::size_t>(c);
    std::vector<float> out(in.size());
    if (sigma <= 0) {
        for (std::size_t i = 0; i < in.size(); ++i) out[i] = static_cast<float>(in[i]);
        return out;
    }
    const blur_axis ax(w, sigma, periodic), ay(h, sigma, periodic);
    // Horizontal pass into tmp, blocks of rows sharing the taps of each column.
    std::vector<double> tmp(in.size());
    constexpr int block = 8;
    const std::size_t blocks = (static_cast<std::size_t>(h) + block - 1) / block;
    parallel_for(0, blocks, [&](std::size_t b) {
        thread_local std::vector<std::pair<int, double>> taps;
        const int j0 = static_cast<int>(b) * block, j1 = std::min(h, j0 + block);
        for (int i = 0; i < w; ++i) {
            ax.taps(i, taps);
            for (int j = j0; j < j1; ++j) {
                const double* src = in.data() + static_cast<std::size_t>(j) * row;
                double acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
                for (const auto& [k, wt] : taps) {
                    const double* p = src + static_cast<std::size_t>(k) * static_cast<std::size_t>(c);
                    for (int ch = 0; ch < c; ++ch) acc[ch] += wt * p[ch];
                }
                double* dst = tmp.data() + static_cast<std::size_t>(j) * row + static_cast<std::size_t>(i) * static_cast<std::size_t>(c);
                for (int ch = 0; ch < c; ++ch) dst[ch] = acc[ch];
            }
        }
    });
    // Vertical pass: each output row is a weighted sum of whole rows of tmp.
    parallel_for(0, static_cast<std::size_t>(h), [&](std::size_t jj) {
        thread_local std::vector<std::pair<int, double>> taps;
        thread_local std::vector<double> acc;
        ay.taps(static_cast<int>(jj), taps);
        acc.assign(row, 0.0);
        for (const auto& [k, wt] : taps) {
            const double* src = tmp.data() + static_cast<std::size_t>(k) * row;
            for (std::size_t q = 0; q < row; ++q) acc[q] += wt * src[q];
        }
        float* dst = out.data() + jj * row;
        for (std::size_t q = 0; q < row; ++q) dst[q] = static_cast<float>(acc[q]);
    }, {.grain = 4});
    return out;
}

/// Bilinear taps of the continuous position (x, y): pixels (i0|i1, j0|j1), fractions fx, fy.
struct bilinear_taps {
    int i0, i1, j0, j1;
    double fx, fy;
};

inline void bilinear_axis(double x, int n, bool periodic, int& a, int& b, double& f) {
    const double nd = n;
    double u;
    if (periodic) {
        u = x - 0.5;
        u -= nd * std::floor(u / nd);
        if (u < 0) u += nd;
        if (u >= nd) u -= nd;
    } else {
        double xw = x - nd * std::floor(x / nd);
        if (xw < 0) xw += nd;
        if (xw >= nd) xw -= nd;
        u = std::clamp(xw - 0.5, 0.0, nd - 1.0);
    }
    a = std::min(static_cast<int>(std::floor(u)), n - 1);
    f = u - a;
    b = a + 1 < n ? a + 1 : (periodic ? 0 : n - 1);
}

}  // namespace detail

class exemplar;
[[nodiscard]] inline exemplar make_exemplar(const image8& mask, const image8* colour, const exemplar_options& opt);

/// A preprocessed exemplar: mask, optional colour, channel image and its Gaussian stack. Built by
/// make_exemplar (a default-constructed exemplar is empty: width 0, no levels). make_exemplar
/// leaves a one-level stack (sigma 0: the unblurred channels); build_stack replaces it.
class exemplar {
public:
    exemplar() = default;

    [[nodiscard]] int width() const noexcept { return width_; }    ///< W [px]
    [[nodiscard]] int height() const noexcept { return height_; }  ///< H [px]
    /// C: 2 without colour (mask, feature), 5 with colour (mask, feature, r, g, b).
    [[nodiscard]] int channels() const noexcept { return channels_; }
    [[nodiscard]] bool has_colour() const noexcept { return !colour_.empty(); }
    [[nodiscard]] bool tileable() const noexcept { return tileable_; }
    [[nodiscard]] double feature_px() const noexcept { return feature_px_; }  ///< r_pattern [px]
    [[nodiscard]] double feature_weight() const noexcept { return feature_weight_; }
    [[nodiscard]] double colour_weight() const noexcept { return colour_weight_; }
    /// Solid pixels / all pixels, in (0, 1).
    [[nodiscard]] double solid_fraction() const noexcept {
        return width_ ? static_cast<double>(solid_count_) / (static_cast<double>(width_) * static_cast<double>(height_)) : 0.0;
    }
    /// The state s per pixel, 0 (empty) or 1 (solid), W*H entries, row-major from the top-left.
    [[nodiscard]] const std::vector<std::uint8_t>& mask() const noexcept { return mask_; }
    /// The colour image as RGB (3 channels, alpha dropped), or an empty image without colour.
    [[nodiscard]] const image8& colour() const noexcept { return colour_; }

    /// Replaces the Gaussian stack: level k = the channel image blurred by a Gaussian of standard
    /// deviation sigmas_px[k] [px] (0 = unblurred), periodic for a tileable exemplar, clamped to
    /// the edge otherwise (definition in the file comment). sigmas_px: at least one value, each
    /// finite, in [0, max_stack_sigma_px], non-decreasing. Cost per level O(W H C min(2r+1, W) +
    /// W H C min(2r+1, H)) with r = ceil(3 sigma), plus O(r) for the kernel. Throws invalid_input.
    void build_stack(std::span<const double> sigmas_px) {
        if (width_ == 0) throw invalid_input("surface_pattern::exemplar::build_stack: empty exemplar (use make_exemplar)");
        if (sigmas_px.empty()) throw invalid_input("surface_pattern::exemplar::build_stack: no sigma (at least one level is needed)");
        for (std::size_t k = 0; k < sigmas_px.size(); ++k) {
            const double s = sigmas_px[k];
            if (!std::isfinite(s) || s < 0 || s > max_stack_sigma_px)
                throw invalid_input("surface_pattern::exemplar::build_stack: sigma[" + std::to_string(k) + "] = " + detail::number_text(s) +
                                    " px is not finite and in [0, " + detail::number_text(max_stack_sigma_px) + "]");
            if (k > 0 && s < sigmas_px[k - 1])
                throw invalid_input("surface_pattern::exemplar::build_stack: sigmas must be non-decreasing, but sigma[" + std::to_string(k) +
                                    "] = " + detail::number_text(s) + " < sigma[" + std::to_string(k - 1) + "] = " +
                                    detail::number_text(sigmas_px[k - 1]));
        }
        std::vector<std::vector<float>> levels;
        levels.reserve(sigmas_px.size());
        for (std::size_t k = 0; k < sigmas_px.size(); ++k) {
            if (k > 0 && sigmas_px[k] == sigmas_px[k - 1]) levels.push_back(levels.back());
            else levels.push_back(detail::gaussian_blur(base_, width_, height_, channels_, sigmas_px[k], tileable_));
        }
        levels_ = std::move(levels);
        sigmas_.assign(sigmas_px.begin(), sigmas_px.end());
    }

    /// Number of stack levels (1 after make_exemplar, 0 for an empty exemplar).
    [[nodiscard]] int stack_levels() const noexcept { return static_cast<int>(levels_.size()); }
    /// Standard deviation [px] of level k (0 <= k < stack_levels(), else invalid_input).
    [[nodiscard]] double sigma(int k) const { return sigmas_[checked_level(k, "sigma")]; }
    /// Level k: W*H*C floats, pixel-interleaved, row-major from the top-left: channel c of pixel
    /// (x, y) is level(k)[(y * W + x) * C + c]. Valid until the next build_stack.
    [[nodiscard]] const float* level(int k) const { return levels_[checked_level(k, "level")].data(); }

    /// Bilinear interpolation of level k's C channels at the continuous position (x, y) [px]
    /// (finite; wrapped, see the file comment), written to out[0..C). At pixel centres this is
    /// the pixel's value exactly.
    void sample(int k, double x, double y, float* out) const {
        const float* l = level(k);
        const detail::bilinear_taps t = taps(x, y, "sample");
        const std::size_t c = static_cast<std::size_t>(channels_);
        const float* p00 = l + pixel(t.i0, t.j0) * c;
        const float* p10 = l + pixel(t.i1, t.j0) * c;
        const float* p01 = l + pixel(t.i0, t.j1) * c;
        const float* p11 = l + pixel(t.i1, t.j1) * c;
        for (std::size_t ch = 0; ch < c; ++ch) out[ch] = static_cast<float>(lerp2(p00[ch], p10[ch], p01[ch], p11[ch], t.fx, t.fy));
    }

    /// The state s at (x, y) [px] (finite; wrapped): bilinear interpolation of the 0/1 mask >= 0.5.
    /// At a pixel centre this is the pixel's mask value.
    [[nodiscard]] bool solid_at(double x, double y) const { return mask_value(taps(x, y, "solid_at")) >= 0.5; }

    /// Colour at (x, y) [px] (finite; wrapped): bilinear interpolation of the RGB image rounded to
    /// the nearest integer, or without colour the bilinear mask as grey (255 = solid) on all
    /// three channels. At a pixel centre this is the pixel's colour.
    [[nodiscard]] std::array<std::uint8_t, 3> colour_at(double x, double y) const {
        const detail::bilinear_taps t = taps(x, y, "colour_at");
        auto to8 = [](double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); };
        if (colour_.empty()) {
            const std::uint8_t g = to8(255.0 * mask_value(t));
            return {g, g, g};
        }
        std::array<std::uint8_t, 3> rgb{};
        for (int ch = 0; ch < 3; ++ch)
            rgb[static_cast<std::size_t>(ch)] = to8(lerp2(colour_.at(t.i0, t.j0, ch), colour_.at(t.i1, t.j0, ch), colour_.at(t.i0, t.j1, ch),
                                                          colour_.at(t.i1, t.j1, ch), t.fx, t.fy));
        return rgb;
    }

private:
    friend exemplar make_exemplar(const image8& mask, const image8* colour, const exemplar_options& opt);

    [[nodiscard]] std::size_t checked_level(int k, const char* what) const {
        if (k < 0 || k >= stack_levels())
            throw invalid_input(std::string("surface_pattern::exemplar::") + what + ": level " + std::to_string(k) + " outside [0, " +
                                std::to_string(stack_levels()) + ")");
        return static_cast<std::size_t>(k);
    }
    [[nodiscard]] std::size_t pixel(int i, int j) const noexcept {
        return static_cast<std::size_t>(j) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(i);
    }
    [[nodiscard]] detail::bilinear_taps taps(double x, double y, const char* what) const {
        if (width_ == 0) throw invalid_input(std::string("surface_pattern::exemplar::") + what + ": empty exemplar");
        if (!std::isfinite(x) || !std::isfinite(y))
            throw invalid_input(std::string("surface_pattern::exemplar::") + what + ": position (" + detail::number_text(x) + ", " +
                                detail::number_text(y) + ") is not finite");
        detail::bilinear_taps t{};
        detail::bilinear_axis(x, width_, tileable_, t.i0, t.i1, t.fx);
        detail::bilinear_axis(y, height_, tileable_, t.j0, t.j1, t.fy);
        return t;
    }
    static double lerp2(double a00, double a10, double a01, double a11, double fx, double fy) noexcept {
        return (1 - fy) * ((1 - fx) * a00 + fx * a10) + fy * ((1 - fx) * a01 + fx * a11);
    }
    [[nodiscard]] double mask_value(const detail::bilinear_taps& t) const noexcept {
        return lerp2(mask_[pixel(t.i0, t.j0)], mask_[pixel(t.i1, t.j0)], mask_[pixel(t.i0, t.j1)], mask_[pixel(t.i1, t.j1)], t.fx, t.fy);
    }

    int width_ = 0, height_ = 0, channels_ = 0;
    bool tileable_ = true;
    double feature_px_ = 0, feature_weight_ = 1, colour_weight_ = 1;
    std::size_t solid_count_ = 0;
    std::vector<std::uint8_t> mask_;
    image8 colour_;
    std::vector<double> base_;  // the unblurred channel image (W*H*C, interleaved)
    std::vector<double> sigmas_;
    std::vector<std::vector<float>> levels_;
};

namespace detail {

/// Checks an image8's shape; what = "mask" or "colour".
inline void check_image(const image8& im, const char* what) {
    if (im.width <= 0 || im.height <= 0 || im.data.empty())
        throw invalid_input(std::string("surface_pattern::make_exemplar: empty ") + what + " image (" + size_text(im.width, im.height) + ")");
    if (im.channels < 1 || im.channels > 4)
        throw invalid_input(std::string("surface_pattern::make_exemplar: ") + what + " image has " + std::to_string(im.channels) +
                            " channels (1 to 4 expected)");
    const std::size_t n = static_cast<std::size_t>(im.width) * static_cast<std::size_t>(im.height) * static_cast<std::size_t>(im.channels);
    if (im.data.size() != n)
        throw invalid_input(std::string("surface_pattern::make_exemplar: ") + what + " image " + size_text(im.width, im.height) + "x" +
                            std::to_string(im.channels) + " holds " + std::to_string(im.data.size()) + " samples instead of " +
                            std::to_string(n));
}

/// Signed feature distance f [px] per pixel (file comment, ch1), before scaling and clamping
/// (only guaranteed exact where |f| <= pad_limit - 0.5 when padding is limited).
inline std::vector<double> feature_distance_px(const std::vector<std::uint8_t>& mask, int w, int h, bool tileable, double feature_px) {
    // Padding per side: wrapped copies of the tile (0 for non-tileable exemplars).
    const double reach = std::ceil(feature_px + 0.5);
    auto pad_for = [&](int n) {
        if (!tileable) return 0;
        const int half = (n + 1) / 2;
        return reach >= half ? half : static_cast<int>(reach);
    };
    const int px = pad_for(w), py = pad_for(h);
    const int pw = w + 2 * px, ph = h + 2 * py;
    const std::size_t cells = static_cast<std::size_t>(pw) * static_cast<std::size_t>(ph);
    std::vector<bool> solid(cells), empty(cells);
    for (int j = 0; j < ph; ++j) {
        const int sj = ((j - py) % h + h) % h;
        for (int i = 0; i < pw; ++i) {
            const int si = ((i - px) % w + w) % w;
            const bool s = mask[static_cast<std::size_t>(sj) * static_cast<std::size_t>(w) + static_cast<std::size_t>(si)] != 0;
            const std::size_t q = static_cast<std::size_t>(j) * static_cast<std::size_t>(pw) + static_cast<std::size_t>(i);
            solid[q] = s, empty[q] = !s;
        }
    }
    const std::array<std::size_t, 3> dims = {static_cast<std::size_t>(pw), static_cast<std::size_t>(ph), 1};
    const std::vector<double> to_empty = squared_distance_transform(dims, empty);
    const std::vector<double> to_solid = squared_distance_transform(dims, solid);
    std::vector<double> f(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::size_t p = static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
            const std::size_t q = static_cast<std::size_t>(j + py) * static_cast<std::size_t>(pw) + static_cast<std::size_t>(i + px);
            f[p] = mask[p] ? std::sqrt(to_empty[q]) - 0.5 : -(std::sqrt(to_solid[q]) - 0.5);
        }
    return f;
}

}  // namespace detail

/// Builds an exemplar from a mask and an optional colour image (the driver reads the PNGs).
/// mask: 1 channel grey (>= 128 = solid), 2 channels grey + alpha (alpha ignored), or 3/4 channels
/// RGB(A) with luminance 0.299 R + 0.587 G + 0.114 B >= 128 (computed exactly in integers:
/// 299 R + 587 G + 114 B >= 128000; alpha ignored). colour: nullptr, or RGB / RGBA (alpha
/// dropped) of the mask's size. The result holds the one-level stack sigma = 0.
/// Throws invalid_input: empty image, bad channel count or inconsistent sample count, mask and
/// colour of different sizes, no solid pixel ("empty mask"), no empty pixel ("full mask"),
/// feature_px <= 0 or not finite, negative or non-finite weights.
[[nodiscard]] inline exemplar make_exemplar(const image8& mask, const image8* colour, const exemplar_options& opt) {
    const std::string ctx = "surface_pattern::make_exemplar: ";
    if (!std::isfinite(opt.feature_px) || opt.feature_px <= 0)
        throw invalid_input(ctx + "feature_px = " + detail::number_text(opt.feature_px) + " (must be finite and > 0)");
    if (!std::isfinite(opt.feature_weight) || opt.feature_weight < 0)
        throw invalid_input(ctx + "feature_weight = " + detail::number_text(opt.feature_weight) + " (must be finite and >= 0)");
    if (!std::isfinite(opt.colour_weight) || opt.colour_weight < 0)
        throw invalid_input(ctx + "colour_weight = " + detail::number_text(opt.colour_weight) + " (must be finite and >= 0)");
    detail::check_image(mask, "mask");
    if (colour) {
        detail::check_image(*colour, "colour");
        if (colour->channels != 3 && colour->channels != 4)
            throw invalid_input(ctx + "colour image has " + std::to_string(colour->channels) + " channels (RGB or RGBA expected)");
        if (colour->width != mask.width || colour->height != mask.height)
            throw invalid_input(ctx + "mask and colour images differ in size (mask " + detail::size_text(mask.width, mask.height) +
                                ", colour " + detail::size_text(colour->width, colour->height) + ")");
    }
    const int w = mask.width, h = mask.height;
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);

    exemplar ex;
    ex.width_ = w, ex.height_ = h;
    ex.tileable_ = opt.tileable;
    ex.feature_px_ = opt.feature_px, ex.feature_weight_ = opt.feature_weight, ex.colour_weight_ = opt.colour_weight;
    ex.mask_.resize(n);
    const auto mc = static_cast<std::size_t>(mask.channels);
    for (std::size_t p = 0; p < n; ++p) {
        const std::uint8_t* s = mask.data.data() + p * mc;
        bool solid;
        if (mc <= 2) solid = s[0] >= 128;
        else solid = 299 * int{s[0]} + 587 * int{s[1]} + 114 * int{s[2]} >= 128000;
        ex.mask_[p] = solid ? 1 : 0;
        ex.solid_count_ += solid;
    }
    if (ex.solid_count_ == 0) throw invalid_input(ctx + "empty mask: no solid pixel in the " + detail::size_text(w, h) + " mask");
    if (ex.solid_count_ == n) throw invalid_input(ctx + "full mask: no empty pixel in the " + detail::size_text(w, h) + " mask");
    if (colour) {
        ex.colour_ = image8(w, h, 3);
        const auto cc = static_cast<std::size_t>(colour->channels);
        for (std::size_t p = 0; p < n; ++p)
            for (std::size_t ch = 0; ch < 3; ++ch) ex.colour_.data[p * 3 + ch] = colour->data[p * cc + ch];
    }
    ex.channels_ = colour ? 5 : 2;

    const std::vector<double> f = detail::feature_distance_px(ex.mask_, w, h, opt.tileable, opt.feature_px);
    const auto c = static_cast<std::size_t>(ex.channels_);
    ex.base_.resize(n * c);
    parallel_for(0, n, [&](std::size_t p) {
        double* b = ex.base_.data() + p * c;
        b[0] = ex.mask_[p];
        b[1] = std::clamp(f[p] / opt.feature_px, -1.0, 1.0) * opt.feature_weight;
        if (c == 5)
            for (std::size_t ch = 0; ch < 3; ++ch) b[2 + ch] = ex.colour_.data[p * 3 + ch] / 255.0 * opt.colour_weight;
    }, {.grain = 4096});
    const double zero = 0;
    ex.build_stack(std::span<const double>(&zero, 1));
    return ex;
}

}  // namespace fabsynth::surface_pattern
