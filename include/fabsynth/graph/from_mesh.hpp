// SPDX-License-Identifier: MIT
#pragma once
/// @file from_mesh.hpp  The edge graph of a triangle mesh.
///
/// Usage:
///   auto g = fabsynth::graph::from_mesh(mesh);      // vertex v of g = mesh.vertices[v]
///   auto geo = fabsynth::graph::geodesic(g, a, b);  // edge-path distance on the surface (mm)
///
/// One vertex per mesh vertex (unreferenced ones stay isolated) and one undirected edge per distinct
/// vertex pair sharing a face edge, weighted by its Euclidean length in mesh units (mm). Degenerate
/// faces contribute only their edges between distinct vertices. Time O(F log F), memory O(F).
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/graph/csr_graph.hpp"

namespace fabsynth::graph {

/// Edge graph of m. Throws invalid_input for a face indexing a missing vertex or a non-finite
/// vertex position (named by index).
[[nodiscard]] inline csr_graph<> from_mesh(const triangle_mesh& m) {
    const std::size_t n = m.vertices.size();
    if (n > max_vertices) throw invalid_input("from_mesh: " + std::to_string(n) + " vertices exceed the limit of 2^32 - 2");
    for (std::size_t v = 0; v < n; ++v)
        if (!all_finite(m.vertices[v])) throw invalid_input("from_mesh: vertex " + std::to_string(v) + " is not finite");
    std::vector<std::uint64_t> keys;
    keys.reserve(3 * m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t a = m.faces[f][static_cast<std::size_t>(i)], b = m.faces[f][static_cast<std::size_t>((i + 1) % 3)];
            if (a >= n || b >= n)
                throw invalid_input("from_mesh: face " + std::to_string(f) + " indexes vertex " + std::to_string(std::max(a, b)) + ", but the mesh has " +
                                    std::to_string(n) + " vertices");
            if (a != b) keys.push_back((std::uint64_t{std::min(a, b)} << 32) | std::max(a, b));
        }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    std::vector<edge_record<>> edges;
    edges.reserve(keys.size());
    for (const std::uint64_t k : keys) {
        const auto a = static_cast<vertex_id>(k >> 32), b = static_cast<vertex_id>(k & 0xffffffffu);
        edges.push_back({a, b, glm::distance(m.vertices[a], m.vertices[b])});
    }
    return build_csr(n, edges);
}

}  // namespace fabsynth::graph
