// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh.hpp  A finite-element model: nodes, mixed hex8 / wedge6 / shell3 elements, sections,
/// and the DOF numbering derived from them.
///
/// Usage:
///   fabsynth::fem::mesh m;
///   m.nodes = {...};                                           // [mm]
///   m.sections.push_back({fabsynth::fem::isotropic_material::pla()});
///   m.elements.push_back(fabsynth::fem::make_element<fabsynth::fem::hex8>({0,1,2,3,4,5,6,7}));
///   auto dofs = fabsynth::fem::dof_map(m);                     // 3 DOFs per solid node, 6 per shell node
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/element.hpp"
#include "fabsynth/fem/hex8.hpp"
#include "fabsynth/fem/material.hpp"
#include "fabsynth/fem/shell3.hpp"
#include "fabsynth/fem/wedge6.hpp"

namespace fabsynth::fem {

/// The element types a mesh can hold.
enum class element_kind : std::uint8_t { hex8, wedge6, shell3 };

/// Material and (for shells) thickness [mm] shared by a set of elements.
struct section {
    isotropic_material material;
    double thickness = 0;  ///< used by shell elements only
};

/// One element: kind, node indices (first num_nodes entries used), section index, and the
/// stiffness scale rho (K_e = rho K_e, e.g. rho_min for "empty" elements as in
/// structurally-sound-patterns.md sec. 5.2.1; 1 = solid).
struct element {
    element_kind kind = element_kind::hex8;
    std::array<std::uint32_t, 8> nodes{};
    std::uint32_t section = 0;
    double stiffness_scale = 1.0;
};

/// Calls f(std::type_identity<E>{}) with E the element type of kind k; returns its result.
template <class F>
decltype(auto) visit_kind(element_kind k, F&& f) {
    switch (k) {
        case element_kind::wedge6: return f(std::type_identity<wedge6>{});
        case element_kind::shell3: return f(std::type_identity<shell3>{});
        default: return f(std::type_identity<hex8>{});
    }
}

/// Number of nodes of an element kind.
[[nodiscard]] inline int num_nodes(element_kind k) {
    return visit_kind(k, []<class E>(std::type_identity<E>) { return E::num_nodes; });
}
/// Abaqus-style name of an element kind ("C3D8", "C3D6", "S3").
[[nodiscard]] inline const char* kind_name(element_kind k) {
    switch (k) {
        case element_kind::wedge6: return "C3D6";
        case element_kind::shell3: return "S3";
        default: return "C3D8";
    }
}

/// Element of type E from its node indices.
template <finite_element E>
[[nodiscard]] element make_element(const std::array<std::uint32_t, E::num_nodes>& nodes, std::uint32_t section = 0,
                                   double stiffness_scale = 1.0) {
    element e;
    if constexpr (std::is_same_v<E, wedge6>) e.kind = element_kind::wedge6;
    else if constexpr (std::is_same_v<E, shell3>) e.kind = element_kind::shell3;
    else e.kind = element_kind::hex8;
    std::copy(nodes.begin(), nodes.end(), e.nodes.begin());
    e.section = section;
    e.stiffness_scale = stiffness_scale;
    return e;
}

/// Nodes, elements and sections. node_ids / element_ids are optional user labels (e.g. the
/// numbers of an .inp deck) used in error messages and output; empty = 0-based indices.
struct mesh {
    std::vector<vec3> nodes;
    std::vector<element> elements;
    std::vector<section> sections;
    std::vector<std::int64_t> node_ids;
    std::vector<std::int64_t> element_ids;

    [[nodiscard]] std::int64_t node_label(std::size_t i) const {
        return i < node_ids.size() ? node_ids[i] : static_cast<std::int64_t>(i);
    }
    [[nodiscard]] std::int64_t element_label(std::size_t e) const {
        return e < element_ids.size() ? element_ids[e] : static_cast<std::int64_t>(e);
    }
    /// Node positions of element e as E::nodes_t (E must match elements[e].kind).
    template <finite_element E>
    [[nodiscard]] typename E::nodes_t element_nodes(std::size_t e) const {
        typename E::nodes_t X{};
        for (int a = 0; a < E::num_nodes; ++a) X[a] = nodes[elements[e].nodes[a]];
        return X;
    }
    /// The properties E needs for element e (material, or shell_section for shells).
    template <finite_element E>
    [[nodiscard]] typename E::properties_t properties(std::size_t e) const {
        const section& s = sections[elements[e].section];
        if constexpr (std::is_same_v<typename E::properties_t, shell_section>) return shell_section{s.material, s.thickness};
        else return s.material;
    }

    /// Throws invalid_input naming the first bad item: non-finite node, element referencing a
    /// missing node/section or repeating a node, bad material or shell thickness, stiffness scale
    /// not finite and > 0, label vectors of the wrong size.
    void validate() const {
        for (std::size_t i = 0; i < nodes.size(); ++i)
            if (!all_finite(nodes[i])) throw invalid_input("fem mesh: node " + std::to_string(node_label(i)) + " is not finite");
        if (!node_ids.empty() && node_ids.size() != nodes.size())
            throw invalid_input("fem mesh: node_ids has " + std::to_string(node_ids.size()) + " entries for " +
                                std::to_string(nodes.size()) + " nodes");
        if (!element_ids.empty() && element_ids.size() != elements.size())
            throw invalid_input("fem mesh: element_ids has " + std::to_string(element_ids.size()) + " entries for " +
                                std::to_string(elements.size()) + " elements");
        for (std::size_t s = 0; s < sections.size(); ++s) sections[s].material.validate();
        for (std::size_t e = 0; e < elements.size(); ++e) {
            const element& el = elements[e];
            const std::string name = "fem mesh: element " + std::to_string(element_label(e)) + " (" + kind_name(el.kind) + ")";
            if (el.section >= sections.size()) throw invalid_input(name + " references missing section " + std::to_string(el.section));
            if (!(std::isfinite(el.stiffness_scale) && el.stiffness_scale > 0))
                throw invalid_input(name + ": stiffness scale must be finite and > 0, got " + std::to_string(el.stiffness_scale));
            if (el.kind == element_kind::shell3 && !(std::isfinite(sections[el.section].thickness) && sections[el.section].thickness > 0))
                throw invalid_input(name + ": shell thickness must be finite and > 0");
            const int n = num_nodes(el.kind);
            for (int a = 0; a < n; ++a) {
                if (el.nodes[a] >= nodes.size())
                    throw invalid_input(name + " references missing node index " + std::to_string(el.nodes[a]));
                for (int b = 0; b < a; ++b)
                    if (el.nodes[a] == el.nodes[b])
                        throw invalid_input(name + " uses node " + std::to_string(node_label(el.nodes[a])) + " twice");
            }
        }
    }
};

/// Global DOF numbering: node i owns dofs [offset[i], offset[i] + count[i]) in the order
/// (ux, uy, uz[, rx, ry, rz]). A node's count is the max dofs_per_node of its elements (0 for
/// nodes no element uses), so solid-only nodes have 3 and shell nodes 6.
struct dof_map {
    std::vector<std::uint8_t> count;
    std::vector<std::size_t> offset;
    std::size_t total = 0;

    dof_map() = default;
    explicit dof_map(const mesh& m) : count(m.nodes.size(), 0), offset(m.nodes.size() + 1, 0) {
        for (const element& e : m.elements) {
            const auto [n, d] = visit_kind(e.kind, []<class E>(std::type_identity<E>) {
                return std::pair<int, int>(E::num_nodes, E::dofs_per_node);
            });
            for (int a = 0; a < n; ++a)
                if (e.nodes[a] < count.size())
                    count[e.nodes[a]] = std::max<std::uint8_t>(count[e.nodes[a]], static_cast<std::uint8_t>(d));
        }
        for (std::size_t i = 0; i < count.size(); ++i) offset[i + 1] = offset[i] + count[i];
        total = offset.back();
    }
    /// Global index of dof k (0..5) of node i; throws invalid_input if the node has no such dof.
    [[nodiscard]] std::size_t index(std::size_t node, int k) const {
        if (node >= count.size() || k < 0 || k >= count[node])
            throw invalid_input("dof " + std::to_string(k + 1) + " of node index " + std::to_string(node) +
                                " does not exist (node has " +
                                std::to_string(node < count.size() ? count[node] : 0) + " dofs)");
        return offset[node] + static_cast<std::size_t>(k);
    }
};

/// Structured hex8 box [origin, origin + size] with n = (nx, ny, nz) elements, one section.
/// Node (i, j, k) has index i + (nx+1) (j + (ny+1) k); element (i, j, k) index i + nx (j + ny k).
[[nodiscard]] inline mesh make_box_mesh(const vec3& origin, const vec3& size, const ivec3& n, const section& sec) {
    if (n.x < 1 || n.y < 1 || n.z < 1 || n.x > 4096 || n.y > 4096 || n.z > 4096 ||
        static_cast<double>(n.x) * n.y * n.z > 5e7)
        throw invalid_input("make_box_mesh: element counts must be in [1, 4096] with at most 5e7 elements");
    if (!all_finite(origin) || !all_finite(size) || !(size.x > 0 && size.y > 0 && size.z > 0))
        throw invalid_input("make_box_mesh: origin and size must be finite, size > 0");
    mesh m;
    m.sections.push_back(sec);
    const auto id = [&](int i, int j, int k) { return static_cast<std::uint32_t>(i + (n.x + 1) * (j + (n.y + 1) * k)); };
    for (int k = 0; k <= n.z; ++k)
        for (int j = 0; j <= n.y; ++j)
            for (int i = 0; i <= n.x; ++i) m.nodes.push_back(origin + size * vec3(i, j, k) / vec3(n));
    for (int k = 0; k < n.z; ++k)
        for (int j = 0; j < n.y; ++j)
            for (int i = 0; i < n.x; ++i)
                m.elements.push_back(make_element<hex8>({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                                                         id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1),
                                                         id(i, j + 1, k + 1)}));
    return m;
}

/// Flat shell3 rectangle [0, a] x [0, b] in the plane z = 0, nx x ny quads each split into two
/// triangles along the diagonal (i,j)-(i+1,j+1); normals +z. Node (i, j) has index i + (nx+1) j.
[[nodiscard]] inline mesh make_rect_shell_mesh(double a, double b, int nx, int ny, const section& sec) {
    if (nx < 1 || ny < 1 || nx > 8192 || ny > 8192) throw invalid_input("make_rect_shell_mesh: nx, ny must be in [1, 8192]");
    if (!(std::isfinite(a) && std::isfinite(b) && a > 0 && b > 0)) throw invalid_input("make_rect_shell_mesh: a, b must be finite and > 0");
    mesh m;
    m.sections.push_back(sec);
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) m.nodes.emplace_back(a * i / nx, b * j / ny, 0.0);
    const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(i + (nx + 1) * j); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            m.elements.push_back(make_element<shell3>({id(i, j), id(i + 1, j), id(i + 1, j + 1)}));
            m.elements.push_back(make_element<shell3>({id(i, j), id(i + 1, j + 1), id(i, j + 1)}));
        }
    return m;
}

}  // namespace fabsynth::fem
