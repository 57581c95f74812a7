// SPDX-License-Identifier: MIT
#pragma once
/// @file workspace.hpp  (internal, behind evaluator.hpp) The data the evaluator's phases share:
/// the public edge_segment, the per-slice seed cache and the per-thread scratch space.
#include <cstdint>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/detail/polytope.hpp"

namespace fabsynth::foam {

/// One straight piece of a Voronoi edge (mm).
struct edge_segment {
    vec3 a, b;
};

}  // namespace fabsynth::foam

namespace fabsynth::foam::detail {

/// Seeds of a block of coarse cells, generated once (in parallel) and shared read-only by tiles.
struct seed_cache {
    i64vec3 lo{0}, dims{0};
    std::vector<std::uint32_t> start;  // per cell, prefix offsets into seeds (size cells + 1)
    std::vector<vec3> seeds;
    [[nodiscard]] bool has(const i64vec3& k) const noexcept {
        return k.x >= lo.x && k.y >= lo.y && k.z >= lo.z && k.x < lo.x + dims.x && k.y < lo.y + dims.y &&
               k.z < lo.z + dims.z;
    }
    [[nodiscard]] std::size_t index(const i64vec3& k) const noexcept {
        const i64vec3 d = k - lo;
        return static_cast<std::size_t>((d.z * dims.y + d.y) * dims.x + d.x);
    }
};

/// Bounds of one sub-box B_k of a query box (certificate.hpp).
struct sub_box_bound {
    double need2;           ///< (d1_k + 2 h + slack)^2: a seed farther from c_k is not needed for B_k
    double cell_reach;      ///< d1_k + h + slack: the cell of s meets B_k only within this of s
    double centre_scale;    ///< |c_k| + h + 1: rounding scale of the half-space test
    double near_len2;       ///< |t_k|^2 of the seed t_k nearest to c_k
    double near_len;        ///< |t_k|
};

/// Per-thread scratch space of the evaluator.
struct foam_workspace {
    // gather (certificate.hpp)
    std::vector<vec3> S;              // gathered seeds, sorted by x
    std::vector<vec3> sub_c;          // sub-box centres c_k
    std::vector<double> sub_d1;       // distance from c_k to its nearest seed in S
    std::vector<vec3> sub_near;       // that nearest seed t_k
    std::vector<sub_box_bound> sub_b;
    std::vector<std::uint8_t> is_cell;  // per S entry: its cell may meet the box
    std::vector<box3> cell_box;         // per S entry with is_cell: box holding (its cell) & (the box)
    const seed_cache* cache = nullptr;  // the slice's seeds, when slicing
    // direct-mapped cache of recently generated coarse cells (point queries), per foam instance
    struct recent_cell {
        i64vec3 key{0};
        bool valid = false;
        std::vector<vec3> seeds;
    };
    std::uint64_t recent_owner = 0;
    std::vector<recent_cell> recent;
    // cell clipping (voronoi_edges.hpp)
    std::vector<std::pair<double, int>> order;
    polytope poly;
    // edge lists (coverage, tiles) and the tile raster (slicer.hpp)
    std::vector<edge_segment> edges;
    std::vector<double> tau2;
    std::vector<std::uint8_t> hits;  // per (sub-)pixel of a tile: 1 = solid
};

}  // namespace fabsynth::foam::detail
