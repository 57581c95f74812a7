// SPDX-License-Identifier: MIT
#pragma once
/// @file stress.hpp  Stress recovery: element stresses at the centroid and Gauss points, principal
/// stresses, von Mises, and the |s1| + |s2| + |s3| edge score of structurally-sound-patterns.md
/// (sec. 5.2.1: "We use the sum of the norm of the principal stresses as the score").
///
/// Voigt order (xx, yy, zz, yz, xz, xy), MPa. With stress_options::apply_stiffness_scale (default)
/// an element with stiffness scale rho reports rho * C * eps, i.e. the stress it really carries;
/// set it false to get C * eps, the stress the element would carry if it were solid.
///
/// Usage:
///   auto r = fabsynth::fem::solve_linear_static(m, loads);
///   std::vector<fabsynth::fem::voigt6> s = fabsynth::fem::centroid_stresses(m, r);
///   double vm = fabsynth::fem::von_mises(s[0]);
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/fem/mesh.hpp"
#include "fabsynth/fem/solvers.hpp"

namespace fabsynth::fem {

struct stress_options {
    bool apply_stiffness_scale = true;
};

/// Symmetric 3x3 tensor of a Voigt stress vector.
[[nodiscard]] inline Eigen::Matrix3d to_tensor(const voigt6& s) {
    Eigen::Matrix3d T;
    T << s(0), s(5), s(4), s(5), s(1), s(3), s(4), s(3), s(2);
    return T;
}
/// Principal stresses s1 >= s2 >= s3 [MPa].
[[nodiscard]] inline std::array<double, 3> principal_stresses(const voigt6& s) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(to_tensor(s), Eigen::EigenvaluesOnly);
    const Eigen::Vector3d ev = es.eigenvalues();  // ascending
    return {ev(2), ev(1), ev(0)};
}
/// von Mises equivalent stress sqrt(3 J2) [MPa].
[[nodiscard]] inline double von_mises(const voigt6& s) {
    const double a = s(0) - s(1), b = s(1) - s(2), c = s(2) - s(0);
    return std::sqrt(0.5 * (a * a + b * b + c * c) + 3.0 * (s(3) * s(3) + s(4) * s(4) + s(5) * s(5)));
}
/// |s1| + |s2| + |s3|, the edge score of structurally-sound-patterns.md sec. 5.2.1 [MPa].
[[nodiscard]] inline double principal_stress_score(const voigt6& s) {
    const auto p = principal_stresses(s);
    return std::abs(p[0]) + std::abs(p[1]) + std::abs(p[2]);
}

/// Stress of element e at natural coordinates xi (see the element's stress() for xi's meaning).
[[nodiscard]] inline voigt6 element_stress(const mesh& m, const static_result& r, std::size_t e, const vec3& xi,
                                           const stress_options& opt = {}) {
    return visit_kind(m.elements[e].kind, [&]<class E>(std::type_identity<E>) -> voigt6 {
        const voigt6 s = E::stress(m.element_nodes<E>(e), m.properties<E>(e), r.element_dofs_of<E>(m, e), xi);
        return opt.apply_stiffness_scale ? voigt6(m.elements[e].stiffness_scale * s) : s;
    });
}

/// Stress of every element at its centroid (shells: centroid of the top face). Parallel.
[[nodiscard]] inline std::vector<voigt6> centroid_stresses(const mesh& m, const static_result& r, const stress_options& opt = {}) {
    std::vector<voigt6> out(m.elements.size());
    parallel_for(0, m.elements.size(), [&](std::size_t e) {
        out[e] = visit_kind(m.elements[e].kind, [&]<class E>(std::type_identity<E>) { return element_stress(m, r, e, E::centroid(), opt); });
    }, {.grain = 64});
    return out;
}

/// Stresses of every element at its stress_points() (8 for hex8, 6 for wedge6 and shell3), in
/// that order. Parallel.
[[nodiscard]] inline std::vector<std::vector<voigt6>> gauss_point_stresses(const mesh& m, const static_result& r,
                                                                           const stress_options& opt = {}) {
    std::vector<std::vector<voigt6>> out(m.elements.size());
    parallel_for(0, m.elements.size(), [&](std::size_t e) {
        visit_kind(m.elements[e].kind, [&]<class E>(std::type_identity<E>) {
            for (const vec3& xi : E::stress_points()) out[e].push_back(element_stress(m, r, e, xi, opt));
        });
    }, {.grain = 64});
    return out;
}

/// Natural coordinates of node a of element type E (shells: on the mid-surface, zeta = 0).
template <finite_element E>
[[nodiscard]] vec3 node_natural_coordinates(int a) {
    if constexpr (std::is_same_v<E, hex8>) {
        return vec3(hex8::corners[a][0], hex8::corners[a][1], hex8::corners[a][2]);
    } else {
        constexpr double r[3] = {0, 1, 0}, s[3] = {0, 0, 1};
        if constexpr (std::is_same_v<E, wedge6>) return vec3(r[a % 3], s[a % 3], a < 3 ? -1.0 : 1.0);
        else return vec3(r[a], s[a], 0.0);
    }
}

/// von Mises stress [MPa] at every node: the mean over its elements of the element's stress
/// evaluated at that node (a shell at its more stressed face, zeta = +-1, where bending peaks).
/// This is the nodal stress whose large values filigree-synthesis.md sec. 5 calls weak nodes.
/// Nodes of no element get 0. Parallel over elements, summed in element order (deterministic).
[[nodiscard]] inline std::vector<double> nodal_von_mises(const mesh& m, const static_result& r, const stress_options& opt = {}) {
    std::vector<std::array<double, 8>> per_element(m.elements.size());
    parallel_for(0, m.elements.size(), [&](std::size_t e) {
        visit_kind(m.elements[e].kind, [&]<class E>(std::type_identity<E>) {
            for (int a = 0; a < E::num_nodes; ++a) {
                const vec3 xi = node_natural_coordinates<E>(a);
                if constexpr (std::is_same_v<E, shell3>)
                    per_element[e][a] = std::max(von_mises(element_stress(m, r, e, vec3(xi.x, xi.y, 1.0), opt)),
                                                 von_mises(element_stress(m, r, e, vec3(xi.x, xi.y, -1.0), opt)));
                else
                    per_element[e][a] = von_mises(element_stress(m, r, e, xi, opt));
            }
        });
    }, {.grain = 64});
    std::vector<double> sum(m.nodes.size(), 0.0);
    std::vector<int> count(m.nodes.size(), 0);
    for (std::size_t e = 0; e < m.elements.size(); ++e)
        for (int a = 0; a < num_nodes(m.elements[e].kind); ++a) sum[m.elements[e].nodes[a]] += per_element[e][a], ++count[m.elements[e].nodes[a]];
    for (std::size_t i = 0; i < sum.size(); ++i)
        if (count[i]) sum[i] /= count[i];
    return sum;
}

}  // namespace fabsynth::fem
