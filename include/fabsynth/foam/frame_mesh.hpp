// SPDX-License-Identifier: MIT
#pragma once
/// @file frame_mesh.hpp  A triangle mesh of a framed foam (frame.hpp) inside a box, by marching
/// cubes (geometry/marching_cubes.hpp: marching tetrahedra, watertight) of framed_foam::implicit
/// sampled on a regular grid. For previews and small parts: the cost is one edge-distance query per
/// sample, and the mesh is only as fine as the sample spacing (beams thinner than about two samples
/// break up); the printable output is the slice stack.
///
/// Usage:
///   fabsynth::triangle_mesh m = fabsynth::foam::framed_foam_mesh(obj, {{15, 9, 11}, {19, 13, 15}}, 0.1);
#include <algorithm>
#include <string>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/frame.hpp"
#include "fabsynth/geometry/marching_cubes.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth::foam {

/// Most grid samples framed_foam_mesh accepts.
inline constexpr double max_frame_mesh_samples = 2e8;

/// Closed mesh of the solid of `obj` inside box `b` (mm), sampled every `voxel` mm: samples at
/// b.lo - voxel + k voxel, one ring of samples outside b set to +voxel (outside), so the mesh is
/// closed along the box faces. The edge search reaches min(cell, max radius + 2 voxel) (see
/// framed_foam::implicit). Throws invalid_input for a non-finite or empty box, voxel <= 0, or more
/// than max_frame_mesh_samples samples.
template <class Foam>
[[nodiscard]] triangle_mesh framed_foam_mesh(const framed_foam<Foam>& obj, const box3& b, double voxel) {
    require_positive(voxel, "foam mesh voxel size");
    if (!all_finite(b.lo) || !all_finite(b.hi) || b.empty()) throw invalid_input("foam mesh: box is empty or not finite");
    const ivec3 dims = ivec3(glm::ceil(b.size() / voxel)) + 3;  // one outside sample per side
    if (double(dims.x) * dims.y * dims.z > max_frame_mesh_samples)
        throw invalid_input("foam mesh: " + std::to_string(double(dims.x) * dims.y * dims.z) +
                            " samples exceed the limit of 2e8; use a smaller box or a larger voxel");
    const vec3 origin = b.lo - vec3(voxel);
    const Foam& foam = obj.foam();
    const double reach = std::min(foam.options().cell, foam.max_radius() + 2 * voxel);
    auto g = [&](ivec3 p) -> double {
        if (glm::any(glm::equal(p, ivec3(0))) || glm::any(glm::equal(p, dims - 1))) return voxel;
        const vec3 q = origin + vec3(p) * voxel;
        if (!b.contains(q)) return voxel;
        return obj.implicit(q, reach);
    };
    return marching_cubes(g, dims, origin, vec3(voxel));
}

}  // namespace fabsynth::foam
