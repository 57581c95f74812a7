// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh_topology.hpp  Combinatorial topology of triangle meshes: edge manifoldness, boundary
/// edges and loops, orientation consistency, watertightness, connected components, Euler
/// characteristic and genus.
///
/// Usage:
///   auto t = fabsynth::analyze_topology(mesh);
///   if (t.is_watertight()) std::cout << "genus " << t.genus << "\n";
///   auto comp = fabsynth::face_components(mesh);   // component id per face
///
/// Definitions (vertices not referenced by any face are ignored):
/// - an edge is an unordered vertex pair used by some face; boundary if used by exactly 1 face,
///   non-manifold if used by 3 or more;
/// - an interior edge is consistently oriented if its two faces traverse it in opposite directions;
/// - watertight = no boundary and no non-manifold edges, every edge consistently oriented, and no
///   degenerate face (repeated vertex index);
/// - components: faces connected through shared vertices;
/// - Euler characteristic chi = V - E + F; for an orientable edge-manifold mesh,
///   genus = (2 * components - chi - boundary loops) / 2.
/// Time O(F log F), memory O(F).
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth {

/// Summary of a mesh's topology.
struct mesh_topology_info {
    std::size_t vertices = 0;           ///< referenced vertices
    std::size_t edges = 0;              ///< distinct undirected edges
    std::size_t faces = 0;
    std::size_t boundary_edges = 0;     ///< edges with one face
    std::size_t nonmanifold_edges = 0;  ///< edges with three or more faces
    std::size_t inconsistent_edges = 0; ///< two-face edges traversed twice in the same direction
    std::size_t degenerate_faces = 0;   ///< faces repeating a vertex index
    std::size_t boundary_loops = 0;     ///< closed chains of boundary edges (edge-manifold meshes)
    std::size_t components = 0;         ///< face components (shared vertices)
    long long euler = 0;                ///< V - E + F
    long long genus = 0;                ///< (2C - chi - loops) / 2; meaningful for orientable edge-manifold meshes

    [[nodiscard]] bool is_edge_manifold() const noexcept { return nonmanifold_edges == 0; }
    [[nodiscard]] bool is_closed() const noexcept { return boundary_edges == 0; }
    [[nodiscard]] bool is_oriented() const noexcept { return inconsistent_edges == 0; }
    [[nodiscard]] bool is_watertight() const noexcept {
        return faces > 0 && boundary_edges == 0 && nonmanifold_edges == 0 && inconsistent_edges == 0 && degenerate_faces == 0;
    }
};

namespace detail {
/// Directed half-edges (from, to) of all non-degenerate faces sorted by undirected key.
struct half_edge {
    std::uint64_t key;  // (min << 32) | max
    std::uint32_t from, to;
    bool operator<(const half_edge& o) const noexcept { return key != o.key ? key < o.key : from < o.from; }
};
}  // namespace detail

/// Component id per face (faces sharing a vertex are connected), numbered 0, 1, ... in order of
/// each component's first face. Throws invalid_input for faces indexing missing vertices.
[[nodiscard]] inline std::vector<std::uint32_t> face_components(const triangle_mesh& m, std::size_t* count = nullptr) {
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (auto v : m.faces[f])
            if (v >= m.vertices.size())
                throw invalid_input("mesh topology: face " + std::to_string(f) + " indexes missing vertex " + std::to_string(v));
    union_find uf(m.vertices.size());
    for (const auto& t : m.faces) uf.unite(t[0], t[1]), uf.unite(t[1], t[2]);
    std::vector<std::uint32_t> label(m.vertices.size(), UINT32_MAX), out(m.faces.size());
    std::uint32_t n = 0;
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        const std::uint32_t r = uf.find(m.faces[f][0]);
        if (label[r] == UINT32_MAX) label[r] = n++;
        out[f] = label[r];
    }
    if (count) *count = n;
    return out;
}

/// A closed, outward-oriented mesh without its cavity shells: the components (face_components)
/// whose signed volume is negative bound voids enclosed in the solid, which a printed part could
/// not drain; the solid is then filled. `removed`: the number of shells dropped. Meant for closed
/// meshes (e.g. a level set's); an open component's signed volume has no such meaning.
[[nodiscard]] inline triangle_mesh without_cavities(const triangle_mesh& m, std::size_t* removed = nullptr) {
    std::size_t count = 0;
    const std::vector<std::uint32_t> comp = face_components(m, &count);
    std::vector<double> volume(count, 0.0);
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        const auto& t = m.faces[f];
        volume[comp[f]] += glm::dot(m.vertices[t[0]], glm::cross(m.vertices[t[1]], m.vertices[t[2]])) / 6.0;
    }
    std::vector<std::uint8_t> keep(m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) keep[f] = volume[comp[f]] >= 0.0;
    if (removed) *removed = static_cast<std::size_t>(std::count_if(volume.begin(), volume.end(), [](double v) { return v < 0.0; }));
    return faces_subset(m, keep);
}

/// Full topology summary (see file comment). Throws invalid_input for faces indexing missing vertices.
[[nodiscard]] inline mesh_topology_info analyze_topology(const triangle_mesh& m) {
    mesh_topology_info info;
    info.faces = m.faces.size();
    (void)face_components(m, &info.components);
    std::vector<std::uint8_t> used(m.vertices.size(), 0);
    std::vector<detail::half_edge> he;
    he.reserve(3 * m.faces.size());
    for (const auto& t : m.faces) {
        for (auto v : t) used[v] = 1;
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) ++info.degenerate_faces;
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t a = t[static_cast<std::size_t>(i)], b = t[static_cast<std::size_t>((i + 1) % 3)];
            if (a == b) continue;
            he.push_back({(static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b), a, b});
        }
    }
    info.vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), std::uint8_t{1}));
    std::sort(he.begin(), he.end());
    // boundary half-edges, for loop counting: union their endpoints
    union_find loops(m.vertices.size());
    std::vector<std::uint8_t> on_boundary(m.vertices.size(), 0);
    for (std::size_t i = 0; i < he.size();) {
        std::size_t j = i;
        while (j < he.size() && he[j].key == he[i].key) ++j;
        const std::size_t n = j - i;
        ++info.edges;
        if (n == 1) {
            ++info.boundary_edges;
            loops.unite(he[i].from, he[i].to);
            on_boundary[he[i].from] = on_boundary[he[i].to] = 1;
        } else if (n == 2) {
            if (he[i].from == he[i + 1].from) ++info.inconsistent_edges;
        } else {
            ++info.nonmanifold_edges;
        }
        i = j;
    }
    // in an edge-manifold mesh, boundary edges form cycles; count one per connected chain
    // (vertex-pinched loops sharing a vertex count once: a documented approximation)
    for (std::uint32_t v = 0; v < m.vertices.size(); ++v)
        if (on_boundary[v] && loops.find(v) == v) ++info.boundary_loops;
    info.euler = static_cast<long long>(info.vertices) - static_cast<long long>(info.edges) + static_cast<long long>(info.faces);
    info.genus = (2 * static_cast<long long>(info.components) - info.euler - static_cast<long long>(info.boundary_loops)) / 2;
    return info;
}

/// Every edge has at most two faces.
[[nodiscard]] inline bool is_edge_manifold(const triangle_mesh& m) { return analyze_topology(m).is_edge_manifold(); }
/// Number of edges with exactly one face.
[[nodiscard]] inline std::size_t count_boundary_edges(const triangle_mesh& m) { return analyze_topology(m).boundary_edges; }
/// Closed, edge-manifold, consistently oriented, no degenerate faces, at least one face.
[[nodiscard]] inline bool is_watertight(const triangle_mesh& m) { return analyze_topology(m).is_watertight(); }

/// Throws solver_error naming `what` and the counts of boundary and non-manifold edges unless m is
/// watertight (for results that must be printable; a failure here is a bug of the producer).
inline void require_watertight(const triangle_mesh& m, const std::string& what) {
    const mesh_topology_info t = analyze_topology(m);
    if (!t.is_watertight())
        throw solver_error(what + " is not watertight (" + std::to_string(t.boundary_edges) + " boundary, " +
                           std::to_string(t.nonmanifold_edges) + " non-manifold edges)");
}

}  // namespace fabsynth
