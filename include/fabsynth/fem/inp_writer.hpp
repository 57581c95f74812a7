// SPDX-License-Identifier: MIT
#pragma once
/// @file inp_writer.hpp  Writes a mesh and load case as an Abaqus / CalculiX .inp deck (the subset
/// inp.hpp reads), so a fabsynth model can be checked by an independent solver (CalculiX `ccx`).
///
/// Numbering: the mesh's node_ids / element_ids when present, else index + 1 (decks are 1-based).
/// Each distinct (section, stiffness scale) pair becomes one material and one section, since a deck
/// has no per-element stiffness scale: E is written as scale * E. Gravity loads are grouped by
/// acceleration into element sets. Numbers are written in shortest round-trip form, so
/// parse_inp(write_inp(m, lc)) reproduces the model exactly.
///
/// Usage:
///   std::string deck = fabsynth::fem::write_inp(mesh, loads, {.heading = "cantilever", .print_displacements = true});
#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/fem/boundary.hpp"
#include "fabsynth/fem/mesh.hpp"

namespace fabsynth::fem {

struct inp_write_options {
    std::string heading = "fabsynth model";
    bool print_displacements = false;  ///< add *NODE PRINT, NSET=NALL / U (CalculiX writes them to the .dat file)
};

namespace detail {
inline void put_number(std::string& s, double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
}
}  // namespace detail

/// Deck text for mesh m under load case lc. Throws invalid_input if the mesh or loads are invalid,
/// or if labels are not positive (a deck cannot name node 0 or a negative id).
[[nodiscard]] inline std::string write_inp(const mesh& m, const load_case& lc, const inp_write_options& opt = {}) {
    m.validate();
    const dof_map dofs(m);
    validate(lc, m, dofs);
    const auto node_id = [&](std::size_t i) { return m.node_ids.empty() ? static_cast<std::int64_t>(i) + 1 : m.node_ids[i]; };
    const auto element_id = [&](std::size_t e) { return m.element_ids.empty() ? static_cast<std::int64_t>(e) + 1 : m.element_ids[e]; };
    for (std::size_t i = 0; i < m.nodes.size(); ++i)
        if (node_id(i) <= 0) throw invalid_input("write_inp: node label " + std::to_string(node_id(i)) + " is not positive");
    for (std::size_t e = 0; e < m.elements.size(); ++e)
        if (element_id(e) <= 0) throw invalid_input("write_inp: element label " + std::to_string(element_id(e)) + " is not positive");

    std::string s = "*HEADING\n" + opt.heading + "\n*NODE, NSET=NALL\n";
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
        s += std::to_string(node_id(i));
        for (int k = 0; k < 3; ++k) s += ", ", detail::put_number(s, m.nodes[i][k]);
        s += '\n';
    }
    // One element block per (kind, section, scale) group, in order of first appearance.
    using group_key = std::tuple<element_kind, std::uint32_t, double>;
    std::map<group_key, std::size_t> group_of;
    std::vector<group_key> groups;
    std::vector<std::vector<std::size_t>> members;
    for (std::size_t e = 0; e < m.elements.size(); ++e) {
        const element& el = m.elements[e];
        const group_key key{el.kind, el.section, el.stiffness_scale};
        auto [it, added] = group_of.emplace(key, groups.size());
        if (added) groups.push_back(key), members.emplace_back();
        members[it->second].push_back(e);
    }
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto [kind, sec, scale] = groups[g];
        s += "*ELEMENT, TYPE=" + std::string(kind_name(kind)) + ", ELSET=G" + std::to_string(g + 1) + "\n";
        for (std::size_t e : members[g]) {
            s += std::to_string(element_id(e));
            for (int a = 0; a < num_nodes(kind); ++a) s += ", " + std::to_string(node_id(m.elements[e].nodes[a]));
            s += '\n';
        }
    }
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto [kind, sec, scale] = groups[g];
        const section& sc = m.sections[sec];
        const std::string name = "M" + std::to_string(g + 1);
        s += "*MATERIAL, NAME=" + name + "\n*ELASTIC\n";
        detail::put_number(s, scale * sc.material.E), s += ", ", detail::put_number(s, sc.material.nu), s += '\n';
        if (sc.material.density > 0) s += "*DENSITY\n", detail::put_number(s, sc.material.density), s += '\n';
        if (kind == element_kind::shell3) {
            s += "*SHELL SECTION, ELSET=G" + std::to_string(g + 1) + ", MATERIAL=" + name + "\n";
            detail::put_number(s, sc.thickness), s += '\n';
        } else {
            s += "*SOLID SECTION, ELSET=G" + std::to_string(g + 1) + ", MATERIAL=" + name + "\n";
        }
    }
    // Gravity: one element set per distinct acceleration vector.
    std::map<std::tuple<double, double, double>, std::vector<std::size_t>> gravity_sets;
    for (const gravity_load& G : lc.gravity)
        if (G.acceleration != vec3(0.0)) gravity_sets[{G.acceleration.x, G.acceleration.y, G.acceleration.z}].push_back(G.element);
    std::size_t gs = 0;
    for (const auto& [acc, elems] : gravity_sets) {
        s += "*ELSET, ELSET=GRAV" + std::to_string(++gs) + "\n";
        for (std::size_t i = 0; i < elems.size(); ++i) s += std::to_string(element_id(elems[i])) + (i % 16 == 15 || i + 1 == elems.size() ? "\n" : ", ");
    }
    s += "*STEP\n*STATIC\n";
    if (!lc.fixed.empty()) {
        s += "*BOUNDARY\n";
        for (const fixed_dof& f : lc.fixed) {
            s += std::to_string(node_id(f.node)) + ", " + std::to_string(f.dof + 1) + ", " + std::to_string(f.dof + 1) + ", ";
            detail::put_number(s, f.value), s += '\n';
        }
    }
    if (!lc.forces.empty()) {
        s += "*CLOAD\n";
        for (const nodal_force& F : lc.forces)
            s += std::to_string(node_id(F.node)) + ", " + std::to_string(F.dof + 1) + ", ", detail::put_number(s, F.value), s += '\n';
    }
    if (!lc.gravity.empty() || !lc.pressures.empty()) {
        s += "*DLOAD\n";
        gs = 0;
        for (const auto& [acc, elems] : gravity_sets) {
            const auto [x, y, z] = acc;
            const double g = std::sqrt(x * x + y * y + z * z);
            s += "GRAV" + std::to_string(++gs) + ", GRAV, ";
            detail::put_number(s, g);
            for (double c : {x, y, z}) s += ", ", detail::put_number(s, g > 0 ? c / g : 0.0);
            s += '\n';
        }
        for (const pressure_load& P : lc.pressures) s += std::to_string(element_id(P.element)) + ", P, ", detail::put_number(s, -P.pressure), s += '\n';  // deck sign: CalculiX's +P pushes along the normal
    }
    if (opt.print_displacements) s += "*NODE PRINT, NSET=NALL\nU\n";
    s += "*END STEP\n";
    return s;
}

}  // namespace fabsynth::fem
