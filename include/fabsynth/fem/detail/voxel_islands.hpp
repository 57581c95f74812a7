// SPDX-License-Identifier: MIT
#pragma once
/// @file voxel_islands.hpp  Face-connected components of solid voxels, with wrap-around detection
/// for periodic grids (internal to fem/voxel.hpp and fem/homogenization.hpp).
///
/// Face (6-) connectivity is used on purpose: voxels that touch only along an edge or at a corner
/// share 2 or 1 nodes, which leaves a rotation mode (a hinge) in the stiffness matrix.
#include <array>
#include <cstdint>
#include <vector>

#include "fabsynth/core/types.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/fem/detail/voxel_operators.hpp"
#include "fabsynth/voxel/components.hpp"
#include "fabsynth/voxel/grid.hpp"

namespace fabsynth::fem::detail {

struct voxel_components {
    std::vector<std::int32_t> label;   ///< per voxel, -1 = void
    std::vector<std::size_t> size;     ///< voxels per component
    std::vector<std::size_t> first;    ///< lowest voxel index of each component
    std::vector<std::uint8_t> wraps;   ///< periodic grids: the component connects to its own periodic image
};

/// Labels components in increasing order of their first voxel (deterministic). The flood fill is
/// voxel/components.hpp's (face neighbours, no wrap); on periodic grids the pieces it finds are
/// then glued across the periodic faces with one potential union-find per axis (the potential is
/// the periodic image, in cells along that axis), and a component wraps iff one of them winds.
/// O(voxels) time and memory.
[[nodiscard]] inline voxel_components label_voxel_components(const ivec3& cells, bool periodic, const std::vector<double>& scale) {
    const std::size_t total = scale.size();
    voxel_grid<std::uint8_t> solid(cells, vec3(0.0), 1.0);
    FABSYNTH_ASSERT(solid.size() == total);
    auto& occupied = solid.storage().data();
    for (std::size_t s = 0; s < total; ++s) occupied[s] = scale[s] != 0.0 ? 1 : 0;
    auto pieces = label_components<connectivity::c6>(solid, [](std::uint8_t v) { return v != 0; });
    std::vector<std::int32_t> piece = std::move(pieces.labels.storage().data());
    const auto np = static_cast<std::size_t>(pieces.count);
    std::vector<std::size_t> piece_first(np, 0);
    for (std::size_t s = total; s-- > 0;)  // lowest voxel of each piece
        if (piece[s] >= 0) piece_first[static_cast<std::size_t>(piece[s])] = s;

    voxel_components r;
    if (!periodic) {
        r.label = std::move(piece);
        r.size.assign(pieces.sizes.begin(), pieces.sizes.end());
        r.first = std::move(piece_first);
        r.wraps.assign(np, 0);
        return r;
    }
    // Glue pieces across each periodic face: crossing from cell n-1 to cell 0 along axis a moves
    // one image forward along a (and none along the other axes).
    std::array<potential_union_find, 3> glue{potential_union_find(np), potential_union_find(np), potential_union_find(np)};
    const node_grid g{cells, true};
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        for (int j = 0; j < cells[c]; ++j)
            for (int i = 0; i < cells[b]; ++i) {
                ivec3 hi{0}, lo{0};
                hi[a] = cells[a] - 1, hi[b] = i, hi[c] = j;
                lo[b] = i, lo[c] = j;
                const std::int32_t ph = piece[g.index(hi.x, hi.y, hi.z)], pl = piece[g.index(lo.x, lo.y, lo.z)];
                if (ph < 0 || pl < 0) continue;
                for (int k = 0; k < 3; ++k)
                    glue[static_cast<std::size_t>(k)].link(static_cast<std::uint32_t>(ph), static_cast<std::uint32_t>(pl), k == a ? 1 : 0);
            }
    }
    // Merged components in order of their smallest piece (= their first voxel).
    std::vector<std::int32_t> merged(np, -1);
    for (std::size_t k = 0; k < np; ++k) {
        const std::uint32_t root = glue[0].find(static_cast<std::uint32_t>(k));
        if (root == k) {
            merged[k] = static_cast<std::int32_t>(r.size.size());
            r.size.push_back(0);
            r.first.push_back(piece_first[k]);
            r.wraps.push_back(glue[0].winds(root) || glue[1].winds(root) || glue[2].winds(root) ? 1 : 0);
        } else {
            merged[k] = merged[root];
        }
        r.size[static_cast<std::size_t>(merged[k])] += static_cast<std::size_t>(pieces.sizes[k]);
    }
    for (auto& l : piece)
        if (l >= 0) l = merged[static_cast<std::size_t>(l)];
    r.label = std::move(piece);
    return r;
}

}  // namespace fabsynth::fem::detail
