// SPDX-License-Identifier: MIT
#pragma once
/// @file preview.hpp  Pictures of voxel grids for a person to look at (the tools' PNG previews).
///
/// Usage:
///   fabsynth::image8 a = fabsynth::shell_solid_slices(shell, solid, 4);   // RGB, rows of z-slices
///   fabsynth::image8 b = fabsynth::mid_plane_slices(dims, [&](ivec3 p) { return density(p); });
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>

#include "fabsynth/core/image.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/voxel/grid.hpp"
#include "fabsynth/voxel/voxelize.hpp"

namespace fabsynth {

/// `slices` z-slices evenly spaced through the grid, one row each: the shell coloured by its
/// normal (n + 1) / 2 on the left, the solid voxels light grey on the right, +y up, each voxel
/// drawn as a square of about 200 / max(nx, ny) pixels. RGB; background dark grey.
/// @param shell  surface voxels with normals (voxelize_surface)
/// @param solid  0/1 per voxel on the same grid (voxelize_solid)
/// @param slices number of z-slices (>= 1)
[[nodiscard]] inline image8 shell_solid_slices(const shell_grid& shell, const voxel_grid<std::uint8_t>& solid, int slices) {
    const grid_geometry& g = shell.geometry();
    slices = std::max(1, slices);
    const int scale = std::max(1, 200 / std::max(g.dims.x, g.dims.y));
    const int pw = g.dims.x * scale, ph = g.dims.y * scale, gap = 4;
    image8 img(2 * pw + 3 * gap, slices * (ph + gap) + gap, 3, 40);
    for (int s = 0; s < slices; ++s) {
        const int z = static_cast<int>((s + 1.0) * g.dims.z / (slices + 1.0));
        const int y0 = gap + s * (ph + gap);
        for (int y = 0; y < g.dims.y; ++y)
            for (int x = 0; x < g.dims.x; ++x) {
                const ivec3 p(x, y, z);
                std::uint8_t shell_rgb[3] = {0, 0, 0}, solid_rgb[3] = {0, 0, 0};
                if (shell.storage().is_stored(g.index(p))) {
                    const vec3 n = shell.get(p).normal;
                    for (int c = 0; c < 3; ++c) shell_rgb[c] = static_cast<std::uint8_t>(std::lround(127.5 * (n[c] + 1.0)));
                }
                if (solid.get(p)) solid_rgb[0] = solid_rgb[1] = solid_rgb[2] = 230;
                for (int dy = 0; dy < scale; ++dy)
                    for (int dx = 0; dx < scale; ++dx) {
                        const int py = y0 + (g.dims.y - 1 - y) * scale + dy;  // +y up
                        for (int c = 0; c < 3; ++c) {
                            img.at(gap + x * scale + dx, py, c) = shell_rgb[c];
                            img.at(2 * gap + pw + x * scale + dx, py, c) = solid_rgb[c];
                        }
                    }
            }
    }
    return img;
}

/// The three orthogonal mid-plane slices xy | xz | yz of a scalar field on a voxel grid, side by
/// side with a one-pixel gap, one pixel per voxel, values in [0, 1] as black..white (clamped; NaN black),
/// second axis up. Grey.
/// @param dims  voxel counts (each >= 1)
/// @param value value(ivec3 voxel) -> double
template <class Value>
    requires std::invocable<Value&, ivec3>
[[nodiscard]] image8 mid_plane_slices(ivec3 dims, Value&& value) {
    const ivec3 n = glm::max(dims, ivec3(1));
    const int w = n.x + 1 + n.x + 1 + n.y, h = std::max(n.y, n.z);
    image8 img(w, h, 1, 64);
    auto put = [&](int x, int y, double v) {
        v = std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 0.0;  // NaN draws black
        img.at(x, h - 1 - y) = static_cast<std::uint8_t>(std::lround(255 * v));
    };
    for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) put(i, j, value(ivec3{i, j, n.z / 2}));
    for (int k = 0; k < n.z; ++k)
        for (int i = 0; i < n.x; ++i) put(n.x + 1 + i, k, value(ivec3{i, n.y / 2, k}));
    for (int k = 0; k < n.z; ++k)
        for (int j = 0; j < n.y; ++j) put(2 * n.x + 2 + j, k, value(ivec3{n.x / 2, j, k}));
    return img;
}

}  // namespace fabsynth
