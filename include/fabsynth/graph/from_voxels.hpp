// SPDX-License-Identifier: MIT
#pragma once
/// @file from_voxels.hpp  Graphs of sparse voxel sets (structurally-sound-patterns.md §5.1: the
/// surface voxel graph G_surface, 26-neighbours, Euclidean edge weights).
///
/// Usage:
///   auto vg = fabsynth::graph::from_voxels<fabsynth::connectivity::c26>(shell);   // sparse grid: stored voxels
///   auto solid = fabsynth::graph::from_voxels(grid, [](float v) { return v > 0.5f; });   // selected voxels
///   vg.graph;                  // csr_graph<>, undirected, weights in mm
///   vg.voxels[v];              // voxel coordinate of vertex v
///   vg.vertex_of({i, j, k});   // vertex of a voxel, or no_vertex
///
/// Vertex i is the i-th selected voxel in increasing linear (x-fastest) index. Two vertices are
/// joined iff their voxels differ by an offset of the neighbourhood C (6: faces, 18: + edges, 26:
/// + corners); the weight is the distance between the voxel centres in mm,
/// sqrt((dx sx)^2 + (dy sy)^2 + (dz sz)^2) for spacing (sx, sy, sz). Rows are sorted by target
/// (vertex order = index order). The neighbour search walks the 9 neighbouring voxel rows with
/// merge pointers: O(V * |C|) time after sorting, no hashing; parallel over vertex blocks with
/// results independent of the thread count. Memory O(V * |C|).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/graph/csr_graph.hpp"
#include "fabsynth/voxel/grid.hpp"
#include "fabsynth/voxel/neighbourhood.hpp"

namespace fabsynth::graph {

/// A graph on voxels with the voxel of every vertex.
struct voxel_graph {
    csr_graph<> graph;                   ///< undirected; weights = centre distances (mm)
    grid_geometry geometry;              ///< grid the voxels live in
    std::vector<ivec3> voxels;           ///< per vertex: voxel coordinate
    std::vector<std::uint64_t> indices;  ///< per vertex: linear voxel index (strictly increasing)

    [[nodiscard]] std::size_t size() const noexcept { return voxels.size(); }
    /// Vertex of voxel p, or no_vertex if p is outside the grid or not a vertex. O(log V).
    [[nodiscard]] vertex_id vertex_of(const ivec3& p) const noexcept {
        if (!geometry.contains(p)) return no_vertex;
        const std::uint64_t i = geometry.index(p);
        const auto it = std::lower_bound(indices.begin(), indices.end(), i);
        return it != indices.end() && *it == i ? static_cast<vertex_id>(it - indices.begin()) : no_vertex;
    }
    /// Centre (mm) of the voxel of vertex v.
    [[nodiscard]] vec3 position(vertex_id v) const noexcept { return geometry.center(voxels[v]); }
};

/// Predicate selecting every stored voxel (every voxel of a dense grid).
struct all_stored {
    template <class T>
    constexpr bool operator()(const T&) const noexcept {
        return true;
    }
};

namespace detail {

/// Graph of the voxels with strictly increasing linear `indices` in grid g under neighbourhood C.
template <neighbourhood C>
[[nodiscard]] voxel_graph voxel_graph_from_sorted(const grid_geometry& g, std::vector<std::uint64_t> indices) {
    if (indices.size() > max_vertices)
        throw invalid_input("from_voxels: " + std::to_string(indices.size()) + " voxels exceed the limit of 2^32 - 2 vertices");
    voxel_graph out;
    out.geometry = g;
    const std::size_t n = indices.size();
    out.voxels.resize(n);
    for (std::size_t v = 0; v < n; ++v) out.voxels[v] = g.coord(indices[v]);
    // Offset table: allowed[dx+1][dy+1][dz+1] and the weight of each offset.
    std::array<double, 27> weight{};
    std::array<bool, 27> allowed{};
    for (const auto& o : C::offsets) {
        const double a = o[0] * g.spacing.x, b = o[1] * g.spacing.y, c = o[2] * g.spacing.z;
        const int k = (o[0] + 1) + 3 * ((o[1] + 1) + 3 * (o[2] + 1));
        allowed[static_cast<std::size_t>(k)] = true;
        weight[static_cast<std::size_t>(k)] = std::sqrt(a * a + b * b + c * c);
    }
    const auto nx = static_cast<std::int64_t>(g.dims.x), ny = static_cast<std::int64_t>(g.dims.y);
    // Visits the neighbours of every vertex in [lo, hi) in increasing target order: for each of the
    // 9 neighbouring rows (dy, dz), a pointer moves monotonically through `indices`.
    auto visit_block = [&](std::size_t lo, std::size_t hi, auto&& emit) {
        std::array<std::size_t, 9> ptr{};
        bool first = true;
        for (std::size_t v = lo; v < hi; ++v) {
            const ivec3 p = out.voxels[v];
            const auto centre = static_cast<std::int64_t>(indices[v]);
            for (int r = 0; r < 9; ++r) {
                const int dy = r % 3 - 1, dz = r / 3 - 1;
                const std::int64_t row_centre = centre + nx * (dy + ny * dz);
                if (first) {
                    const std::int64_t from = std::max<std::int64_t>(0, row_centre - 1);
                    ptr[static_cast<std::size_t>(r)] = static_cast<std::size_t>(
                        std::lower_bound(indices.begin(), indices.end(), static_cast<std::uint64_t>(from)) - indices.begin());
                }
                std::size_t& k = ptr[static_cast<std::size_t>(r)];
                while (k < n && static_cast<std::int64_t>(indices[k]) < row_centre - 1) ++k;
                if (p.y + dy < 0 || p.y + dy >= g.dims.y || p.z + dz < 0 || p.z + dz >= g.dims.z) continue;
                for (std::size_t j = k; j < n && static_cast<std::int64_t>(indices[j]) <= row_centre + 1; ++j) {
                    const int dx = out.voxels[j].x - p.x;
                    if (dx < -1 || dx > 1 || out.voxels[j].y != p.y + dy || out.voxels[j].z != p.z + dz) continue;  // other row
                    const auto o = static_cast<std::size_t>((dx + 1) + 3 * ((dy + 1) + 3 * (dz + 1)));
                    if (allowed[o]) emit(v, static_cast<vertex_id>(j), weight[o]);
                }
            }
            first = false;
        }
    };
    constexpr std::size_t block = 4096;
    const std::size_t blocks = (n + block - 1) / block;
    std::vector<arc_id> offsets(n + 1, 0);
    parallel_for(0, blocks, [&](std::size_t b) {
        visit_block(b * block, std::min(n, (b + 1) * block), [&](std::size_t v, vertex_id, double) { ++offsets[v + 1]; });
    });
    for (std::size_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
    std::vector<vertex_id> targets(offsets[n]);
    std::vector<double> weights(offsets[n]);
    parallel_for(0, blocks, [&](std::size_t b) {
        const std::size_t lo = b * block;
        arc_id next = offsets[lo];
        visit_block(lo, std::min(n, (b + 1) * block), [&](std::size_t, vertex_id t, double w) {
            targets[next] = t;
            weights[next] = w;
            ++next;
        });
    });
    out.graph = csr_graph<>::from_arrays(std::move(offsets), std::move(targets), std::move(weights), false);
    out.indices = std::move(indices);
    return out;
}

}  // namespace detail

/// Graph of a list of voxels of grid g (any order).
/// @param g       grid geometry (dims, origin, spacing in mm); validated
/// @param voxels  #V voxel coordinates inside g, no duplicates
/// Throws invalid_input for a voxel outside the grid or a repeated voxel (named by its position in
/// the list). Time O(V log V + V |C|).
template <neighbourhood C = connectivity::c26>
[[nodiscard]] voxel_graph from_voxels(const grid_geometry& g, std::span<const ivec3> voxels, C = {}) {
    g.validate("from_voxels");
    std::vector<std::uint64_t> indices(voxels.size());
    for (std::size_t i = 0; i < voxels.size(); ++i) {
        const ivec3 p = voxels[i];
        if (!g.contains(p))
            throw invalid_input("from_voxels: voxel " + std::to_string(i) + " (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " +
                                std::to_string(p.z) + ") is outside the grid");
        indices[i] = g.index(p);
    }
    std::sort(indices.begin(), indices.end());
    const auto dup = std::adjacent_find(indices.begin(), indices.end());
    if (dup != indices.end()) {
        const ivec3 p = g.coord(*dup);
        throw invalid_input("from_voxels: voxel (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                            ") is listed more than once");
    }
    return detail::voxel_graph_from_sorted<C>(g, std::move(indices));
}

/// from_voxels for a std::vector of voxels.
template <neighbourhood C = connectivity::c26>
[[nodiscard]] voxel_graph from_voxels(const grid_geometry& g, const std::vector<ivec3>& voxels, C c = {}) {
    return from_voxels<C>(g, std::span<const ivec3>(voxels), c);
}

/// Graph of the stored voxels of a voxel_grid (dense: every voxel; sparse: the set ones) whose
/// value satisfies pred (default: all). Time O(stored voxels + V |C|).
template <neighbourhood C = connectivity::c26, class Grid, class Pred = all_stored>
    requires requires(const Grid& grid) { grid.storage().for_each_stored([](std::uint64_t, const typename Grid::value_type&) {}); }
[[nodiscard]] voxel_graph from_voxels(const Grid& grid, Pred&& pred = {}, C = {}) {
    std::vector<std::uint64_t> indices;
    grid.storage().for_each_stored([&](std::uint64_t i, const typename Grid::value_type& v) {
        if (pred(v)) indices.push_back(i);
    });
    return detail::voxel_graph_from_sorted<C>(grid.geometry(), std::move(indices));
}

}  // namespace fabsynth::graph
