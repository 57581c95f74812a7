// SPDX-License-Identifier: MIT
#pragma once
/// @file components.hpp  Connected-component labelling of voxel sets.
///
/// Usage:
///   auto cc = fabsynth::label_components<fabsynth::connectivity::c26>(grid, [](auto v) { return v != 0; });
///   cc.count;              // number of components
///   cc.labels.get(p);      // component of voxel p, or -1 if pred(p) is false
///   cc.sizes[label];       // voxels in that component
///
/// Labels are deterministic: components are numbered 0, 1, ... in the order of their first voxel in
/// x-fastest index order. The flood fill is iterative (explicit stack), so huge components cannot
/// overflow the call stack. Time O(voxels visited * neighbourhood size), memory O(grid) for dense
/// grids and O(selected voxels) for sparse grids.
#include <cstdint>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "fabsynth/voxel/grid.hpp"
#include "fabsynth/voxel/neighbourhood.hpp"

namespace fabsynth {

/// Labels grid of the same storage kind as the input (dense int32 or sparse int32, background -1).
template <class Grid>
using label_grid_for = std::conditional_t<Grid::storage_type::is_sparse, sparse_voxel_grid<std::int32_t>,
                                          voxel_grid<std::int32_t>>;

/// Result of label_components.
template <class LabelGrid>
struct component_labels {
    LabelGrid labels;                  ///< component id per voxel, -1 = not selected
    int count = 0;                     ///< number of components
    std::vector<std::int64_t> sizes;   ///< voxels per component
};

/// Labels the connected components of the voxels p with pred(grid.get(p)), under neighbourhood C.
/// For sparse grids, pred(background) must be false (only stored voxels are examined); this is
/// checked and invalid_input is thrown otherwise.
template <neighbourhood C, class Grid, class Pred>
[[nodiscard]] auto label_components(const Grid& grid, Pred&& pred, C = {}) {
    using LG = label_grid_for<Grid>;
    component_labels<LG> out{LG(grid.geometry(), -1), 0, {}};
    const grid_geometry& g = grid.geometry();
    std::vector<std::uint64_t> stack;
    if constexpr (Grid::storage_type::is_sparse) {
        if (pred(grid.background()))
            throw invalid_input("label_components: predicate selects the background of a sparse grid");
        // work on slots of the selected voxels (one hash lookup per neighbour), then store labels
        std::vector<std::uint64_t> keys;
        grid.storage().for_each_stored([&](std::uint64_t i, const auto& v) {
            if (pred(v)) keys.push_back(i);
        });
        std::unordered_map<std::uint64_t, std::uint32_t> slot;
        slot.reserve(keys.size());
        for (std::size_t s = 0; s < keys.size(); ++s) slot.emplace(keys[s], static_cast<std::uint32_t>(s));
        std::vector<std::int32_t> label(keys.size(), -1);
        for (std::size_t seed = 0; seed < keys.size(); ++seed) {
            if (label[seed] >= 0) continue;
            const int l = out.count++;
            std::int64_t size = 0;
            label[seed] = l;
            stack.push_back(seed);
            while (!stack.empty()) {
                const std::uint64_t cur = stack.back();
                stack.pop_back();
                ++size;
                const ivec3 p = g.coord(keys[static_cast<std::size_t>(cur)]);
                for (const auto& o : C::offsets) {
                    const ivec3 q = p + as_ivec3(o);
                    if (!g.contains(q)) continue;
                    const auto it = slot.find(g.index(q));
                    if (it == slot.end() || label[it->second] >= 0) continue;
                    label[it->second] = l;
                    stack.push_back(it->second);
                }
            }
            out.sizes.push_back(size);
        }
        out.labels.storage().reserve(keys.size());
        for (std::size_t s = 0; s < keys.size(); ++s) out.labels.storage().set(keys[s], label[s]);
    } else {
        auto& labels = out.labels.storage();
        auto selected = [&](std::uint64_t i) { return static_cast<bool>(pred(grid.storage().get(i))); };
        for (std::uint64_t seed = 0, n = g.count(); seed < n; ++seed) {
            if (labels.get(seed) >= 0 || !selected(seed)) continue;
            const int l = out.count++;
            std::int64_t size = 0;
            labels.set(seed, l);
            stack.push_back(seed);
            while (!stack.empty()) {
                const std::uint64_t cur = stack.back();
                stack.pop_back();
                ++size;
                const ivec3 p = g.coord(cur);
                for (const auto& o : C::offsets) {
                    const ivec3 q = p + as_ivec3(o);
                    if (!g.contains(q)) continue;
                    const std::uint64_t qi = g.index(q);
                    if (labels.get(qi) >= 0 || !selected(qi)) continue;
                    labels.set(qi, l);
                    stack.push_back(qi);
                }
            }
            out.sizes.push_back(size);
        }
    }
    return out;
}

}  // namespace fabsynth
