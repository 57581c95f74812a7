// SPDX-License-Identifier: MIT
#pragma once
/// @file isoparametric_solid.hpp  The integration code shared by the isoparametric solid elements
/// (hex8, wedge6): stiffness, consistent body loads, strains, stresses and volume, all evaluated
/// with the element's own quadrature rule.
///
/// CRTP: `struct hex8 : isoparametric_solid<hex8, 8, 8>` (element, nodes, quadrature points) where the element provides
///   static constexpr const char* name;                          // for error messages
///   static Eigen::Matrix<double, N, 1> shape(const vec3& xi);
///   static Eigen::Matrix<double, 3, N> shape_derivatives(const vec3& xi);
///   static const std::array<quad_point, Q>& quadrature();      // exact for its stiffness
#include <Eigen/Core>

#include <array>

#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/detail/isoparametric.hpp"
#include "fabsynth/fem/material.hpp"

namespace fabsynth::fem::detail {

template <class Element, int N, std::size_t Q>
struct isoparametric_solid {
    using solid_nodes_t = std::array<vec3, N>;
    using solid_matrix_t = Eigen::Matrix<double, 3 * N, 3 * N>;
    using solid_vector_t = Eigen::Matrix<double, 3 * N, 1>;

    /// det of the Jacobian dx/dxi at xi (throws invalid_input if <= 0: inverted or degenerate).
    static double jacobian_det(const solid_nodes_t& X, const vec3& xi) {
        return map_derivatives<N>(X, Element::shape_derivatives(xi), Element::name).detJ;
    }
    /// 6 x 3N strain-displacement matrix B at natural coordinates xi: eps = B * ue (Voigt,
    /// engineering shear).
    static Eigen::Matrix<double, 6, 3 * N> strain_displacement(const solid_nodes_t& X, const vec3& xi) {
        return voigt_b<N>(map_derivatives<N>(X, Element::shape_derivatives(xi), Element::name).dN);
    }
    /// 3N x 3N stiffness matrix [N/mm].
    static solid_matrix_t stiffness(const solid_nodes_t& X, const isotropic_material& m) {
        m.validate();  // a NaN modulus must not turn into a silent NaN matrix
        const Eigen::Matrix<double, 6, 6> C = m.elasticity();
        solid_matrix_t K = solid_matrix_t::Zero();
        for (const auto& q : Element::quadrature()) {
            const auto p = map_derivatives<N>(X, Element::shape_derivatives(q.xi), Element::name);
            const Eigen::Matrix<double, 6, 3 * N> B = voigt_b<N>(p.dN);
            K.noalias() += B.transpose() * (C * B) * (p.detJ * q.weight);
        }
        return 0.5 * (K + K.transpose());  // exact symmetry for the sparse solvers
    }
    /// Consistent nodal loads [N] of a uniform force per volume [N/mm^3] (e.g. density * g).
    static solid_vector_t body_force(const solid_nodes_t& X, const vec3& force_per_volume) {
        solid_vector_t f = solid_vector_t::Zero();
        for (const auto& q : Element::quadrature()) {
            const double w = jacobian_det(X, q.xi) * q.weight;
            const Eigen::Matrix<double, N, 1> shp = Element::shape(q.xi);
            for (int a = 0; a < N; ++a)
                for (int i = 0; i < 3; ++i) f(3 * a + i) += shp(a) * force_per_volume[i] * w;
        }
        return f;
    }
    /// Same as body_force(X, b) (the material is not needed); form required by finite_element.
    static solid_vector_t body_force(const solid_nodes_t& X, const isotropic_material&, const vec3& force_per_volume) {
        return body_force(X, force_per_volume);
    }
    /// Cauchy stress [MPa] at natural coordinates xi for element displacements ue [mm].
    static voigt6 stress(const solid_nodes_t& X, const isotropic_material& m, const solid_vector_t& ue, const vec3& xi) {
        return m.elasticity() * (strain_displacement(X, xi) * ue);
    }
    /// The quadrature points, in the rule's order.
    static std::array<vec3, Q> stress_points() {
        std::array<vec3, Q> r{};
        for (std::size_t i = 0; i < r.size(); ++i) r[i] = Element::quadrature()[i].xi;
        return r;
    }
    /// Volume [mm^3] (the rule is exact for the Jacobian of the linear/trilinear map).
    static double volume(const solid_nodes_t& X, const isotropic_material& = {}) {
        double v = 0;
        for (const auto& q : Element::quadrature()) v += jacobian_det(X, q.xi) * q.weight;
        return v;
    }
};

}  // namespace fabsynth::fem::detail
