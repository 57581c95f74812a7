// SPDX-License-Identifier: MIT
#pragma once
/// @file offset.hpp  A printable solid from a thin surface: the set of points within half a
/// thickness of a triangle mesh (open or closed), meshed as a closed, consistently oriented
/// triangle mesh. This is §6.2 of filigree-synthesis.md with eq. 9 (the point q of the surface
/// nearest to p is inflated in all directions, also at open boundaries):
///   p is inside  iff  |p - q|^2 - tau(q)^2 / 4 <= 0,   q = the closest point of M_b to p,
/// with tau(q) interpolated barycentrically from per-vertex thicknesses.
///
/// Usage:
///   fabsynth::triangle_mesh solid = fabsynth::thicken_surface(baked, 1.2, {.cell = 0.1});   // mm
///   fabsynth::triangle_mesh graded = fabsynth::thicken_surface(baked, per_vertex_tau, {.cell = 0.1});
///
/// Method and why: the paper meshes F = 0 by Poisson reconstruction; here the field
/// d(p) - tau(q) / 2 (d = distance to M_b by geometry/distance.hpp's BVH, searched only within
/// tau_max / 2 + 2 cells, farther points are plain outside) is sampled on a grid of cell `cell`
/// over M_b's box grown by tau_max / 2 + 2 cells and meshed by geometry/marching_cubes.hpp (marching
/// tetrahedra). Both are already in the tree, the result is watertight by construction (the grid
/// border is outside), and the error is the grid's: surface within about one cell of the exact
/// offset, volume converging as O(cell^2). A surface thinner than about two cells can fall between
/// the samples: pick cell <= tau_min / 4. The sign-free distance makes it work on open and
/// non-manifold surfaces alike (no inside/outside of M_b is needed). The level set of a closed
/// surface has an inner shell around the void it encloses (and a folded one tiny voids); by
/// default such cavities are filled (options), so the result is one shell per solid piece.
///
/// Cost: one bounded closest-point query per grid point, O(N log F) for N grid points; the grid
/// size is checked against `max_samples` before any work.
///
/// Errors: invalid_input naming the input for an empty or invalid mesh, a thickness that is not
/// finite and > 0 (per vertex: a count that is not the vertex count), a cell that is not finite and
/// > 0; no_solution when the grid would exceed max_samples (the message gives the count).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/marching_cubes.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"

namespace fabsynth {

struct surface_offset_options {
    double cell = 0.1;                    ///< grid spacing, mm (<= tau_min / 4 recommended)
    double max_samples = 4e8;             ///< refuse grids with more points than this
    /// Fill enclosed voids: drop the level set's inner shells (negative signed volume,
    /// geometry/mesh_topology.hpp's without_cavities). A closed or folded surface thickened
    /// encloses the space it wraps; a printed part could not drain such a void.
    bool fill_cavities = true;
};

namespace detail::offset {

[[nodiscard]] inline triangle_mesh thicken(const triangle_mesh& mb, std::span<const double> tau, const surface_offset_options& opt) {
    validate(mb, "thicken_surface input mesh");
    if (mb.faces.empty()) throw invalid_input("thicken_surface: the surface has no faces");
    if (!(std::isfinite(opt.cell) && opt.cell > 0)) throw invalid_input("thicken_surface: cell must be finite and > 0 mm");
    double tau_max = 0;
    for (std::size_t v = 0; v < tau.size(); ++v) {
        if (!(std::isfinite(tau[v]) && tau[v] > 0))
            throw invalid_input("thicken_surface: thickness at vertex " + std::to_string(v) + " must be finite and > 0 mm");
        tau_max = std::max(tau_max, tau[v]);
    }
    const double band = 0.5 * tau_max + 2 * opt.cell;
    box3 box = bounding_box(mb);
    box = box3(box.lo - vec3(band), box.hi + vec3(band));
    const ivec3 dims = ivec3(glm::ceil(box.size() / opt.cell)) + 1;
    const double samples = static_cast<double>(dims.x) * dims.y * dims.z;
    if (!(samples <= opt.max_samples))
        throw no_solution("thicken_surface: a grid of " + std::to_string(dims.x) + " x " + std::to_string(dims.y) + " x " + std::to_string(dims.z) +
                          " points exceeds max_samples = " + std::to_string(opt.max_samples) + " (a larger cell)");
    const mesh_distance md(mb);
    const bool constant = tau.size() == 1;
    auto f = [&](ivec3 ip) -> double {
        const vec3 p = box.lo + opt.cell * vec3(ip);
        const mesh_closest c = md.closest(p, band);
        if (!c.found()) return band;  // outside
        double t = tau[0];
        if (!constant) {
            const auto& fc = mb.faces[c.face];
            const vec3 b = barycentric(c.point, mb.vertices[fc[0]], mb.vertices[fc[1]], mb.vertices[fc[2]]);
            t = b.x * tau[fc[0]] + b.y * tau[fc[1]] + b.z * tau[fc[2]];
        }
        return std::sqrt(c.dist2) - 0.5 * t;
    };
    triangle_mesh solid = marching_cubes(f, dims, box.lo, vec3(opt.cell));
    return opt.fill_cavities ? without_cavities(solid) : solid;
}

}  // namespace detail::offset

/// The solid within tau / 2 (mm, constant) of the surface mb (see the file comment).
[[nodiscard]] inline triangle_mesh thicken_surface(const triangle_mesh& mb, double tau, const surface_offset_options& opt = {}) {
    const double t[1] = {tau};
    return detail::offset::thicken(mb, t, opt);
}

/// The same with one thickness per vertex of mb (mm), interpolated over the faces.
[[nodiscard]] inline triangle_mesh thicken_surface(const triangle_mesh& mb, std::span<const double> tau_per_vertex, const surface_offset_options& opt = {}) {
    if (tau_per_vertex.size() != mb.num_vertices())
        throw invalid_input("thicken_surface: " + std::to_string(tau_per_vertex.size()) + " thickness values for " + std::to_string(mb.num_vertices()) +
                            " vertices");
    return detail::offset::thicken(mb, tau_per_vertex, opt);
}

}  // namespace fabsynth
