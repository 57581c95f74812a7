// SPDX-License-Identifier: MIT
#pragma once
/// @file wedge6.hpp  Linear 6-node prism (Abaqus C3D6), 3-point triangle x 2-point Gauss rule.
///
/// Node order (Abaqus C3D6), natural coordinates (r, s, zeta) with r, s >= 0, r + s <= 1:
///   0 (0,0,-1)  1 (1,0,-1)  2 (0,1,-1)     bottom triangle, counter-clockwise seen from the top
///   3 (0,0,+1)  4 (1,0,+1)  5 (0,1,+1)     top triangle, node 3+i above node i
/// Shape functions N_a = L_a (1 - zeta)/2 (bottom), L_a (1 + zeta)/2 (top) with L = (1-r-s, r, s).
///
/// VTK_WEDGE (13) orders the base triangle the other way round (its (0,1,2) normal points away
/// from (3,4,5)), so writing VTK uses vtk_order = {0,2,1,3,5,4}.
///
/// Quadrature: for a prism whose top is a translate of its bottom (constant Jacobian) the
/// integrand B^T C B is quadratic in (r,s) and in zeta, so the 3-point (degree 2) triangle rule
/// times 2-point Gauss is exact; for distorted prisms it is the usual 6-point rule.
#include <Eigen/Core>

#include <array>

#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/detail/isoparametric.hpp"
#include "fabsynth/fem/detail/isoparametric_solid.hpp"
#include "fabsynth/fem/detail/quadrature.hpp"
#include "fabsynth/fem/element.hpp"
#include "fabsynth/fem/material.hpp"

namespace fabsynth::fem {

struct wedge6 : detail::isoparametric_solid<wedge6, 6, 6> {
    static constexpr const char* name = "wedge6";
    /// 3-point triangle rule x 2-point Gauss (see the file comment for exactness).
    static const auto& quadrature() { return detail::wedge_3x2(); }
    static constexpr int num_nodes = 6, dofs_per_node = 3, vtk_type = 13;
    using nodes_t = std::array<vec3, 6>;
    using properties_t = isotropic_material;
    using matrix_t = Eigen::Matrix<double, 18, 18>;
    using vector_t = Eigen::Matrix<double, 18, 1>;
    static constexpr std::array<int, 6> vtk_order = {0, 2, 1, 3, 5, 4};

    static Eigen::Matrix<double, 6, 1> shape(const vec3& xi) {
        const double L[3] = {1 - xi.x - xi.y, xi.x, xi.y};
        Eigen::Matrix<double, 6, 1> N;
        for (int a = 0; a < 3; ++a) N(a) = L[a] * (1 - xi.z) / 2, N(a + 3) = L[a] * (1 + xi.z) / 2;
        return N;
    }
    static Eigen::Matrix<double, 3, 6> shape_derivatives(const vec3& xi) {
        const double L[3] = {1 - xi.x - xi.y, xi.x, xi.y};
        const double dLr[3] = {-1, 1, 0}, dLs[3] = {-1, 0, 1};
        Eigen::Matrix<double, 3, 6> d;
        for (int a = 0; a < 3; ++a) {
            const double lo = (1 - xi.z) / 2, hi = (1 + xi.z) / 2;
            d(0, a) = dLr[a] * lo, d(0, a + 3) = dLr[a] * hi;
            d(1, a) = dLs[a] * lo, d(1, a + 3) = dLs[a] * hi;
            d(2, a) = -L[a] / 2, d(2, a + 3) = L[a] / 2;
        }
        return d;
    }
    static constexpr vec3 centroid() { return vec3(1.0 / 3, 1.0 / 3, 0.0); }
};

static_assert(finite_element<wedge6>);

}  // namespace fabsynth::fem
