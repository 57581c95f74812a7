// SPDX-License-Identifier: MIT
#pragma once
/// @file box.hpp  Axis-aligned boxes in N dimensions (closed: lo <= p <= hi).
#include <algorithm>
#include <limits>

#include "fabsynth/core/types.hpp"

namespace fabsynth {

/// Axis-aligned box [lo, hi]. Default-constructed boxes are empty (lo > hi), so extend() works
/// from nothing. Usage: `box3 b; for (auto& p : pts) b.extend(p);`
template <glm::length_t N, class T>
struct box {
    using point = glm::vec<N, T>;
    point lo{std::numeric_limits<T>::max()};
    point hi{std::numeric_limits<T>::lowest()};

    constexpr box() = default;
    constexpr box(const point& l, const point& h) : lo(l), hi(h) {}

    [[nodiscard]] constexpr bool empty() const {
        for (glm::length_t i = 0; i < N; ++i)
            if (lo[i] > hi[i]) return true;
        return false;
    }
    constexpr box& extend(const point& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
        return *this;
    }
    constexpr box& extend(const box& b) {
        if (!b.empty()) extend(b.lo), extend(b.hi);
        return *this;
    }
    [[nodiscard]] constexpr point size() const { return empty() ? point(T(0)) : hi - lo; }
    [[nodiscard]] constexpr point center() const { return (lo + hi) / T(2); }
    [[nodiscard]] constexpr bool contains(const point& p) const {
        for (glm::length_t i = 0; i < N; ++i)
            if (p[i] < lo[i] || p[i] > hi[i]) return false;
        return true;
    }
    [[nodiscard]] constexpr bool intersects(const box& b) const {
        for (glm::length_t i = 0; i < N; ++i)
            if (b.hi[i] < lo[i] || b.lo[i] > hi[i]) return false;
        return true;
    }
    /// Box grown by d on every side.
    [[nodiscard]] constexpr box inflated(T d) const { return box(lo - point(d), hi + point(d)); }
    /// Product of the side lengths (0 for an empty box).
    [[nodiscard]] constexpr T volume() const {
        if (empty()) return T(0);
        T v(1);
        for (glm::length_t i = 0; i < N; ++i) v *= hi[i] - lo[i];
        return v;
    }
    friend constexpr bool operator==(const box&, const box&) = default;
};

using box2 = box<2, double>;
using box3 = box<3, double>;
using ibox3 = box<3, int>;

}  // namespace fabsynth
