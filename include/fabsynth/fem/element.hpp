// SPDX-License-Identifier: MIT
#pragma once
/// @file element.hpp  The finite-element policy concept shared by hex8, wedge6 and shell3.
///
/// An element type E is a stateless policy with static members only:
///   E::num_nodes, E::dofs_per_node, E::vtk_type     (static constexpr int)
///   E::nodes_t = std::array<vec3, num_nodes>          node positions [mm]
///   E::properties_t                                   what the element needs besides geometry
///                                                     (isotropic_material for solids, shell_section for shells)
///   E::vtk_order                                      std::array<int, num_nodes>: VTK node i = our node vtk_order[i]
///   E::stiffness(X, p)        -> Matrix<nd, nd>       nd = num_nodes * dofs_per_node, global axes
///   E::body_force(X, p, b)    -> Matrix<nd, 1>        consistent nodal loads of a force per volume b [N/mm^3]
///   E::stress(X, p, ue, xi)   -> voigt6               Cauchy stress [MPa] at natural point xi, global axes
///   E::centroid()             -> vec3                 natural coordinates of the centroid
///   E::stress_points()        -> std::array<vec3, K>  natural coordinates of the Gauss points
///   E::volume(X, p)           -> double               [mm^3]
/// Element DOFs are node-major: (node 0 dofs..., node 1 dofs...); solids have (ux,uy,uz), shells
/// (ux,uy,uz,rx,ry,rz). Cost: stiffness is O(quadrature points * nd^2).
#include <Eigen/Core>

#include <array>
#include <concepts>
#include <cstddef>

#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/material.hpp"

namespace fabsynth::fem {

/// Number of element DOFs of E.
template <class E>
inline constexpr int element_dofs = E::num_nodes * E::dofs_per_node;

/// A finite-element policy (see the file comment for what each member must do).
template <class E>
concept finite_element =
    requires {
        typename E::nodes_t;
        typename E::properties_t;
        { E::num_nodes } -> std::convertible_to<int>;
        { E::dofs_per_node } -> std::convertible_to<int>;
        { E::vtk_type } -> std::convertible_to<int>;
        { E::vtk_order } -> std::convertible_to<std::array<int, static_cast<std::size_t>(E::num_nodes)>>;
    } && std::same_as<typename E::nodes_t, std::array<vec3, static_cast<std::size_t>(E::num_nodes)>> &&
    requires(const typename E::nodes_t& X, const typename E::properties_t& p, const vec3& v,
             const Eigen::Matrix<double, element_dofs<E>, 1>& ue) {
        { E::stiffness(X, p) } -> std::convertible_to<Eigen::Matrix<double, element_dofs<E>, element_dofs<E>>>;
        { E::body_force(X, p, v) } -> std::convertible_to<Eigen::Matrix<double, element_dofs<E>, 1>>;
        { E::stress(X, p, ue, v) } -> std::convertible_to<voigt6>;
        { E::centroid() } -> std::convertible_to<vec3>;
        E::stress_points();
        { E::volume(X, p) } -> std::convertible_to<double>;
    };

}  // namespace fabsynth::fem
