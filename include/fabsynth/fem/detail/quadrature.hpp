// SPDX-License-Identifier: MIT
#pragma once
/// @file quadrature.hpp  Gauss rules used by the elements (internal).
#include <array>

#include "fabsynth/core/types.hpp"

namespace fabsynth::fem::detail {

struct quad_point {
    vec3 xi;        ///< natural coordinates
    double weight;  ///< weight in natural coordinates
};

/// 2x2x2 Gauss-Legendre rule on [-1,1]^3 (exact for tri-cubic polynomials).
inline const std::array<quad_point, 8>& gauss_2x2x2() {
    static const std::array<quad_point, 8> rule = [] {
        const double g = 0.57735026918962576451;  // 1/sqrt(3)
        std::array<quad_point, 8> r{};
        int n = 0;
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) r[n++] = {vec3(i ? g : -g, j ? g : -g, k ? g : -g), 1.0};
        return r;
    }();
    return rule;
}

/// Wedge rule: 3-point interior triangle rule (degree 2, points (1/6,1/6),(2/3,1/6),(1/6,2/3),
/// weights 1/6) times 2-point Gauss in zeta (degree 3). xi = (r, s, zeta), r,s >= 0, r+s <= 1.
inline const std::array<quad_point, 6>& wedge_3x2() {
    static const std::array<quad_point, 6> rule = [] {
        const double g = 0.57735026918962576451;
        const double tri[3][2] = {{1.0 / 6, 1.0 / 6}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}};
        std::array<quad_point, 6> r{};
        int n = 0;
        for (int k = 0; k < 2; ++k)
            for (const auto& t : tri) r[n++] = {vec3(t[0], t[1], k ? g : -g), 1.0 / 6};
        return r;
    }();
    return rule;
}

}  // namespace fabsynth::fem::detail
