// SPDX-License-Identifier: MIT
#pragma once
/// @file slice_stack.hpp  Which slices to print for a part: the layers of a stack through its
/// bounding box and the region every slice covers (used with framed_foam::slice or
/// voronoi_foam::slice).
///
/// Layer k spans z in [lo.z + k h, lo.z + (k + 1) h] (h = layer height) and is sliced at its
/// middle; there are max(1, floor(height / h)) layers. The slice region is the box's xy footprint
/// grown by one pixel on every side, so the part's outline never touches the image border.
///
/// Usage:
///   slice_stack st = plan_slice_stack(bounding_box(mesh), 0.05, 0.05, 8);   // 8 evenly spaced layers
///   for (int k : st.selected) image8 s = obj.slice(st.z(k), st.region, st.pixel);
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth::foam {

/// A planned slice stack (see the file comment).
struct slice_stack {
    box2 region;               ///< xy region of every slice, mm
    double pixel = 0;          ///< pixel side, mm
    double layer = 0;          ///< layer height, mm
    double z0 = 0;             ///< bottom of layer 0, mm
    int layers = 0;            ///< layers in the stack
    std::vector<int> selected; ///< layer indices to slice, increasing
    /// Height of the slice through layer k (its middle), mm.
    [[nodiscard]] double z(int k) const noexcept { return z0 + (k + 0.5) * layer; }
};

/// Plans the stack through box bb (mm) with square pixels of side `pixel` (> 0) and layers of
/// height `layer` (<= 0: the pixel size). count > 0 selects count evenly spaced layers (layer
/// floor((s + 1/2) layers / count) for s = 0..count-1); count <= 0 selects every layer. Throws
/// invalid_input for a non-positive pixel, a box that is empty or not finite, more layers than
/// an int holds, or count > layers (the stack has fewer distinct layers than asked for).
[[nodiscard]] inline slice_stack plan_slice_stack(const box3& bb, double pixel, double layer, int count) {
    if (layer <= 0) layer = pixel;
    require_positive(pixel, "foam slice stack pixel size");
    if (!all_finite(bb.lo) || !all_finite(bb.hi) || bb.empty()) throw invalid_input("foam slice stack: box is empty or not finite");
    slice_stack st;
    st.pixel = pixel, st.layer = layer, st.z0 = bb.lo.z;
    st.region = box2(vec2(bb.lo.x, bb.lo.y) - vec2(pixel), vec2(bb.hi.x, bb.hi.y) + vec2(pixel));
    const double layers = std::floor(bb.size().z / layer);
    if (!(layers < 2e9)) throw invalid_input("foam slice stack: " + std::to_string(layers) + " layers of " + std::to_string(layer) + " mm are too many");
    st.layers = std::max(1, static_cast<int>(layers));
    if (count > st.layers)
        throw invalid_input("foam slice stack: " + std::to_string(count) + " slices asked for, but the stack has only " + std::to_string(st.layers) +
                            " layers of " + std::to_string(layer) + " mm");
    if (count > 0) {
        for (int s = 0; s < count; ++s) st.selected.push_back(static_cast<int>((s + 0.5) * st.layers / count));
    } else {
        for (int s = 0; s < st.layers; ++s) st.selected.push_back(s);
    }
    return st;
}

/// What a stack would cost, estimated from its box alone (nothing is allocated), so a caller can
/// refuse an oversized stack before planning it (a 0.003 mm pixel over 40 mm is 2e12 evaluations).
struct slice_stack_cost {
    double slices = 0;            ///< slices that would be rendered (count, or every layer)
    double pixels_per_slice = 0;  ///< of the region plan_slice_stack would choose
    double evaluations = 0;       ///< point evaluations: slices x pixels x supersample^2
    double slab_bytes = 0;        ///< images for_each_slice holds at once (one byte per pixel; at least one slice)
};

/// The cost of plan_slice_stack(bb, pixel, layer, count) sliced at `supersample`^2 samples per
/// pixel by for_each_slice with a slab limit of `slab_bytes` (slice_options::slab_bytes). The
/// arguments are not checked here (plan_slice_stack does).
[[nodiscard]] inline slice_stack_cost estimate_slice_stack(const box3& bb, double pixel, double layer, int count, int supersample, double slab_bytes) {
    slice_stack_cost c;
    const double layers = std::max(1.0, std::floor(bb.size().z / (layer > 0 ? layer : pixel)));
    c.slices = count > 0 ? std::min<double>(count, layers) : layers;
    c.pixels_per_slice = std::ceil(bb.size().x / pixel + 2) * std::ceil(bb.size().y / pixel + 2);
    c.evaluations = c.slices * c.pixels_per_slice * supersample * supersample;
    c.slab_bytes = std::max(c.pixels_per_slice, std::min(c.slices * c.pixels_per_slice, slab_bytes));
    return c;
}

}  // namespace fabsynth::foam
