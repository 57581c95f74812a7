// SPDX-License-Identifier: MIT
#pragma once
/// @file shell.hpp  The voxel shell of a surface and its multi-resolution pyramid
/// (structurally-sound-patterns.md §3 "Pre-processing", §4: V^0 .. V^L).
///
/// Usage:
///   auto shell = fabsynth::surface_pattern::make_shell(mesh, {.size_mm = 100, .resolution = 256});
///   auto pyr = fabsynth::surface_pattern::build_shell_pyramid(shell, 8);   // levels 0 (finest) .. 7
///   pyr.levels[3].voxels[i];   // coordinates on level 3's grid (fine coordinates >> 3)
///   pyr.levels[3].parent[i];   // index of its parent on level 4
///
/// The mesh is scaled uniformly so that its longest side is `size_mm` (geometry/mesh.hpp
/// fit_to_size) and voxelized conservatively (voxel/voxelize.hpp: every voxel whose box meets
/// the surface, with the unit normal averaged over the surface inside it). Voxels that only touch
/// the surface along an edge or at a corner (zero enclosed area) carry no normal and are dropped, so
/// every shell voxel encloses a piece of surface, as §3 assumes. Level l + 1 holds the parents
/// p >> 1 of level l's voxels; a parent's normal is the area-weighted mean of its children's
/// normals (the normal averaged over the surface it encloses), or its largest child's normal where
/// opposite sheets cancel. Voxels of each level are sorted by grid index (x fastest), so everything
/// built here is deterministic. Memory O(shell voxels) plus O(ny * nz) row offsets per level,
/// never O(grid voxels).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/huge_pages.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/voxel/grid.hpp"
#include "fabsynth/voxel/pyramid.hpp"
#include "fabsynth/voxel/voxelize.hpp"

namespace fabsynth::surface_pattern {

/// How to voxelize the surface.
struct shell_options {
    double size_mm = 0;                        ///< longest side of the scaled mesh (mm, > 0)
    int resolution = 256;                      ///< voxels along that side (paper: 256; 512 for large models), 4..4096
    int padding = 2;                           ///< empty voxels around the mesh on every side
    double max_memory_bytes = 16.0 * (1ull << 30);  ///< refuse shells estimated to need more (before voxelizing)
};

/// The finest level: surface voxels of the scaled mesh.
struct surface_shell {
    grid_geometry geometry;      ///< the voxel grid (mm), cubic voxels
    triangle_mesh mesh;          ///< the input mesh after scaling (mm), the one that was voxelized
    std::vector<ivec3> voxels;   ///< shell voxels, sorted by grid index
    std::vector<vec3> normals;   ///< unit normal per voxel (outward for an outward-oriented mesh)
    std::vector<double> area;    ///< surface area inside each voxel (mm^2, > 0)
    [[nodiscard]] std::size_t size() const noexcept { return voxels.size(); }
};

/// Bytes per shell voxel the synthesis needs at most: the pyramid (position, normal, area, parent,
/// row offsets), 5x5x5 neighbour lists (~40 neighbours x 5 bytes), labels, colour caches and the
/// voxelizer's hash map, rounded up. Used to refuse impossible requests before any allocation.
inline constexpr double shell_bytes_per_voxel = 640;

/// Estimated number of shell voxels of a mesh of `area_mm2` on voxels of `spacing` mm: a
/// conservative shell is at most about 3 voxels per spacing^2 of surface (a plane at 45 degrees to two
/// axes meets sqrt(2) voxels per column, a general one up to sqrt(3) plus corner contacts).
[[nodiscard]] inline double estimated_shell_voxels(double area_mm2, double spacing) noexcept { return 3.0 * area_mm2 / (spacing * spacing); }

/// Scales `mesh` to opt.size_mm and voxelizes its surface (see the file comment). Any triangle soup
/// is accepted: open and non-manifold meshes voxelize like closed ones (their normals then follow the
/// local face orientation, and thickening goes against them); a closed mesh with negative signed
/// volume (oriented inward) is turned outward first. Throws invalid_input for an empty mesh, non-finite vertices, bad face
/// indices, a mesh without extent, size or resolution out of range, a shell estimated above
/// opt.max_memory_bytes (naming the estimate), or a shell with no voxel.
[[nodiscard]] inline surface_shell make_shell(const triangle_mesh& mesh, const shell_options& opt) {
    if (mesh.empty()) throw invalid_input("surface shell: the mesh has no faces");
    validate(mesh, "surface shell: mesh");
    if (!(std::isfinite(opt.size_mm) && opt.size_mm > 0))
        throw invalid_input("surface shell: size must be finite and > 0 mm, got " + std::to_string(opt.size_mm));
    if (opt.resolution < 4 || opt.resolution > 4096)
        throw invalid_input("surface shell: resolution must be in [4, 4096], got " + std::to_string(opt.resolution));
    if (opt.padding < 0 || opt.padding > 64) throw invalid_input("surface shell: padding must be in [0, 64], got " + std::to_string(opt.padding));
    surface_shell s;
    s.mesh = mesh;
    fit_to_size(s.mesh, opt.size_mm);
    // A closed mesh oriented inward would thicken outward: turn it outward (open meshes keep theirs).
    if (is_watertight(s.mesh) && signed_volume(s.mesh) < 0)
        for (auto& f : s.mesh.faces) std::swap(f[1], f[2]);
    s.geometry = fit_grid(bounding_box(s.mesh), opt.resolution, opt.padding);
    const double estimate = estimated_shell_voxels(surface_area(s.mesh), s.geometry.spacing.x) * shell_bytes_per_voxel;
    if (estimate > opt.max_memory_bytes) {
        char msg[256];
        std::snprintf(msg, sizeof msg, "surface shell: resolution %d on this surface needs about %.1f GiB, more than the limit of %.3g GiB",
                      opt.resolution, estimate / double(1ull << 30), opt.max_memory_bytes / double(1ull << 30));
        throw invalid_input(msg);
    }
    const shell_grid grid = voxelize_surface(s.mesh, s.geometry);
    for (std::uint64_t key : grid.storage().sorted_keys()) {
        const shell_voxel v = grid.storage().get(key);
        if (!(v.area > 0) || v.normal == vec3(0)) continue;
        s.voxels.push_back(s.geometry.coord(key));
        s.normals.push_back(v.normal);
        s.area.push_back(v.area);
    }
    if (s.voxels.empty()) throw invalid_input("surface shell: the surface covers no voxel (degenerate mesh?)");
    return s;
}

/// One level of the pyramid.
struct shell_level {
    int level = 0;                        ///< 0 = finest
    grid_geometry geometry;               ///< this level's grid: dims ceil(dims_0 / 2^l), spacing 2^l h
    std::vector<ivec3> voxels;            ///< voxel coordinates on this level's grid, sorted by grid index
    std::vector<vec3> normals;            ///< unit normals
    std::vector<double> area;             ///< enclosed surface area (mm^2)
    std::vector<std::uint32_t> parent;    ///< index of the parent on level + 1 (empty on the coarsest level)
    std::vector<std::uint32_t> child_offset;  ///< children of voxel i: child_index[child_offset[i] .. child_offset[i+1]) (empty on level 0)
    std::vector<std::uint32_t> child_index;   ///< indices on level - 1
    std::vector<std::uint32_t> row_offset;    ///< voxels of row (y, z) are [row_offset[z*ny+y], row_offset[z*ny+y+1])

    [[nodiscard]] std::size_t size() const noexcept { return voxels.size(); }
    /// Centre of voxel i (mm).
    [[nodiscard]] vec3 center(std::size_t i) const noexcept { return geometry.center(voxels[i]); }
    /// Index of the voxel at p on this level, or -1 if p is not a shell voxel.
    [[nodiscard]] std::int64_t find(const ivec3& p) const noexcept {
        const ivec3& d = geometry.dims;
        if (p.x < 0 || p.y < 0 || p.z < 0 || p.x >= d.x || p.y >= d.y || p.z >= d.z) return -1;
        const std::size_t row = static_cast<std::size_t>(p.z) * static_cast<std::size_t>(d.y) + static_cast<std::size_t>(p.y);
        auto first = voxels.begin() + row_offset[row], last = voxels.begin() + row_offset[row + 1];
        auto it = std::lower_bound(first, last, p.x, [](const ivec3& a, int x) { return a.x < x; });
        return it != last && it->x == p.x ? static_cast<std::int64_t>(it - voxels.begin()) : -1;
    }
};

/// V^0 .. V^L.
struct shell_pyramid {
    std::vector<shell_level> levels;
    [[nodiscard]] int coarsest() const noexcept { return static_cast<int>(levels.size()) - 1; }
};

/// Default number of levels for a resolution: ceil(log2 N), so the coarsest voxel spans half the
/// grid (256 -> 8 levels, 512 -> 9: the paper's settings, §6.1).
[[nodiscard]] inline int default_levels(int resolution) noexcept {
    int l = 0;
    while ((1 << l) < resolution) ++l;
    return std::max(1, l);
}

namespace detail {

inline void index_rows(shell_level& lv) {
    const ivec3& d = lv.geometry.dims;
    lv.row_offset.assign(static_cast<std::size_t>(d.y) * static_cast<std::size_t>(d.z) + 1, 0);
    for (const ivec3& p : lv.voxels) ++lv.row_offset[static_cast<std::size_t>(p.z) * static_cast<std::size_t>(d.y) + static_cast<std::size_t>(p.y) + 1];
    for (std::size_t r = 1; r < lv.row_offset.size(); ++r) lv.row_offset[r] += lv.row_offset[r - 1];
}

/// Level l + 1 from level l: unique parents in index order, area-weighted normals, links.
inline shell_level coarsen(shell_level& fine) {
    shell_level c;
    c.level = fine.level + 1;
    c.geometry = fine.geometry;
    c.geometry.dims = (fine.geometry.dims + 1) / 2;
    c.geometry.spacing = fine.geometry.spacing * 2.0;
    const std::size_t n = fine.size();
    // parent keys in the coarse grid's index order; sorting (key, child) pairs keeps it deterministic
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
    for (std::size_t i = 0; i < n; ++i) keyed[i] = {c.geometry.index(parent_voxel(fine.voxels[i])), static_cast<std::uint32_t>(i)};
    std::sort(keyed.begin(), keyed.end());
    fine.parent.assign(n, 0);
    c.child_index.resize(n);
    std::vector<vec3> weighted;
    for (std::size_t k = 0; k < n; ++k) {
        const auto [key, child] = keyed[k];
        if (k == 0 || key != keyed[k - 1].first) {
            c.voxels.push_back(c.geometry.coord(key));
            c.child_offset.push_back(static_cast<std::uint32_t>(k));
            weighted.push_back(vec3(0));
            c.area.push_back(0);
            c.normals.push_back(vec3(0));
        }
        const std::size_t p = c.voxels.size() - 1;
        fine.parent[child] = static_cast<std::uint32_t>(p);
        c.child_index[k] = child;
        weighted[p] += fine.normals[child] * fine.area[child];
        if (fine.area[child] > c.area[p] || c.normals[p] == vec3(0)) c.normals[p] = fine.normals[child];  // largest child so far
        c.area[p] += fine.area[child];
    }
    c.child_offset.push_back(static_cast<std::uint32_t>(n));
    // Children were grouped by parent with the larger-area child winning as fallback; use the mean where it is defined.
    for (std::size_t p = 0; p < c.size(); ++p) {
        const double len = glm::length(weighted[p]);
        if (len > 1e-9 * c.area[p]) c.normals[p] = weighted[p] / len;
    }
    index_rows(c);
    return c;
}

}  // namespace detail

/// Pyramid with `levels` levels (1 .. 16; default_levels(resolution) is the paper's choice).
/// Throws invalid_input for an empty shell or a level count out of range.
[[nodiscard]] inline shell_pyramid build_shell_pyramid(const surface_shell& s, int levels) {
    if (s.voxels.empty()) throw invalid_input("shell pyramid: the shell has no voxel");
    if (levels < 1 || levels > 16) throw invalid_input("shell pyramid: levels must be in [1, 16], got " + std::to_string(levels));
    shell_pyramid pyr;
    shell_level l0;
    l0.geometry = s.geometry;
    l0.voxels = s.voxels;
    l0.normals = s.normals;
    l0.area = s.area;
    detail::index_rows(l0);
    pyr.levels.push_back(std::move(l0));
    while (static_cast<int>(pyr.levels.size()) < levels) pyr.levels.push_back(detail::coarsen(pyr.levels.back()));
    return pyr;
}

/// Neighbours of every voxel of a level inside the (2r+1)^3 box around it (the 5x5x5 neighbourhood
/// N(v) of §4.2 for r = 2), the voxel itself excluded, as CSR lists ordered farthest offset first
/// (ties by code); `code` is the offset's index (dx + r) + (2r+1) ((dy + r) + (2r+1) (dz + r)).
struct shell_neighbourhood {
    int radius = 2;
    std::vector<std::uint32_t> offset;  ///< size + 1
    std::vector<std::uint32_t> index;   ///< neighbour voxel indices
    std::vector<std::uint8_t> code;     ///< offset code per neighbour
    [[nodiscard]] std::uint32_t count(std::size_t v) const noexcept { return offset[v + 1] - offset[v]; }
};

/// Builds the neighbour lists of a level (parallel over groups of rows, deterministic). radius 1..3.
/// Each row of voxels is merged with its (2r+1)^2 neighbouring rows by pointers that only move
/// forward, so the cost is O(voxels x (2r+1)^2) without searches; a counting pass sizes the lists,
/// which are advised as huge pages before they are filled (first-touch faults dominate otherwise).
[[nodiscard]] inline shell_neighbourhood build_neighbourhood(const shell_level& lv, int radius = 2) {
    if (radius < 1 || radius > 3) throw invalid_input("neighbourhood radius must be in [1, 3], got " + std::to_string(radius));
    const std::size_t n = lv.size();
    const int side = 2 * radius + 1;
    const ivec3& d = lv.geometry.dims;
    const std::size_t rows = static_cast<std::size_t>(d.y) * static_cast<std::size_t>(d.z);
    constexpr std::size_t rows_per_task = 256;
    const std::size_t tasks = (rows + rows_per_task - 1) / rows_per_task;
    // scan(t, emit): emit(v, w, code) for every voxel v of task t's rows and its neighbours w, in order
    auto scan = [&](std::size_t t, auto&& emit) {
        std::vector<std::uint32_t> ptr(static_cast<std::size_t>(side * side)), stop(static_cast<std::size_t>(side * side));
        std::vector<int> code_base(static_cast<std::size_t>(side * side));
        for (std::size_t row = t * rows_per_task; row < std::min(rows, (t + 1) * rows_per_task); ++row) {
            const std::uint32_t first = lv.row_offset[row], last = lv.row_offset[row + 1];
            if (first == last) continue;
            const int y = static_cast<int>(row % static_cast<std::size_t>(d.y)), z = static_cast<int>(row / static_cast<std::size_t>(d.y));
            int m = 0;  // neighbouring rows in increasing (z, y) order, i.e. increasing voxel index
            for (int dz = -radius; dz <= radius; ++dz)
                for (int dy = -radius; dy <= radius; ++dy) {
                    const int yy = y + dy, zz = z + dz;
                    if (yy < 0 || yy >= d.y || zz < 0 || zz >= d.z) continue;
                    const std::size_t r = static_cast<std::size_t>(zz) * static_cast<std::size_t>(d.y) + static_cast<std::size_t>(yy);
                    ptr[static_cast<std::size_t>(m)] = lv.row_offset[r];
                    stop[static_cast<std::size_t>(m)] = lv.row_offset[r + 1];
                    code_base[static_cast<std::size_t>(m)] = side * ((dy + radius) + side * (dz + radius));
                    ++m;
                }
            for (std::uint32_t v = first; v < last; ++v) {
                const int x = lv.voxels[v].x;
                for (int k = 0; k < m; ++k) {
                    std::uint32_t& p = ptr[static_cast<std::size_t>(k)];
                    const std::uint32_t e = stop[static_cast<std::size_t>(k)];
                    while (p < e && lv.voxels[p].x < x - radius) ++p;
                    for (std::uint32_t q = p; q < e && lv.voxels[q].x <= x + radius; ++q)
                        if (q != v) emit(v, q, lv.voxels[q].x - x + radius + code_base[static_cast<std::size_t>(k)]);
                }
            }
        }
    };
    shell_neighbourhood nb;
    nb.radius = radius;
    nb.offset.assign(n + 1, 0);
    parallel_for(0, tasks, [&](std::size_t t) { scan(t, [&](std::uint32_t v, std::uint32_t, int) { ++nb.offset[v + 1]; }); });
    for (std::size_t v = 0; v < n; ++v) nb.offset[v + 1] += nb.offset[v];
    const std::size_t total = nb.offset[n];
    nb.index.reserve(total);
    nb.code.reserve(total);
    advise_huge_pages(nb.index.data(), total * sizeof(std::uint32_t));
    advise_huge_pages(nb.code.data(), total);
    nb.index.resize(total);
    nb.code.resize(total);
    parallel_for(0, tasks, [&](std::size_t t) {
        std::uint32_t cur = std::numeric_limits<std::uint32_t>::max(), k = 0;
        scan(t, [&](std::uint32_t v, std::uint32_t w, int code) {
            if (v != cur) cur = v, k = nb.offset[v];
            nb.index[k] = w;
            nb.code[k] = static_cast<std::uint8_t>(code);
            ++k;
        });
    });
    // Reorder each list farthest offset first (ties by offset code): the synthesizer's branch and
    // bound stops sooner when the neighbours most likely to disagree with a candidate come first.
    const int codes = side * side * side;
    std::vector<int> order(static_cast<std::size_t>(codes));
    for (int c = 0; c < codes; ++c) order[static_cast<std::size_t>(c)] = c;
    auto dist2 = [&](int c) {
        const int dx = c % side - radius, dy = (c / side) % side - radius, dz = c / (side * side) - radius;
        return dx * dx + dy * dy + dz * dz;
    };
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return dist2(a) > dist2(b); });
    parallel_for(0, n, [&](std::size_t v) {
        std::uint32_t slot[343];
        bool present[343] = {};
        const std::uint32_t a = nb.offset[v], b = nb.offset[v + 1];
        for (std::uint32_t k = a; k < b; ++k) slot[nb.code[k]] = nb.index[k], present[nb.code[k]] = true;
        std::uint32_t k = a;
        for (int c : order)
            if (present[c]) nb.index[k] = slot[c], nb.code[k] = static_cast<std::uint8_t>(c), ++k;
    }, {.grain = 1024});
    return nb;
}

}  // namespace fabsynth::surface_pattern
