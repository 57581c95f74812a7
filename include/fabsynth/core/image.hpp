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

}  // namespace fabsynth
