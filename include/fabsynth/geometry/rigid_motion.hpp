// SPDX-License-Identifier: MIT
#pragma once
/// @file rigid_motion.hpp  Rigid motions of the plane (a rotation, then a translation) and their
/// least-squares fit to point correspondences (2D Procrustes without scaling).
///
/// Usage:
///   auto m = fabsynth::fit_rigid_motion(from, to);   // spans of vec2, same length
///   vec2 y = m(x);  vec2 x2 = m.inverse()(y);
///
/// The fit: both point sets centred on their centroids, the angle is atan2(sum of cross products,
/// sum of dot products) of the centred pairs, which minimises the sum of squared distances over
/// rotations; the translation then matches the centroids. Exact (up to rounding) when `to` is a
/// rigid image of `from`.
#include <cmath>
#include <span>
#include <string>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth {

/// x -> R x + t, R the rotation by the angle whose cosine and sine are c and s.
struct rigid_motion2 {
    double c = 1.0, s = 0.0;  ///< cosine and sine of the angle
    vec2 t{0.0, 0.0};         ///< translation, mm

    [[nodiscard]] vec2 operator()(vec2 x) const noexcept { return {c * x.x - s * x.y + t.x, s * x.x + c * x.y + t.y}; }
    /// The motion undoing this one: x = R^T (y - t).
    [[nodiscard]] rigid_motion2 inverse() const noexcept { return {c, -s, vec2(-(c * t.x + s * t.y), s * t.x - c * t.y)}; }
};

/// The rigid motion m minimising sum |m(from[k]) - to[k]|^2 (see the file comment). Throws
/// invalid_input for spans of different lengths, empty spans or non-finite points.
[[nodiscard]] inline rigid_motion2 fit_rigid_motion(std::span<const vec2> from, std::span<const vec2> to) {
    if (from.size() != to.size() || from.empty())
        throw invalid_input("fit_rigid_motion: " + std::to_string(from.size()) + " and " + std::to_string(to.size()) +
                            " points; two non-empty lists of equal length are needed");
    vec2 cf(0.0), ct(0.0);
    for (std::size_t k = 0; k < from.size(); ++k) {
        if (!all_finite(from[k]) || !all_finite(to[k])) throw invalid_input("fit_rigid_motion: point " + std::to_string(k) + " is not finite");
        cf += from[k], ct += to[k];
    }
    cf /= static_cast<double>(from.size()), ct /= static_cast<double>(to.size());
    double dot = 0.0, cross = 0.0;
    for (std::size_t k = 0; k < from.size(); ++k) {
        const vec2 a = from[k] - cf, b = to[k] - ct;
        dot += a.x * b.x + a.y * b.y, cross += a.x * b.y - a.y * b.x;
    }
    const double angle = (dot == 0.0 && cross == 0.0) ? 0.0 : std::atan2(cross, dot);  // all points equal: any angle
    rigid_motion2 m{std::cos(angle), std::sin(angle), vec2(0.0)};
    m.t = ct - m(cf);  // m(cf) is R cf while t is zero
    return m;
}

}  // namespace fabsynth
