// SPDX-License-Identifier: MIT
#pragma once
/// @file hex8.hpp  Trilinear 8-node hexahedron (Abaqus C3D8, VTK_HEXAHEDRON), full 2x2x2 Gauss.
///
/// Node order (same in Abaqus C3D8 and VTK_HEXAHEDRON), natural coordinates (xi, eta, zeta):
///   0 (-1,-1,-1)  1 (+1,-1,-1)  2 (+1,+1,-1)  3 (-1,+1,-1)     bottom face zeta = -1
///   4 (-1,-1,+1)  5 (+1,-1,+1)  6 (+1,+1,+1)  7 (-1,+1,+1)     top face zeta = +1
/// i.e. nodes 0-3 run counter-clockwise when seen from the top face (from +zeta), and node 4+i
/// sits above node i. A positively oriented element has det J > 0 everywhere; an inverted or
/// degenerate one makes every function here throw invalid_input.
///
/// Element DOFs: (ux, uy, uz) per node, node-major: dof 3a+i = component i of node a.
/// Voigt order (xx, yy, zz, yz, xz, xy) with engineering shear strains (material.hpp).
///
/// Full integration locks in bending for coarse meshes (parasitic shear); it converges as O(h^2).
///
/// Usage:
///   fabsynth::fem::hex8::nodes_t X = {...};
///   auto K = fabsynth::fem::hex8::stiffness(X, fabsynth::fem::isotropic_material::pla());
#include <Eigen/Core>

#include <array>

#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/detail/isoparametric.hpp"
#include "fabsynth/fem/detail/isoparametric_solid.hpp"
#include "fabsynth/fem/detail/quadrature.hpp"
#include "fabsynth/fem/element.hpp"
#include "fabsynth/fem/material.hpp"

namespace fabsynth::fem {

struct hex8 : detail::isoparametric_solid<hex8, 8, 8> {
    static constexpr const char* name = "hex8";
    /// Full 2x2x2 Gauss (order: xi fastest, then eta, then zeta; each -1/sqrt3 before +1/sqrt3).
    static const auto& quadrature() { return detail::gauss_2x2x2(); }
    static constexpr int num_nodes = 8, dofs_per_node = 3, vtk_type = 12;
    using nodes_t = std::array<vec3, 8>;
    using properties_t = isotropic_material;
    using matrix_t = Eigen::Matrix<double, 24, 24>;
    using vector_t = Eigen::Matrix<double, 24, 1>;
    /// VTK node i is our node vtk_order[i] (identical orders).
    static constexpr std::array<int, 8> vtk_order = {0, 1, 2, 3, 4, 5, 6, 7};
    /// Natural coordinates of node a.
    static constexpr std::array<std::array<double, 3>, 8> corners = {
        {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}};

    /// Shape functions N_a(xi) = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a) / 8.
    static Eigen::Matrix<double, 8, 1> shape(const vec3& xi) {
        Eigen::Matrix<double, 8, 1> N;
        for (int a = 0; a < 8; ++a)
            N(a) = 0.125 * (1 + xi.x * corners[a][0]) * (1 + xi.y * corners[a][1]) * (1 + xi.z * corners[a][2]);
        return N;
    }
    /// Natural derivatives: row i = dN/dxi_i.
    static Eigen::Matrix<double, 3, 8> shape_derivatives(const vec3& xi) {
        Eigen::Matrix<double, 3, 8> d;
        for (int a = 0; a < 8; ++a) {
            const double x = 1 + xi.x * corners[a][0], y = 1 + xi.y * corners[a][1], z = 1 + xi.z * corners[a][2];
            d(0, a) = 0.125 * corners[a][0] * y * z;
            d(1, a) = 0.125 * corners[a][1] * x * z;
            d(2, a) = 0.125 * corners[a][2] * x * y;
        }
        return d;
    }
    /// Natural coordinates of the centroid.
    static constexpr vec3 centroid() { return vec3(0.0); }
};

static_assert(finite_element<hex8>);

}  // namespace fabsynth::fem
