// SPDX-License-Identifier: MIT
#pragma once
/// @file types.hpp  Vocabulary types at API edges (glm vectors), units and small numeric helpers.
///
/// Units everywhere: millimetres, newtons, MPa, unless a name says otherwise.
#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <string>

#include "fabsynth/core/error.hpp"

namespace fabsynth {

using vec2 = glm::dvec2;
using vec3 = glm::dvec3;
using fvec3 = glm::vec3;
using ivec2 = glm::ivec2;
using ivec3 = glm::ivec3;
using i64vec3 = glm::i64vec3;

/// True iff every component is finite (not NaN, not +-inf).
template <glm::length_t N, class T, glm::qualifier Q>
[[nodiscard]] constexpr bool all_finite(const glm::vec<N, T, Q>& v) {
    for (glm::length_t i = 0; i < N; ++i)
        if (!std::isfinite(static_cast<double>(v[i]))) return false;
    return true;
}

/// Throws invalid_input naming `what` unless x is finite.
inline double require_finite(double x, const char* what) {
    if (!std::isfinite(x)) throw invalid_input(std::string(what) + " must be finite, got " + std::to_string(x));
    return x;
}

/// Throws invalid_input naming `what` unless x is finite and > 0.
inline double require_positive(double x, const char* what) {
    if (!(std::isfinite(x) && x > 0.0))
        throw invalid_input(std::string(what) + " must be finite and > 0, got " + std::to_string(x));
    return x;
}

}  // namespace fabsynth
