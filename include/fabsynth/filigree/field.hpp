// SPDX-License-Identifier: MIT
#pragma once
/// @file field.hpp  Control fields of filigree synthesis (filigree-synthesis.md §3.2, §7.2, Fig. 15):
/// at every point of the domain, the rotation and scale an element placed there takes. Elements are
/// rotated and scaled by the field at their reference point before any overlap or matching test
/// (§4.1, §4.3.1).
///
/// A control field is any callable `field_sample f(vec2 p)` (p in mm, domain frame). Provided:
///   constant_field{rotation, scale}
///   linear_ramp{from, to, at_from, at_to}        values blended along the segment from -> to, clamped
///   radial_ramp{centre, radius, at_centre, at_radius, tangential}
///   image_field{gray, extent, scale_black, scale_white, rotation}  a grayscale picture over a box: scale
///   image_rotation_field{gray, extent, rotation_black, rotation_white, scale}  the same: rotation
///   combined_field{rotation_from, scale_from}     the rotation of one field, the scale of another
/// Usage:
///   fabsynth::filigree::any_field f = fabsynth::filigree::radial_ramp{{50, 50}, 40, {0, 0.6}, {0, 1.2}};
///   fabsynth::filigree::field_sample s = f({10, 20});   // s.rotation [rad], s.scale (factor)
///
/// Rotation is in radians, counter-clockwise in a y-up frame; scale multiplies the element size.
#include <algorithm>
#include <cmath>
#include <concepts>
#include <functional>
#include <string>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth::filigree {

/// Rotation (radians) and scale (factor > 0) of an element at one point.
struct field_sample {
    double rotation = 0.0;
    double scale = 1.0;
};

/// Anything callable as field_sample(vec2).
template <class F>
concept control_field = requires(const F& f, vec2 p) {
    { f(p) } -> std::convertible_to<field_sample>;
};

/// Type-erased control field (what the synthesis driver stores).
using any_field = std::function<field_sample(vec2)>;

/// The same rotation and scale everywhere.
struct constant_field {
    double rotation = 0.0;
    double scale = 1.0;
    [[nodiscard]] field_sample operator()(vec2) const noexcept { return {rotation, scale}; }
};

namespace detail::field {
[[nodiscard]] inline field_sample blend(const field_sample& a, const field_sample& b, double t) noexcept {
    t = std::clamp(t, 0.0, 1.0);
    return {a.rotation + t * (b.rotation - a.rotation), a.scale + t * (b.scale - a.scale)};
}
}  // namespace detail::field

/// Linear ramp: at_from at `from`, at_to at `to`, blended by the projection onto from -> to (mm),
/// constant beyond both ends.
struct linear_ramp {
    vec2 from{0, 0}, to{1, 0};
    field_sample at_from, at_to;
    [[nodiscard]] field_sample operator()(vec2 p) const noexcept {
        const vec2 d = to - from;
        const double l2 = glm::dot(d, d);
        return detail::field::blend(at_from, at_to, l2 > 0 ? glm::dot(p - from, d) / l2 : 0.0);
    }
};

/// Radial ramp: at_centre at `centre`, at_radius at distance `radius` (mm) and beyond. With
/// `tangential`, the polar angle of p around the centre is added to the rotation (elements turn
/// around the centre, as in the paper's Fig. 15 swirl).
struct radial_ramp {
    vec2 centre{0, 0};
    double radius = 1.0;
    field_sample at_centre, at_radius;
    bool tangential = false;
    [[nodiscard]] field_sample operator()(vec2 p) const noexcept {
        const vec2 d = p - centre;
        field_sample s = detail::field::blend(at_centre, at_radius, radius > 0 ? glm::length(d) / radius : 0.0);
        if (tangential && (d.x != 0 || d.y != 0)) s.rotation += std::atan2(d.y, d.x);
        return s;
    }
};

namespace detail::field {
// The checks of a grey picture stretched over a box (what image_field and image_rotation_field share).
inline void check_picture(const image8& gray, const box2& extent, const char* who) {
    if (gray.empty() || gray.channels != 1) throw invalid_input(std::string(who) + ": the field image must be a non-empty grayscale image");
    if (extent.empty() || !(extent.hi.x > extent.lo.x && extent.hi.y > extent.lo.y))
        throw invalid_input(std::string(who) + ": the field extent is empty");
}
// The picture's value at p in [0, 1] (0 black, 1 white): bilinear between pixel centres, clamped
// at the border; pixel row 0 at extent.lo.y.
[[nodiscard]] inline double picture_value(const image8& gray, const box2& extent, vec2 p) noexcept {
    const double fx = (p.x - extent.lo.x) / (extent.hi.x - extent.lo.x) * gray.width - 0.5;
    const double fy = (p.y - extent.lo.y) / (extent.hi.y - extent.lo.y) * gray.height - 0.5;
    const double cx = std::clamp(fx, 0.0, gray.width - 1.0), cy = std::clamp(fy, 0.0, gray.height - 1.0);
    const int x0 = static_cast<int>(cx), y0 = static_cast<int>(cy);
    const int x1 = std::min(x0 + 1, gray.width - 1), y1 = std::min(y0 + 1, gray.height - 1);
    const double tx = cx - x0, ty = cy - y0;
    return ((1 - ty) * ((1 - tx) * gray.at(x0, y0) + tx * gray.at(x1, y0)) + ty * ((1 - tx) * gray.at(x0, y1) + tx * gray.at(x1, y1))) / 255.0;
}
}  // namespace detail::field

/// A grayscale picture stretched over `extent` (mm; pixel row 0 at extent.lo.y): the scale goes
/// from scale_black (value 0) to scale_white (255), bilinear between pixel centres, clamped at
/// the border; the rotation is constant. Throws invalid_input for an empty or multi-channel image,
/// an empty extent or a scale that is not finite and > 0.
struct image_field {
    image8 gray;
    box2 extent;
    double scale_black = 1.0, scale_white = 1.0;
    double rotation = 0.0;

    image_field(image8 g, box2 e, double s0, double s1, double rot = 0.0)
        : gray(std::move(g)), extent(e), scale_black(s0), scale_white(s1), rotation(rot) {
        detail::field::check_picture(gray, extent, "image_field");
        for (double s : {s0, s1})
            if (!(std::isfinite(s) && s > 0)) throw invalid_input("image_field: field scales must be finite and > 0");
        if (!std::isfinite(rot)) throw invalid_input("image_field: the rotation is not finite");
    }
    [[nodiscard]] field_sample operator()(vec2 p) const noexcept {
        return {rotation, scale_black + detail::field::picture_value(gray, extent, p) * (scale_white - scale_black)};
    }
};

/// An orientation field drawn as a grayscale picture over `extent` (mm, as image_field): the
/// rotation goes from rotation_black (value 0) to rotation_white (255) radians, bilinear between
/// pixel centres (so a grey ramp turns the elements steadily; the angle is not wrapped, draw the
/// range you want); the scale is constant. Throws invalid_input for an empty or multi-channel
/// image, an empty extent, a rotation that is not finite or a scale that is not finite and > 0.
struct image_rotation_field {
    image8 gray;
    box2 extent;
    double rotation_black = 0.0, rotation_white = 0.0;
    double scale = 1.0;

    image_rotation_field(image8 g, box2 e, double r0, double r1, double s = 1.0)
        : gray(std::move(g)), extent(e), rotation_black(r0), rotation_white(r1), scale(s) {
        detail::field::check_picture(gray, extent, "image_rotation_field");
        if (!(std::isfinite(r0) && std::isfinite(r1))) throw invalid_input("image_rotation_field: the rotations must be finite (radians)");
        if (!(std::isfinite(s) && s > 0)) throw invalid_input("image_rotation_field: the scale must be finite and > 0");
    }
    [[nodiscard]] field_sample operator()(vec2 p) const noexcept {
        return {rotation_black + detail::field::picture_value(gray, extent, p) * (rotation_white - rotation_black), scale};
    }
};

/// The rotation of one field with the scale of another (e.g. an image_rotation_field steering the
/// orientation and an image_field the size).
template <control_field R, control_field S>
struct combined_field {
    R rotation_from;
    S scale_from;
    [[nodiscard]] field_sample operator()(vec2 p) const { return {field_sample(rotation_from(p)).rotation, field_sample(scale_from(p)).scale}; }
};

}  // namespace fabsynth::filigree
