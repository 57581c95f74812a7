// SPDX-License-Identifier: MIT
#pragma once
/// @file coverage_image.hpp  The PNG preview of planar shapes (vector patterns, filigrees): a
/// grey-level coverage image of polygons (pattern dark on white), so a person can look at a result
/// instead of reading it.
///
/// The view box is divided into square pixels, max_side of them along its longer side (the other
/// side rounded up); every pixel is split into supersample x supersample sub-pixels, each inside
/// iff its centre is (even-odd fill, geometry/raster.hpp's polygon_rasterizer), and the pixel's
/// grey level is 255 - 255 * covered / supersample^2 (integer division): 0 = fully covered,
/// 255 = background. Row 0 is the view's smallest y (for SVG coordinates, the top of the drawing),
/// so the image shows the drawing as an SVG viewer does.
///
/// framed_view() is the view both outputs of a driver share: the pattern's bounding box with a
/// margin of pad_fraction of its longer side on every side.
///
/// Usage:
///   const box2 view = fabsynth::framed_view(bounding_box(drawn));
///   image8 png = fabsynth::preview_image(drawn, view, {.max_side = 1600});
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/raster.hpp"

namespace fabsynth {

/// Options of preview_image.
struct preview_options {
    int max_side = 1600;  ///< pixels along the view's longer side, in [1, 16384]
    int supersample = 4;  ///< sub-pixels per pixel along each axis, in [1, 16]
};

/// `bounds` grown by pad_fraction (>= 0) of its longer side on every side. Throws invalid_input for
/// empty bounds or a negative or non-finite fraction.
[[nodiscard]] inline box2 framed_view(const box2& bounds, double pad_fraction = 0.02) {
    if (bounds.empty()) throw invalid_input("framed_view: the bounds are empty (nothing to show)");
    if (!(std::isfinite(pad_fraction) && pad_fraction >= 0.0))
        throw invalid_input("framed_view: pad_fraction must be finite and >= 0, got " + std::to_string(pad_fraction));
    const double pad = pad_fraction * std::max(bounds.size().x, bounds.size().y);
    return box2(bounds.lo - vec2(pad), bounds.hi + vec2(pad));
}

/// Coverage image of `polys` (mm) over `view` (see the file comment); one channel. Throws
/// invalid_input for an empty, degenerate or non-finite view, or options out of range.
[[nodiscard]] inline image8 preview_image(const std::vector<polygon_with_holes>& polys, const box2& view,
                                          const preview_options& opt = {}) {
    if (view.empty() || !all_finite(view.lo) || !all_finite(view.hi) || !(std::max(view.size().x, view.size().y) > 0.0))
        throw invalid_input("preview_image: the view box is empty, degenerate or not finite");
    if (opt.max_side < 1 || opt.max_side > 16384)
        throw invalid_input("preview_image: max_side must be in [1, 16384], got " + std::to_string(opt.max_side));
    if (opt.supersample < 1 || opt.supersample > 16)
        throw invalid_input("preview_image: supersample must be in [1, 16], got " + std::to_string(opt.supersample));
    const vec2 size = view.size();
    const double px = std::max(size.x, size.y) / opt.max_side;
    const int w = std::max(1, static_cast<int>(std::ceil(size.x / px))), h = std::max(1, static_cast<int>(std::ceil(size.y / px)));
    const int ss = opt.supersample;
    std::vector<int> cover(static_cast<std::size_t>(w) * h, 0);
    polygon_rasterizer raster;
    for (const auto& p : polys) raster.add_polygon(p);
    raster.for_each_run({view.lo, px / ss, w * ss, h * ss}, [&](int row, int c0, int c1) {
        for (int c = c0; c < c1; ++c) ++cover[static_cast<std::size_t>(row / ss) * w + static_cast<std::size_t>(c / ss)];
    });
    image8 img(w, h, 1, 255);
    for (std::size_t i = 0; i < cover.size(); ++i) img.data[i] = static_cast<std::uint8_t>(255 - (255 * cover[i]) / (ss * ss));
    return img;
}

}  // namespace fabsynth
