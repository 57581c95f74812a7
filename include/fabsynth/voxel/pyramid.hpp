// SPDX-License-Identifier: MIT
#pragma once
/// @file pyramid.hpp  Multi-resolution voxel pyramids (2x downsampling per level) for
/// coarse-to-fine algorithms.
///
/// Level 0 is the input; level l+1 has dims ceil(dims_l / 2), the same origin and twice the
/// spacing, so parent voxel P covers children 2P + {0,1}^3 (those inside level l). Each parent's
/// value is a reduction of its existing children's values (1 to 8 of them at odd borders).
///
/// Usage:
///   auto pyr = fabsynth::build_pyramid(mask, fabsynth::reduce_any{});   // down to a 1x1x1 grid
///   auto& coarse = pyr.levels.back();
///   ivec3 parent = fabsynth::parent_voxel(p);
#include <algorithm>
#include <concepts>
#include <string>
#include <type_traits>
#include <cstdint>
#include <vector>

#include "fabsynth/voxel/grid.hpp"

namespace fabsynth {

/// Reduction policy: r(const T* children, int count) -> T, count in [1, 8]. For sparse grids,
/// reducing only background values must give the background (parents of unstored regions are not
/// stored).
template <class R, class T>
concept voxel_reduction = requires(const R r, const T* v, int n) {
    { r(v, n) } -> std::convertible_to<T>;
};

/// Parent is set (non-zero / true) if any child is.
struct reduce_any {
    template <class T>
    T operator()(const T* v, int n) const {
        for (int i = 0; i < n; ++i)
            if (v[i] != T{}) return v[i];
        return T{};
    }
};
/// Parent is set only if every child is (returns the first child then, else T{}).
struct reduce_all {
    template <class T>
    T operator()(const T* v, int n) const {
        for (int i = 0; i < n; ++i)
            if (v[i] == T{}) return T{};
        return v[0];
    }
};
/// Arithmetic mean of the existing children, in T (integers truncate toward zero).
struct reduce_mean {
    template <class T>
    T operator()(const T* v, int n) const {
        if constexpr (std::is_integral_v<T>) {
            long double s = 0;
            for (int i = 0; i < n; ++i) s += static_cast<long double>(v[i]);
            return static_cast<T>(s / n);
        } else {
            T s = v[0];
            for (int i = 1; i < n; ++i) s = s + v[i];
            return s / static_cast<double>(n);
        }
    }
};

/// Parent of voxel p one level up.
[[nodiscard]] constexpr ivec3 parent_voxel(const ivec3& p) noexcept { return {p.x >> 1, p.y >> 1, p.z >> 1}; }

/// Levels 0 (finest, the input) .. L (coarsest).
template <class Grid>
struct voxel_pyramid {
    std::vector<Grid> levels;
    [[nodiscard]] std::size_t size() const noexcept { return levels.size(); }
    [[nodiscard]] const Grid& operator[](std::size_t l) const { return levels.at(l); }
    [[nodiscard]] Grid& operator[](std::size_t l) { return levels.at(l); }
};

/// One level of downsampling of `fine` with reduction r.
template <class T, class S, voxel_reduction<T> R>
[[nodiscard]] voxel_grid<T, S> downsample(const voxel_grid<T, S>& fine, const R& r) {
    grid_geometry g = fine.geometry();
    g.dims = (g.dims + 1) / 2;
    g.spacing *= 2.0;
    voxel_grid<T, S> coarse(g, fine.background());
    const grid_geometry& fg = fine.geometry();
    auto reduce_parent = [&](const ivec3& P) {
        T vals[8]{};
        int n = 0;
        for (int dz = 0; dz < 2; ++dz)
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) {
                    const ivec3 c = 2 * P + ivec3(dx, dy, dz);
                    if (fg.contains(c)) vals[n++] = fine.get(c);
                }
        return static_cast<T>(r(vals, n));
    };
    if constexpr (S::is_sparse) {
        std::vector<std::uint64_t> parents;
        parents.reserve(static_cast<std::size_t>(fine.storage().stored()));
        fine.storage().for_each_stored([&](std::uint64_t i, const T&) { parents.push_back(g.index(parent_voxel(fg.coord(i)))); });
        std::sort(parents.begin(), parents.end());
        parents.erase(std::unique(parents.begin(), parents.end()), parents.end());
        for (std::uint64_t P : parents) coarse.storage().set(P, reduce_parent(g.coord(P)));
    } else {
        for (int z = 0; z < g.dims.z; ++z)
            for (int y = 0; y < g.dims.y; ++y)
                for (int x = 0; x < g.dims.x; ++x) coarse.set({x, y, z}, reduce_parent({x, y, z}));
    }
    return coarse;
}

/// Pyramid of `fine` with up to max_levels levels (including level 0), stopping once a level is a
/// single voxel. Throws invalid_input for max_levels < 1.
template <class T, class S, voxel_reduction<T> R>
[[nodiscard]] voxel_pyramid<voxel_grid<T, S>> build_pyramid(const voxel_grid<T, S>& fine, const R& r, int max_levels = 64) {
    if (max_levels < 1) throw invalid_input("build_pyramid: max_levels must be >= 1, got " + std::to_string(max_levels));
    voxel_pyramid<voxel_grid<T, S>> pyr;
    pyr.levels.push_back(fine);
    while (static_cast<int>(pyr.levels.size()) < max_levels) {
        const ivec3 d = pyr.levels.back().dims();
        if (d.x == 1 && d.y == 1 && d.z == 1) break;
        pyr.levels.push_back(downsample(pyr.levels.back(), r));
    }
    return pyr;
}

}  // namespace fabsynth
