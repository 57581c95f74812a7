// SPDX-License-Identifier: MIT
#pragma once
/// @file drawing.hpp  What the pipelines read from a vector drawing, as concepts, so that they take
/// io::svg_document (io/svg.hpp) without depending on io/ (the drivers read the files).
///
///   svg_like_document  shapes with `subpaths`, `closed`, `rule`, `id` and `filled()`
///                      (vector_pattern/exemplar.hpp: filled exemplars)
///   stroked_document   additionally `stroke_width` and `stroked()` (filigree/element.hpp: strokes
///                      are skeletons)
#include <concepts>
#include <string>

#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth {

/// A document of shapes with flattened subpaths and fill attributes.
template <class Doc>
concept svg_like_document = requires(const Doc& d) {
    d.shapes.size();
    d.shapes[0].subpaths;
    d.shapes[0].closed;
    { d.shapes[0].rule } -> std::convertible_to<fill_rule>;
    { d.shapes[0].filled() } -> std::convertible_to<bool>;
    { d.shapes[0].id } -> std::convertible_to<std::string>;
};

/// An svg_like_document whose shapes also carry their stroke.
template <class Doc>
concept stroked_document = svg_like_document<Doc> && requires(const Doc& d) {
    { d.shapes[0].stroke_width } -> std::convertible_to<double>;
    { d.shapes[0].stroked() } -> std::convertible_to<bool>;
};

}  // namespace fabsynth
