// SPDX-License-Identifier: MIT
#pragma once
/// @file isoparametric.hpp  Shared kernel of the isoparametric solid elements (internal).
#include <Eigen/Core>
#include <Eigen/LU>

#include <array>
#include <cmath>
#include <string>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth::fem::detail {

/// Result of mapping natural derivatives to physical ones at one point.
template <int N>
struct iso_point {
    Eigen::Matrix<double, 3, N> dN;  ///< dN_a/dx_i, row i = x, y, z
    double detJ = 0;
};

/// dNdxi: row i = derivatives w.r.t. natural coordinate i. Throws invalid_input if the element is
/// inverted or degenerate at this point (det J <= tiny * size^3) or has non-finite nodes.
template <int N>
iso_point<N> map_derivatives(const std::array<vec3, N>& X, const Eigen::Matrix<double, 3, N>& dNdxi, const char* name) {
    Eigen::Matrix3d J = Eigen::Matrix3d::Zero();  // J(i, j) = d x_j / d xi_i
    double size2 = 0;
    for (int a = 0; a < N; ++a) {
        if (!all_finite(X[a])) throw invalid_input(std::string(name) + ": node " + std::to_string(a) + " is not finite");
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) J(i, j) += dNdxi(i, a) * X[a][j];
        const vec3 d = X[a] - X[0];
        size2 = std::max(size2, glm::dot(d, d));
    }
    iso_point<N> r;
    r.detJ = J.determinant();
    // Natural cells have volume O(1), so det J ~ size^3; a relative 1e-12 floor catches collapse.
    if (!(r.detJ > 1e-12 * size2 * std::sqrt(size2)))
        throw invalid_input(std::string(name) + ": element is inverted or degenerate (det J = " + std::to_string(r.detJ) +
                            "); check the node order and coordinates");
    r.dN = J.inverse() * dNdxi;
    return r;
}

/// 6 x 3N strain-displacement matrix in Voigt order (xx, yy, zz, yz, xz, xy), engineering shear.
template <int N>
Eigen::Matrix<double, 6, 3 * N> voigt_b(const Eigen::Matrix<double, 3, N>& dN) {
    Eigen::Matrix<double, 6, 3 * N> B = Eigen::Matrix<double, 6, 3 * N>::Zero();
    for (int a = 0; a < N; ++a) {
        const double dx = dN(0, a), dy = dN(1, a), dz = dN(2, a);
        const int c = 3 * a;
        B(0, c) = dx;
        B(1, c + 1) = dy;
        B(2, c + 2) = dz;
        B(3, c + 1) = dz, B(3, c + 2) = dy;  // gamma_yz
        B(4, c) = dz, B(4, c + 2) = dx;      // gamma_xz
        B(5, c) = dy, B(5, c + 1) = dx;      // gamma_xy
    }
    return B;
}

}  // namespace fabsynth::fem::detail
