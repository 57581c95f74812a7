// SPDX-License-Identifier: MIT
#pragma once
/// @file reeb_slicing.hpp  Topology-driven slicing positions from a Reeb-graph sweep of the
/// rasterized exemplar (Zhou et al. 2014, §5.2, §5.2.1, §5.2.2).
///
/// 1. The exemplar is rasterized (pixel centres inside = solid, even-odd scanlines).
/// 2. A vertical line sweeps the columns left to right. Each column's solid pixels form vertical
///    runs; two runs of neighbouring columns are linked when they share a row (4-connectivity).
///    Between two columns the topology changes unless the links are a one-to-one matching: a run
///    beginning or ending, splitting or merging. The x of every such column boundary is an *event*
///    Only interior boundaries count: at the exemplar's two ends the band itself is cut (as in
///    data/vector/), which leaves portals there, not a topology change.
/// 3. §5.2.2 grouping: sorted events form groups; a group grows until the next event is farther
///    than `group distance` from the last one; each group's mean is an *attacher* A_i. A band whose
///    two end columns are empty (separate motifs) is periodic across its ends: its last and first
///    events group across the seam when they are that close, and the group's attacher stands at
///    both ends (not in the paper, which has no band ends).
/// 4. Cuts are the midpoints C_i = (A_i + A_{i+1}) / 2.
/// 5. §5.2.1: cuts whose narrowest portal is thinner than `min_portal_width` are dropped.
///
/// About the grouping distance: the paper uses 0.2 W (W = exemplar width, "experimentally
/// determined"), the default here. On a long band repeating one motif (the bundled data repeat
/// theirs 6-12 times) events of neighbouring repeats are closer than 0.2 W and chain into one
/// group, leaving no cut; pass a smaller `group_fraction` or an absolute `group_distance` (e.g. a fraction of the
/// motif's width) for such bands.
///
/// Usage:
///   auto r = fabsynth::vector_pattern::reeb_slicing(ex, {.group_distance = 5.0, .min_portal_width = 1.0});
///   auto pieces = fabsynth::vector_pattern::slice(ex, r.cuts);
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/raster.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"
#include "fabsynth/vector_pattern/pieces.hpp"

namespace fabsynth::vector_pattern {

/// Options of the Reeb sweep.
struct reeb_options {
    double pixel = 0.0;               ///< raster pixel size (mm); 0 = max(W, height) / 1024
    double group_fraction = 0.2;      ///< §5.2.2 grouping distance as a fraction of W (paper: 0.2)
    double group_distance = 0.0;      ///< absolute grouping distance (mm); > 0 overrides group_fraction
    double min_portal_width = 0.0;    ///< §5.2.1: drop cuts with a portal thinner than this (mm)
    std::size_t max_pixels = std::size_t{1} << 26;  ///< raster size limit (bounds memory)
};

/// Result of the sweep (x positions in mm, increasing).
struct reeb_result {
    std::vector<double> events;     ///< raw topology-change positions (column boundaries)
    std::vector<double> attachers;  ///< grouped events (group means)
    std::vector<double> cuts;       ///< midpoints of consecutive attachers, after the thin filter
    double pixel = 0.0;             ///< pixel size used
};

namespace detail {

/// Solid runs [row_begin, row_end) of every column of the rasterized exemplar.
inline std::vector<std::vector<std::pair<int, int>>> column_runs(const exemplar& ex, double pixel, int nx, int ny) {
    std::vector<std::uint8_t> solid(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0);
    polygon_rasterizer raster;
    for (const auto& p : ex.polygons) raster.add_polygon(p);
    raster.for_each_run({ex.bounds.lo, pixel, nx, ny}, [&](int j, int i0, int i1) {
        std::fill_n(solid.begin() + static_cast<std::ptrdiff_t>(j) * nx + i0, i1 - i0, std::uint8_t{1});
    });
    std::vector<std::vector<std::pair<int, int>>> runs(static_cast<std::size_t>(nx));
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny;) {
            if (!solid[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)]) {
                ++j;
                continue;
            }
            const int j0 = j;
            while (j < ny && solid[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)]) ++j;
            runs[static_cast<std::size_t>(i)].emplace_back(j0, j);
        }
    return runs;
}

/// True unless the runs of two neighbouring columns are linked one to one.
inline bool topology_changes(const std::vector<std::pair<int, int>>& a, const std::vector<std::pair<int, int>>& b) {
    if (a.size() != b.size()) return true;
    std::vector<int> ca(a.size(), 0), cb(b.size(), 0);
    // Both lists are sorted and disjoint: a two-pointer walk finds every overlapping pair.
    for (std::size_t i = 0, k = 0; i < a.size() && k < b.size();) {
        if (a[i].first < b[k].second && b[k].first < a[i].second) ++ca[i], ++cb[k];
        if (a[i].second < b[k].second) ++i;
        else ++k;
    }
    for (int c : ca)
        if (c != 1) return true;
    for (int c : cb)
        if (c != 1) return true;
    return false;
}

}  // namespace detail

/// Reeb sweep of the exemplar (see the file comment). Throws invalid_input for an empty exemplar,
/// bad options, or a raster above max_pixels. O(rows * n + pixels).
[[nodiscard]] inline reeb_result reeb_slicing(const exemplar& ex, const reeb_options& opt = {}) {
    if (ex.polygons.empty() || ex.bounds.empty() || !(ex.width() > 0.0) || !(ex.height() > 0.0))
        throw invalid_input("reeb_slicing: empty or degenerate exemplar");
    if (!(opt.pixel >= 0.0) || !std::isfinite(opt.pixel)) throw invalid_input("reeb_slicing: pixel must be finite and >= 0");
    if (!(opt.group_fraction >= 0.0) || !std::isfinite(opt.group_fraction))
        throw invalid_input("reeb_slicing: group_fraction must be finite and >= 0");
    if (!(opt.group_distance >= 0.0) || !std::isfinite(opt.group_distance))
        throw invalid_input("reeb_slicing: group_distance must be finite and >= 0");
    if (!(opt.min_portal_width >= 0.0) || !std::isfinite(opt.min_portal_width))
        throw invalid_input("reeb_slicing: min_portal_width must be finite and >= 0");
    const double W = ex.width();
    reeb_result r;
    r.pixel = opt.pixel > 0.0 ? opt.pixel : std::max(W, ex.height()) / 1024.0;
    const double fx = std::ceil(W / r.pixel), fy = std::ceil(ex.height() / r.pixel);
    if (!(fx * fy <= static_cast<double>(opt.max_pixels)) || fx > 1e9 || fy > 1e9)
        throw invalid_input("reeb_slicing: raster of " + std::to_string(fx) + " x " + std::to_string(fy) +
                            " pixels exceeds max_pixels = " + std::to_string(opt.max_pixels));
    const int nx = static_cast<int>(fx), ny = static_cast<int>(fy);
    const auto runs = detail::column_runs(ex, r.pixel, nx, ny);
    // Only interior column boundaries: runs starting or stopping at the exemplar's two ends are the
    // band's own cut (portals there), not a topology change of the pattern.
    for (int i = 1; i < nx; ++i)
        if (detail::topology_changes(runs[static_cast<std::size_t>(i - 1)], runs[static_cast<std::size_t>(i)]))
            r.events.push_back(ex.bounds.lo.x + i * r.pixel);
    const double d = opt.group_distance > 0.0 ? opt.group_distance : opt.group_fraction * W;
    std::vector<std::pair<std::size_t, std::size_t>> groups;  // [first, last) event index ranges
    for (std::size_t i = 0; i < r.events.size();) {
        std::size_t k = i + 1;
        while (k < r.events.size() && r.events[k] - r.events[k - 1] <= d) ++k;
        groups.emplace_back(i, k);
        i = k;
    }
    const auto sum_of = [&](std::size_t a, std::size_t b, double shift) {  // events a..b-1, shifted
        double sum = 0.0;
        for (std::size_t e = a; e < b; ++e) sum += r.events[e] + shift;
        return sum;
    };
    // A band of separate motifs begins and ends in empty columns; being periodic (data/vector/
    // convention), its last and first events are neighbours across the seam, one gap apart. When
    // they group, that group's attacher lies near the band's ends (once at each), so the end cuts
    // fall where the inner ones do (e.g. mid-motif) and the end pieces are halves of an inner
    // piece, not longer or shorter ones that no sequence of natural length can use.
    const bool empty_ends = nx > 1 && runs.front().empty() && runs.back().empty();
    if (empty_ends && groups.size() >= 2 && (r.events.front() - ex.bounds.lo.x) + (ex.bounds.hi.x - r.events.back()) <= d) {
        const auto [a0, b0] = groups.front();
        const auto [a1, b1] = groups.back();
        const double seam = (sum_of(a1, b1, -W) + sum_of(a0, b0, 0.0)) / static_cast<double>((b1 - a1) + (b0 - a0));
        r.attachers.push_back(seam);
        for (std::size_t g = 1; g + 1 < groups.size(); ++g)
            r.attachers.push_back(sum_of(groups[g].first, groups[g].second, 0.0) / static_cast<double>(groups[g].second - groups[g].first));
        r.attachers.push_back(seam + W);
    } else {
        for (const auto& [a, b] : groups) r.attachers.push_back(sum_of(a, b, 0.0) / static_cast<double>(b - a));
    }
    std::vector<double> cuts;
    for (std::size_t i = 0; i + 1 < r.attachers.size(); ++i) {
        const double c = 0.5 * (r.attachers[i] + r.attachers[i + 1]);
        if (c > ex.bounds.lo.x && c < ex.bounds.hi.x) cuts.push_back(c);
    }
    r.cuts = filter_thin_cuts(ex, cuts, opt.min_portal_width);
    return r;
}

}  // namespace fabsynth::vector_pattern
