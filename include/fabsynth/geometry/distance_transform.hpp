// SPDX-License-Identifier: MIT
#pragma once
/// @file distance_transform.hpp  Exact Euclidean distance transform of a binary grid in 1, 2 or 3
/// dimensions (the feature-distance channel of an exemplar, structurally-sound-patterns.md sec. 3;
/// distances to a shell when thickening it, sec. 6.2.1).
///
/// Method: P. F. Felzenszwalb & D. P. Huttenlocher, "Distance transforms of sampled functions",
/// Theory of Computing 8 (2012): the squared distance is separable, and each 1D pass is the lower
/// envelope of parabolas, O(n) per line. Exact in integer arithmetic (squared distances in cells^2
/// are integers up to 2^53); lines of each pass run in parallel, so results do not depend on the
/// thread count. Cost O(N) for N cells, memory one double per cell plus one line per thread.
///
/// Grid layout: cells[i + nx (j + ny k)] for dims (nx, ny, nz) (unused trailing dims = 1).
///
/// Usage:
///   std::vector<double> d2 = fabsynth::squared_distance_transform({w, h, 1}, is_feature);
///   // d2[i] = squared distance [cells^2] from cell i to the nearest cell with is_feature true
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"

namespace fabsynth {

namespace detail {

/// In place: f[q] <- min_p (f[p] + (q - p)^2) along one line of n samples (stride apart), with
/// f = +inf where there is no feature. v, z: scratch of n and n + 1 entries.
inline void distance_transform_line(double* f, std::size_t n, std::size_t stride, std::vector<double>& line, std::vector<std::size_t>& v,
                                    std::vector<double>& z) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    line.resize(n), v.resize(n), z.resize(n + 1);
    for (std::size_t q = 0; q < n; ++q) line[q] = f[q * stride];
    std::size_t k = 0;
    bool any = false;
    for (std::size_t q = 0; q < n; ++q) {
        if (line[q] == inf) continue;
        if (!any) {
            v[0] = q, z[0] = -inf, z[1] = inf, any = true;
            continue;
        }
        const auto qd = static_cast<double>(q);
        // Where the parabola from q overtakes the envelope's rightmost one; z[0] = -inf ends the loop.
        double s;
        for (;;) {
            const auto p = static_cast<double>(v[k]);
            s = ((line[q] + qd * qd) - (line[v[k]] + p * p)) / (2.0 * (qd - p));
            if (s > z[k]) break;
            --k;
        }
        ++k;
        v[k] = q, z[k] = s, z[k + 1] = inf;
    }
    if (!any) return;  // no feature on this line: stays +inf
    k = 0;
    for (std::size_t q = 0; q < n; ++q) {
        const auto qd = static_cast<double>(q);
        while (z[k + 1] < qd) ++k;
        const auto d = qd - static_cast<double>(v[k]);
        f[q * stride] = d * d + line[v[k]];
    }
}

}  // namespace detail

/// Squared Euclidean distance [cells^2] from every cell to the nearest feature cell (feature[i]
/// true; distance 0 there). dims: (nx, ny, nz), each >= 1. Without any feature every entry is
/// +infinity. Throws invalid_input if feature.size() != nx * ny * nz.
[[nodiscard]] inline std::vector<double> squared_distance_transform(const std::array<std::size_t, 3>& dims, const std::vector<bool>& feature) {
    const std::size_t nx = dims[0], ny = dims[1], nz = dims[2];
    if (nx == 0 || ny == 0 || nz == 0 || feature.size() != nx * ny * nz)
        throw invalid_input("squared_distance_transform: " + std::to_string(feature.size()) + " cells for a " + std::to_string(nx) + " x " +
                            std::to_string(ny) + " x " + std::to_string(nz) + " grid");
    std::vector<double> f(feature.size());
    for (std::size_t i = 0; i < f.size(); ++i) f[i] = feature[i] ? 0.0 : std::numeric_limits<double>::infinity();
    // One pass per axis; the lines of a pass are independent.
    const std::array<std::size_t, 3> stride = {1, nx, nx * ny};
    for (int axis = 0; axis < 3; ++axis) {
        const std::size_t n = dims[static_cast<std::size_t>(axis)];
        if (n == 1) continue;
        const std::size_t lines = f.size() / n;
        parallel_for(0, lines, [&](std::size_t l) {
            thread_local std::vector<double> line, z;
            thread_local std::vector<std::size_t> v;
            // Line l: the cell coordinates other than `axis`, in storage order.
            std::size_t start;
            if (axis == 0) start = l * nx;
            else if (axis == 1) start = (l % nx) + nx * ny * (l / nx);
            else start = l;
            detail::distance_transform_line(f.data() + start, n, stride[static_cast<std::size_t>(axis)], line, v, z);
        }, {.grain = 64});
    }
    return f;
}

}  // namespace fabsynth
