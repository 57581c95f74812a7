// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh_check.hpp  Shared checks for mesh writers.
#include <cmath>
#include <limits>
#include <string>

#include "fabsynth/core/error.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth::io::detail {

/// Throws invalid_input (naming the output file) unless the mesh has finite vertices, valid
/// face indices and fewer than 2^31 vertices (so every format can index them).
inline void check_mesh_for_writing(const triangle_mesh& m, const std::string& file) {
    if (m.vertices.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
        throw invalid_input(file + ": mesh has too many vertices to write (" + std::to_string(m.vertices.size()) + ")");
    validate(m, (file + ": mesh to write").c_str());
}

/// Binary formats store float32: a coordinate beyond float range would become inf, so refuse it.
inline void check_fits_float(const triangle_mesh& m, const std::string& file, const char* format) {
    for (const vec3& v : m.vertices)
        for (int a = 0; a < 3; ++a)
            if (!std::isfinite(static_cast<float>(v[a])))
                throw invalid_input(file + ": coordinate " + std::to_string(v[a]) + " does not fit a float (" + format + ")");
}

}  // namespace fabsynth::io::detail
