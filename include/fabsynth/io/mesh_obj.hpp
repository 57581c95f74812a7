// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh_obj.hpp  Wavefront OBJ triangle meshes: read (strict) and write (exact).
///
/// Reading keeps `v` positions (extra values such as w or vertex colours are parsed and ignored)
/// and `f` faces; polygons with more than 3 corners are fan-triangulated (v0 v_i v_i+1). Corner
/// references may be `v`, `v/vt`, `v//vn` or `v/vt/vn`; only v is used. Positive indices are
/// 1-based and may point to vertices defined later in the file; negative indices are relative to
/// the vertices defined so far (-1 = last). Texture coordinates, normals, groups, materials,
/// lines, points and unknown statements are skipped. Every vertex is kept, including unreferenced
/// ones, so indices match the file.
///
/// Rejected with io_error "FILE:LINE: ...": empty files or files without faces, unparsable or
/// non-finite coordinates, fewer than 3 coordinates, index 0, indices outside the vertex list,
/// faces with fewer than 3 corners, more than 2^32-1 vertices.
///
/// Usage: `auto m = fabsynth::io::read_obj("bunny.obj"); fabsynth::io::write_obj("out.obj", m);`
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/io/atomic_file.hpp"
#include "fabsynth/io/detail/mesh_check.hpp"
#include "fabsynth/io/detail/read_file.hpp"
#include "fabsynth/io/detail/text.hpp"

namespace fabsynth::io {

/// Parses OBJ text; `name` (usually the file name) prefixes error messages.
inline triangle_mesh parse_obj(std::string_view bytes, std::string_view name) {
    if (bytes.empty()) throw io_error(name, 0, "file is empty");
    if (bytes.starts_with("\xEF\xBB\xBF")) bytes.remove_prefix(3);  // UTF-8 BOM: else line 1 would be skipped
    detail::token_cursor c(bytes, name);
    triangle_mesh m;
    // Positive indices may refer to vertices further down: check those once all are known.
    struct pending {
        std::size_t line;
        std::int64_t index;
    };
    std::vector<pending> forward_refs;
    std::vector<std::int64_t> corners;
    constexpr std::int64_t max_index = std::numeric_limits<std::uint32_t>::max();

    for (;;) {
        const std::string_view kw = c.next();
        if (kw.empty()) break;
        if (kw[0] == '#') {
            c.skip_line();
        } else if (kw == "v") {
            double xyz[3];
            int n = 0;
            for (;;) {
                const std::string_view t = c.next_on_line();
                if (t.empty() || t[0] == '#') break;
                if (n >= 7) c.fail("vertex has more than 7 values");
                const double x = c.finite(t, "vertex coordinate");
                if (n < 3) xyz[n] = x;
                ++n;
            }
            if (n < 3) c.fail(std::string("vertex has ") + std::to_string(n) + " coordinates, expected 3");
            if (static_cast<std::int64_t>(m.vertices.size()) >= max_index) c.fail("more than 2^32-1 vertices");
            m.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
        } else if (kw == "f") {
            corners.clear();
            for (;;) {
                const std::string_view t = c.next_on_line();
                if (t.empty() || t[0] == '#') break;
                const std::string_view v = t.substr(0, t.find('/'));
                std::int64_t idx = c.integer(v, "face vertex index", -max_index, max_index);
                if (idx == 0) c.fail("face vertex index 0 is invalid (OBJ indices start at 1)");
                if (idx < 0) {
                    idx += static_cast<std::int64_t>(m.vertices.size());  // -1 = last vertex so far
                    if (idx < 0)
                        c.fail(std::string("relative face index ") + std::string(v) + " points before the first vertex (only " +
                               std::to_string(m.vertices.size()) + " defined so far)");
                } else {
                    idx -= 1;
                    if (idx >= static_cast<std::int64_t>(m.vertices.size())) forward_refs.push_back({c.line(), idx});
                }
                corners.push_back(idx);
            }
            if (corners.size() < 3) c.fail(std::string("face has ") + std::to_string(corners.size()) + " corners, expected at least 3");
            for (std::size_t i = 1; i + 1 < corners.size(); ++i)
                m.faces.push_back({static_cast<std::uint32_t>(corners[0]), static_cast<std::uint32_t>(corners[i]),
                                   static_cast<std::uint32_t>(corners[i + 1])});
        } else {
            c.skip_line();  // vt, vn, g, o, s, usemtl, mtllib, l, p, ... carry nothing we keep
        }
    }
    for (const pending& p : forward_refs)
        if (p.index >= static_cast<std::int64_t>(m.vertices.size()))
            throw io_error(name, p.line,
                           std::string("face vertex index ") + std::to_string(p.index + 1) + " exceeds the " +
                               std::to_string(m.vertices.size()) + " vertices in the file");
    if (m.faces.empty()) throw io_error(name, 0, std::string("no faces found (") + std::to_string(m.vertices.size()) + " vertices)");
    return m;
}

/// Reads an OBJ file (see file comment for what is accepted).
inline triangle_mesh read_obj(const std::filesystem::path& path) {
    return parse_obj(detail::read_file(path), path.string());
}

/// OBJ text for a mesh: `v x y z` with shortest exact decimals, `f a b c` 1-based.
inline std::string format_obj(const triangle_mesh& m) {
    std::string out = std::string("# fabsynth OBJ: ") + std::to_string(m.vertices.size()) + " vertices, " +
                      std::to_string(m.faces.size()) + " triangles\n";
    out.reserve(out.size() + m.vertices.size() * 40 + m.faces.size() * 24);
    for (const vec3& v : m.vertices) {
        out += "v ";
        detail::append_number(out, v.x);
        out += ' ';
        detail::append_number(out, v.y);
        out += ' ';
        detail::append_number(out, v.z);
        out += '\n';
    }
    for (const auto& f : m.faces) {
        out += 'f';
        for (std::uint32_t i : f) {
            out += ' ';
            detail::append_number(out, static_cast<std::int64_t>(i) + 1);
        }
        out += '\n';
    }
    return out;
}

/// Writes `m` as OBJ (atomically). Doubles are printed so they read back bit-exactly.
/// Throws invalid_input for non-finite vertices or bad indices, io_error if writing fails.
inline void write_obj(const std::filesystem::path& path, const triangle_mesh& m) {
    detail::check_mesh_for_writing(m, path.string());
    atomic_write(path, format_obj(m));
}

}  // namespace fabsynth::io
