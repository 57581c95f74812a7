// SPDX-License-Identifier: MIT
#pragma once
/// @file segment.hpp  Distance from a point to a line segment, in 2D or 3D (the one copy used by
/// the foam evaluator, the band map and every other caller).
///
/// Usage:
///   double d2 = fabsynth::segment_distance2(p, a, b);   // squared distance, mm^2
///   double d  = fabsynth::segment_distance(p, a, b);    // distance, mm
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace fabsynth {

/// Parameter t in [0, 1] of the point of segment [a, b] closest to p (0 for a degenerate segment).
template <glm::length_t N, class T, glm::qualifier Q>
[[nodiscard]] inline T segment_closest_parameter(const glm::vec<N, T, Q>& p, const glm::vec<N, T, Q>& a,
                                                 const glm::vec<N, T, Q>& b) noexcept {
    const glm::vec<N, T, Q> ab = b - a;
    const T l2 = glm::dot(ab, ab);
    return l2 > T(0) ? std::clamp(glm::dot(p - a, ab) / l2, T(0), T(1)) : T(0);
}

/// Squared distance from p to segment [a, b].
template <glm::length_t N, class T, glm::qualifier Q>
[[nodiscard]] inline T segment_distance2(const glm::vec<N, T, Q>& p, const glm::vec<N, T, Q>& a,
                                         const glm::vec<N, T, Q>& b) noexcept {
    const glm::vec<N, T, Q> d = (p - a) - segment_closest_parameter(p, a, b) * (b - a);
    return glm::dot(d, d);
}

/// Distance from p to segment [a, b].
template <glm::length_t N, class T, glm::qualifier Q>
[[nodiscard]] inline T segment_distance(const glm::vec<N, T, Q>& p, const glm::vec<N, T, Q>& a,
                                        const glm::vec<N, T, Q>& b) noexcept {
    return std::sqrt(segment_distance2(p, a, b));
}

}  // namespace fabsynth
