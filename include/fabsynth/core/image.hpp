// SPDX-License-Identifier: MIT
#pragma once
/// @file image.hpp  A minimal row-major multi-channel raster (no file I/O here; see io/image.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"

namespace fabsynth {

/// width x height pixels of `channels` samples each, row-major from the top-left corner:
/// sample (x, y, c) is data[(y * width + x) * channels + c].
template <class T>
struct image {
    int width = 0;
    int height = 0;
    int channels = 1;
    std::vector<T> data;

    image() = default;
    image(int w, int h, int c = 1, T fill = T{}) : width(w), height(h), channels(c) {
        if (w < 0 || h < 0 || c < 1 || c > 4)
            throw invalid_input("image size " + std::to_string(w) + "x" + std::to_string(h) + "x" +
                                std::to_string(c) + " is invalid");
        data.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(c), fill);
    }
    [[nodiscard]] bool empty() const noexcept { return data.empty(); }
    [[nodiscard]] T& at(int x, int y, int c = 0) noexcept { return data[index(x, y, c)]; }
    [[nodiscard]] const T& at(int x, int y, int c = 0) const noexcept { return data[index(x, y, c)]; }
    friend bool operator==(const image&, const image&) = default;

private:
    [[nodiscard]] std::size_t index(int x, int y, int c) const noexcept {
        return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) *
                   static_cast<std::size_t>(channels) + static_cast<std::size_t>(c);
    }
};

using image8 = image<std::uint8_t>;    ///< 8-bit samples (PNG/PGM)
using image16 = image<std::uint16_t>;  ///< 16-bit samples (PNG/PGM with maxval > 255)

/// A single-channel picture of `img`: the grey level itself for grey and grey+alpha pictures
/// (channels 1, 2), the integer mean (R + G + B) / 3 for RGB and RGBA (3, 4). Alpha is ignored.
[[nodiscard]] inline image8 grey_levels(const image8& img) {
    if (img.channels <= 2) {
        if (img.channels == 1) return img;
        image8 g(img.width, img.height, 1);
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) g.at(x, y) = img.at(x, y, 0);
        return g;
    }
    image8 g(img.width, img.height, 1);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) g.at(x, y) = static_cast<std::uint8_t>((img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3);
    return g;
}

/// Single-channel images of one size side by side, left to right, `gap` pixels of `background`
/// between them; flip_y turns each upside down (slices stored with row 0 at the bottom become
/// pictures with +y up). Throws invalid_input for an empty list or images of different sizes.
template <class T>
[[nodiscard]] image<T> side_by_side(const std::vector<image<T>>& images, int gap, T background, bool flip_y) {
    if (images.empty()) throw invalid_input("side_by_side: no images");
    const int w = images[0].width, h = images[0].height, n = static_cast<int>(images.size());
    for (const auto& im : images)
        if (im.width != w || im.height != h || im.channels != 1)
            throw invalid_input("side_by_side: the images must be single-channel and of one size");
    image<T> out(w * n + gap * (n - 1), h, 1, background);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) out.at(k * (w + gap) + i, flip_y ? h - 1 - j : j) = images[static_cast<std::size_t>(k)].at(i, j);
    return out;
}

}  // namespace fabsynth
