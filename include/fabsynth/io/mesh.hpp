// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh.hpp  Triangle mesh files by extension: .obj, .stl, .ply (case-insensitive).
///
/// Usage:
///   auto m = fabsynth::io::read_mesh(FABSYNTH_DATA_DIR "/meshes/spot.stl");
///   fabsynth::io::write_mesh("out.ply", m);   // binary PLY
#include <filesystem>
#include <string>

#include "fabsynth/core/error.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/io/mesh_obj.hpp"
#include "fabsynth/io/mesh_ply.hpp"
#include "fabsynth/io/mesh_stl.hpp"

namespace fabsynth::io {

namespace detail {
/// Lower-case extension including the dot ("" if none).
inline std::string lower_extension(const std::filesystem::path& p) {
    std::string e = p.extension().string();
    for (char& ch : e)
        if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
    return e;
}
}  // namespace detail

/// Reads a triangle mesh, choosing the format by extension. Throws invalid_input for an
/// unknown extension and io_error for unreadable or malformed files.
inline triangle_mesh read_mesh(const std::filesystem::path& path) {
    const std::string ext = detail::lower_extension(path);
    if (ext == ".obj") return read_obj(path);
    if (ext == ".stl") return read_stl(path);
    if (ext == ".ply") return read_ply(path);
    throw invalid_input(path.string() + ": unknown mesh extension '" + ext + "' (expected .obj, .stl or .ply)");
}

/// Writes a triangle mesh by extension: .obj (exact decimals), .stl and .ply (binary float32).
/// Atomic. Throws invalid_input for an unknown extension or an invalid mesh.
inline void write_mesh(const std::filesystem::path& path, const triangle_mesh& m) {
    const std::string ext = detail::lower_extension(path);
    if (ext == ".obj") return write_obj(path, m);
    if (ext == ".stl") return write_stl(path, m, encoding::binary);
    if (ext == ".ply") return write_ply(path, m, encoding::binary);
    throw invalid_input(path.string() + ": unknown mesh extension '" + ext + "' (expected .obj, .stl or .ply)");
}

}  // namespace fabsynth::io
