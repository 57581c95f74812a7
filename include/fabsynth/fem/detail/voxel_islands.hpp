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
#include "fabsynth/fem/detail/voxel_operators.hpp"

namespace fabsynth::fem::detail {

struct voxel_components {
    std::vector<std::int32_t> label;   ///< per voxel, -1 = void
    std::vector<std::size_t> size;     ///< voxels per component
    std::vector<std::size_t> first;    ///< lowest voxel index of each component
    std::vector<std::uint8_t> wraps;   ///< periodic grids: the component connects to its own periodic image
};

/// Labels components in increasing order of their first voxel (deterministic). Iterative flood
/// fill, O(voxels) time and memory.
[[nodiscard]] inline voxel_components label_voxel_components(const ivec3& cells, bool periodic, const std::vector<double>& scale) {
    const std::size_t total = scale.size();
    voxel_components r;
    r.label.assign(total, -1);
    // Periodic image each voxel was reached in (unwrapped = coords + shift * cells).
    std::vector<std::array<std::int32_t, 3>> shift(periodic ? total : 0);
    std::vector<std::size_t> stack;
    const node_grid g{cells, periodic};
    for (std::size_t s = 0; s < total; ++s) {
        if (scale[s] == 0.0 || r.label[s] >= 0) continue;
        const auto id = static_cast<std::int32_t>(r.size.size());
        r.size.push_back(0);
        r.first.push_back(s);
        r.wraps.push_back(0);
        r.label[s] = id;
        if (periodic) shift[s] = {0, 0, 0};
        stack.push_back(s);
        while (!stack.empty()) {
            const std::size_t v = stack.back();
            stack.pop_back();
            ++r.size.back();
            const ivec3 p = g.coords(v);
            for (int f = 0; f < 6; ++f) {
                ivec3 q = p;
                q[f / 2] += (f % 2) ? 1 : -1;
                std::array<std::int32_t, 3> sh{};
                if (periodic) {
                    sh = shift[v];
                    for (int a = 0; a < 3; ++a) {
                        if (q[a] < 0) q[a] += cells[a], --sh[static_cast<std::size_t>(a)];
                        else if (q[a] >= cells[a]) q[a] -= cells[a], ++sh[static_cast<std::size_t>(a)];
                    }
                } else if (q[f / 2] < 0 || q[f / 2] >= cells[f / 2]) {
                    continue;
                }
                const std::size_t w = g.index(q.x, q.y, q.z);
                if (scale[w] == 0.0) continue;
                if (r.label[w] >= 0) {
                    if (periodic && shift[w] != sh) r.wraps.back() = 1;
                    continue;
                }
                r.label[w] = id;
                if (periodic) shift[w] = sh;
                stack.push_back(w);
            }
        }
    }
    return r;
}

}  // namespace fabsynth::fem::detail
