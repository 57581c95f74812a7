// SPDX-License-Identifier: MIT
#pragma once
/// @file fields.hpp  Scalar fields that drive a Voronoi foam: seed density rho(x) (seeds/mm^3) and
/// beam radius tau(x) (mm).
///
/// Any callable `double f(const vec3& x)` is a field (concept `scalar_field`). The ready-made
/// fields below also report an upper bound of their values (`bounded_field`), which the foam needs
/// as a certified bound on tau. Fields that read an image, a mesh or the elasticity fit are in
/// field_adaptors.hpp (kept apart so the seed and evaluator headers do not pull those in).
///
/// Usage:
///   linear_field rho{.axis = 2, .v0 = 0.05, .v1 = 0.6, .x0 = 0, .x1 = 30};     // seeds/mm^3 along z
///   variant_field<constant_field, linear_field> f{rho};                        // chosen at run time
///   double r = f({1, 2, 3}), bound = f.max_value();
#include <algorithm>
#include <concepts>
#include <string>
#include <type_traits>
#include <variant>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth::foam {

/// A field: callable as f(vec3 x [mm]) -> double. Expected O(1) and thread-safe (called concurrently).
template <class F>
concept scalar_field = std::invocable<const F&, const vec3&> &&
                       std::convertible_to<std::invoke_result_t<const F&, const vec3&>, double>;

/// A field that also knows an upper bound of its values over all space: f.max_value() -> double.
template <class F>
concept bounded_field = scalar_field<F> && requires(const F& f) {
    { f.max_value() } -> std::convertible_to<double>;
};

/// The same value everywhere.
struct constant_field {
    double value = 0;
    [[nodiscard]] constexpr double operator()(const vec3&) const noexcept { return value; }
    [[nodiscard]] constexpr double max_value() const noexcept { return value; }
};

/// Linear ramp along one axis: v0 at coordinate x0, v1 at x1, constant outside [x0, x1].
struct linear_field {
    int axis = 0;  ///< 0 = x, 1 = y, 2 = z
    double v0 = 0, v1 = 0;
    double x0 = 0, x1 = 1;  ///< mm, x0 != x1
    [[nodiscard]] double operator()(const vec3& p) const noexcept {
        const double t = std::clamp((p[axis] - x0) / (x1 - x0), 0.0, 1.0);
        return v0 + (v1 - v0) * t;
    }
    [[nodiscard]] double max_value() const noexcept { return std::max(v0, v1); }
    /// Throws invalid_input naming `what` on a bad axis, equal ends or non-finite values.
    void validate(const char* what) const {
        if (axis < 0 || axis > 2) throw invalid_input(std::string(what) + ": axis must be 0, 1 or 2");
        require_finite(v0, what), require_finite(v1, what), require_finite(x0, what), require_finite(x1, what);
        if (x0 == x1) throw invalid_input(std::string(what) + ": ramp ends x0 and x1 must differ");
    }
};

/// One of several field types, chosen at run time (e.g. from a command line): a std::variant of
/// fields called through std::visit, value and bound those of the held alternative. Bounded when
/// every alternative is. Same values, bit for bit, as calling the held field directly.
template <scalar_field... Fields>
struct variant_field {
    std::variant<Fields...> field;
    [[nodiscard]] double operator()(const vec3& p) const {
        return std::visit([&](const auto& f) { return static_cast<double>(f(p)); }, field);
    }
    [[nodiscard]] double max_value() const
        requires(bounded_field<Fields> && ...)
    {
        return std::visit([](const auto& f) { return static_cast<double>(f.max_value()); }, field);
    }
};

}  // namespace fabsynth::foam
