// SPDX-License-Identifier: MIT
#pragma once
/// @file box_pairs.hpp  All intersecting pairs between two sets of axis-aligned boxes through a
/// uniform grid (the broad phase of segment-crossing and contact tests: filigree topology cut).
///
/// Usage:
///   fabsynth::for_each_overlapping_box(edge_boxes_p, edge_boxes_q, [&](std::size_t i, std::size_t j) {
///       test(i, j);
///       return false;  // true stops
///   });
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth {

/// Calls visit(i, j) once for every i, j with a[i] and b[j] intersecting (closed boxes; empty boxes
/// never intersect), b in increasing j, until visit returns true; returns whether one did. The
/// boxes of a are bucketed in a uniform grid over the overlap of the two extents whose cell is
/// the median box side, coarsened to at most about 4 (|a| + |b|) cells; each box of b then looks
/// only into the cells it covers. Linear unless boxes crowd into a few cells or are much larger
/// than the median.
template <class Visit>
bool for_each_overlapping_box(std::span<const box2> a, std::span<const box2> b, Visit&& visit) {
    box2 extent_a, extent_b;
    for (const box2& x : a) extent_a.extend(x);
    for (const box2& x : b) extent_b.extend(x);
    if (extent_a.empty() || extent_b.empty() || !extent_a.intersects(extent_b)) return false;
    const box2 region(glm::max(extent_a.lo, extent_b.lo), glm::min(extent_a.hi, extent_b.hi));
    std::vector<double> sides;
    for (const auto boxes : {a, b})
        for (const box2& x : boxes)
            if (!x.empty()) sides.push_back(std::max(x.size().x, x.size().y));
    std::nth_element(sides.begin(), sides.begin() + static_cast<std::ptrdiff_t>(sides.size() / 2), sides.end());
    const double w = region.hi.x - region.lo.x, h = region.hi.y - region.lo.y;
    double cell = sides[sides.size() / 2];
    if (!(cell > 0.0)) cell = std::max({w, h, 1.0});
    const double max_cells = 4.0 * static_cast<double>(a.size() + b.size()) + 16.0;
    while ((std::floor(w / cell) + 1.0) * (std::floor(h / cell) + 1.0) > max_cells) cell *= 1.5;
    const auto nx = static_cast<std::int64_t>(std::floor(w / cell)) + 1, ny = static_cast<std::int64_t>(std::floor(h / cell)) + 1;
    auto cell_of = [&](double v, double origin, std::int64_t count) {
        return std::clamp(static_cast<std::int64_t>(std::floor((v - origin) / cell)), std::int64_t{0}, count - 1);
    };
    // calls f(c) for every cell c that box x covers
    auto for_cells = [&](const box2& x, auto&& f) {
        const std::int64_t x0 = cell_of(x.lo.x, region.lo.x, nx), x1 = cell_of(x.hi.x, region.lo.x, nx);
        const std::int64_t y0 = cell_of(x.lo.y, region.lo.y, ny), y1 = cell_of(x.hi.y, region.lo.y, ny);
        for (std::int64_t y = y0; y <= y1; ++y)
            for (std::int64_t cx = x0; cx <= x1; ++cx) f(static_cast<std::size_t>(y * nx + cx));
    };
    // the boxes of a by cell, in compressed rows: bucket[start[c] .. start[c + 1])
    std::vector<std::size_t> start(static_cast<std::size_t>(nx * ny) + 1, 0);
    for (const box2& x : a)
        if (x.intersects(region)) for_cells(x, [&](std::size_t c) { ++start[c + 1]; });
    for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    std::vector<std::size_t> bucket(start.back()), fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].intersects(region)) for_cells(a[i], [&](std::size_t c) { bucket[fill[c]++] = i; });
    std::vector<std::size_t> seen(a.size(), static_cast<std::size_t>(-1));  // last j that looked at i
    for (std::size_t j = 0; j < b.size(); ++j) {
        if (!b[j].intersects(region)) continue;
        bool stop = false;
        for_cells(b[j], [&](std::size_t c) {
            for (std::size_t k = start[c]; k < start[c + 1] && !stop; ++k) {
                const std::size_t i = bucket[k];
                if (seen[i] == j) continue;
                seen[i] = j;
                stop = a[i].intersects(b[j]) && visit(i, j);
            }
        });
        if (stop) return true;
    }
    return false;
}

}  // namespace fabsynth
