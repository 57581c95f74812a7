// SPDX-License-Identifier: MIT
#pragma once
/// @file boundary.hpp  Boundary conditions and loads: fixed DOFs, nodal forces, gravity (consistent
/// nodal loads from the element's body_force) and pressure on shells.
///
/// DOF numbers are 0-based: 0,1,2 = ux,uy,uz; 3,4,5 = rx,ry,rz (shell nodes only).
/// Nodes and elements are 0-based indices into the mesh.
///
/// Usage:
///   fabsynth::fem::load_case lc;
///   for (auto n : bottom) for (int k = 0; k < 3; ++k) lc.fixed.push_back({n, k});
///   lc.forces.push_back({tip, 2, -10.0});                          // 10 N downwards
///   lc.gravity.push_back({e, {0, 0, -9810.0}});                    // g in mm/s^2
#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/mesh.hpp"

namespace fabsynth::fem {

/// Prescribed displacement [mm] or rotation [rad] of one DOF.
struct fixed_dof {
    std::uint32_t node = 0;
    int dof = 0;
    double value = 0;
};
/// Concentrated force [N] or moment [N mm] on one DOF.
struct nodal_force {
    std::uint32_t node = 0;
    int dof = 0;
    double value = 0;
};
/// Gravity-like body load on one element: force per volume = density * acceleration [mm/s^2].
struct gravity_load {
    std::uint32_t element = 0;
    vec3 acceleration{0.0};
};
/// Uniform pressure [MPa] on a shell element, positive against its normal (a pressure from the
/// side the normal points to). Decks use the opposite sign: CalculiX's *DLOAD P on S3 pushes along
/// the normal (checked with ccx on a clamped plate: +P moves it along +n); inp.hpp and
/// inp_writer.hpp convert.
struct pressure_load {
    std::uint32_t element = 0;
    double pressure = 0;
};

struct load_case {
    std::vector<fixed_dof> fixed;
    std::vector<nodal_force> forces;
    std::vector<gravity_load> gravity;
    std::vector<pressure_load> pressures;
};

/// Throws invalid_input naming the first load or support that references a missing node,
/// element or DOF, or has a non-finite value.
inline void validate(const load_case& lc, const mesh& m, const dof_map& dofs) {
    auto check_dof = [&](const char* what, std::size_t i, std::uint32_t node, int dof, double v) {
        const std::string name = std::string(what) + " " + std::to_string(i);
        if (node >= m.nodes.size()) throw invalid_input(name + " references missing node index " + std::to_string(node));
        if (dof < 0 || dof >= dofs.count[node])
            throw invalid_input(name + ": node " + std::to_string(m.node_label(node)) + " has no dof " + std::to_string(dof + 1) +
                                " (it has " + std::to_string(dofs.count[node]) + " dofs)");
        if (!std::isfinite(v)) throw invalid_input(name + ": value is not finite");
    };
    for (std::size_t i = 0; i < lc.fixed.size(); ++i) check_dof("fixed dof", i, lc.fixed[i].node, lc.fixed[i].dof, lc.fixed[i].value);
    for (std::size_t i = 0; i < lc.forces.size(); ++i) check_dof("nodal force", i, lc.forces[i].node, lc.forces[i].dof, lc.forces[i].value);
    for (std::size_t i = 0; i < lc.gravity.size(); ++i) {
        if (lc.gravity[i].element >= m.elements.size()) throw invalid_input("gravity load " + std::to_string(i) + " references missing element");
        if (!all_finite(lc.gravity[i].acceleration)) throw invalid_input("gravity load " + std::to_string(i) + ": acceleration is not finite");
    }
    for (std::size_t i = 0; i < lc.pressures.size(); ++i) {
        const auto& p = lc.pressures[i];
        if (p.element >= m.elements.size()) throw invalid_input("pressure load " + std::to_string(i) + " references missing element");
        if (m.elements[p.element].kind != element_kind::shell3)
            throw invalid_input("pressure load " + std::to_string(i) + ": element " + std::to_string(m.element_label(p.element)) +
                                " is not a shell (pressure is supported on S3 only)");
        if (!std::isfinite(p.pressure)) throw invalid_input("pressure load " + std::to_string(i) + ": pressure is not finite");
    }
}

/// Global load vector [N, N mm] (length dofs.total) of the forces, gravity and pressures of lc.
/// Gravity uses the element's density and consistent nodal loads. Summation order is fixed.
[[nodiscard]] inline Eigen::VectorXd assemble_loads(const mesh& m, const dof_map& dofs, const load_case& lc) {
    validate(lc, m, dofs);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(dofs.total));
    for (const auto& F : lc.forces) f(static_cast<Eigen::Index>(dofs.index(F.node, F.dof))) += F.value;
    auto scatter = [&](const element& el, int n, int d, const auto& fe) {
        for (int a = 0; a < n; ++a)
            for (int i = 0; i < d; ++i) f(static_cast<Eigen::Index>(dofs.offset[el.nodes[a]] + static_cast<std::size_t>(i))) += fe(d * a + i);
    };
    for (const auto& G : lc.gravity) {
        const element& el = m.elements[G.element];
        const double rho = m.sections[el.section].material.density;
        visit_kind(el.kind, [&]<class E>(std::type_identity<E>) {
            const auto fe = E::body_force(m.element_nodes<E>(G.element), m.properties<E>(G.element), rho * G.acceleration);
            scatter(el, E::num_nodes, E::dofs_per_node, fe);
        });
    }
    for (const auto& P : lc.pressures) {
        const element& el = m.elements[P.element];
        scatter(el, 3, 6, shell3::pressure_load(m.element_nodes<shell3>(P.element), P.pressure));
    }
    return f;
}

}  // namespace fabsynth::fem
